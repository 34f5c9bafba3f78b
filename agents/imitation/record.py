"""An imitation student as a row of the run table: the files ``agents.study.table add`` reads.

A student is a DQN checkpoint with the config that built it, and its tests are the DQN test
phase's (``eval.json``, ``tests/<options>/eval.json``). What it lacks is a training curve: it
played no episode of its own, so its ``metrics.csv`` has the header alone, and its training time
(the teacher's labels and the fits, in seconds of wall-clock) goes into ``sweep_run.json`` with
its experiment's name, as a sweep writes it.
"""

from __future__ import annotations

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
