"""An imitation student as a row of the run table: the files ``agents.study.table add`` reads.

A student is a DQN checkpoint with the config that built it, and its tests are the DQN test
phase's (``eval.json``, ``tests/<options>/eval.json``). Its training curve is the episodes it
learned from: an imitation run's ``metrics.csv`` has a row per labelled episode (``write_metrics``:
its return, length and outcome, whoever drove it, the round's fit loss as its loss, the rounds'
wall-clock so far as its time; no epsilon or learning rate), so the run table's curves show how
the gathered episodes' success moved as the student took over. A student fitted on another
run's episodes (``ablation.py``) gathered none: its ``metrics.csv`` has the header alone, and its
training time goes into ``sweep_run.json`` (``train_s``), with its experiment's name, as a sweep
writes it.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from agents.files import atomic_write_bytes
from agents.training.run_dir import METRICS

RUN_INFO = "sweep_run.json"


def write_record(run_dir: str | Path, experiment: str, train_s: float, eval_s: float = 0.0, **extra) -> None:
    """Write ``run_dir``'s empty metrics.csv (if it has none) and its sweep_run.json."""
    run_dir = Path(run_dir)
    if not (run_dir / "metrics.csv").is_file():
        atomic_write_bytes(run_dir / "metrics.csv", (",".join(METRICS) + "\n").encode())
    info = dict(experiment=experiment, train_s=round(float(train_s), 2), eval_s=round(float(eval_s), 2), **extra)
    atomic_write_bytes(run_dir / RUN_INFO, json.dumps(info, indent=1).encode())


def write_metrics(run_dir: str | Path, rollouts: list, rounds: list[int], round_rows: list[dict]) -> None:
    """``run_dir``'s metrics.csv: a row per labelled episode (``rollouts``, gathered in ``rounds``),
    with the fit loss and the cumulated seconds of its round (``round_rows``: rounds.csv's rows)."""
    by_round = {int(r["round"]): r for r in round_rows}
    elapsed, done = {}, 0.0
    for k in sorted(by_round):
        done += float(by_round[k]["seconds"])
        elapsed[k] = done
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=METRICS, lineterminator="\n")
    writer.writeheader()
    step = 0
    for i, (r, k) in enumerate(zip(rollouts, rounds)):
        step += r.steps
        row = by_round[k]
        writer.writerow(dict(episode=i, global_step=step, **{"return": round(float(r.rewards.sum()), 4)},
                             length=r.steps, success=int(r.outcome == "success"), collision=int(r.outcome == "collision"),
                             timeout=int(r.outcome == "timeout"), loss=f"{float(row['fit_loss']):.6g}", epsilon="",
                             learning_rate="", steps_per_s=round(r.steps / max(r.label_seconds, 1e-9), 1),
                             wall_time_s=round(elapsed[k], 2)))
    atomic_write_bytes(Path(run_dir) / "metrics.csv", buffer.getvalue().encode())
