"""The report's generalization section: navigators tested in worlds other than their training's.

Made from the run table's rows with a ``tested_on`` (tests with other task options, see
agents/training/test_phase.py):

* procedural navigators (task ``DynNav-Procedural-v1``), one row per training experiment and
  test (``difficulty=..,split=..``): success, collision and timeout rates and SPL, as means over
  seeds (success with the seeds' standard deviation), beside the full-state planner's ceiling and
  the go-to-target floor of the same difficulty and split (``procedural_ceilings.json``, written
  by ``dynnav_tasks.baselines.state_planner`` and ``go_to_target`` with ``--out``);
* a figure of test success against the number of moving obstacles and the arena's longer side,
  per training experiment, over the test episodes of every seed (the episode table's
  ``moving_obstacles`` and ``arena_side``), in bins with at least MIN_EPISODES episodes, one line
  for the train and test worlds and one (dashed) for the ood worlds;
* the one navigator for every difficulty and its ablation, in tables of their own
  (``agents/study/generalist.py``);
* transfer tests of the fixed worlds' navigators (e.g. 5.3 with ``obstacle_count=4,
  obstacle_speed_scale=1.5``, or with noise): the same seeds' success in their own test and in the
  other one, beside the planner's ceiling in the task with its default options and with the
  test's (``ceilings.json``, entries ``"<task>"`` and ``"<task> [<options>]"``; "-" if not measured).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from agents.files import save_figure
from agents.study.generalist import ABLATION, ablation_table, generalist_table, is_shown_here
from dynnav_tasks.task_options import parse_task_options

PROCEDURAL_TASK = "DynNav-Procedural-v1"
OBSTACLE_BINS = (0, 1, 4, 7, 10, 13, 16, 21, 26, 31)
"""moving-obstacle count bins [a, b) of the figure"""
ARENA_BINS = (6.0, 8.0, 10.0, 12.0, 14.0, 17.0, 20.01)
"""arena longer-side bins [a, b) of the figure (m)"""
MIN_EPISODES = 20
"""test episodes a bin needs to be drawn"""
SPLIT_ORDER = {"train": 0, "test": 1, "ood": 2}
DIFFICULTY_ORDER = {"easy": 0, "medium": 1, "hard": 2}


def _mean(rows: list[dict], key: str) -> float | None:
    values = [r[key] for r in rows if r[key] is not None]
    return float(np.mean(values)) if values else None


def _pct(x: float | None) -> str:
    return "-" if x is None else f"{x:.0%}"


def _grouped(rows: list[dict]) -> dict[tuple[str, str], list[dict]]:
    out: dict[tuple[str, str], list[dict]] = {}
    for r in sorted(rows, key=lambda r: (r["experiment"], r["tested_on"], r["seed"])):
        out.setdefault((r["experiment"], r["tested_on"]), []).append(r)
    return out


def _test_order(key: tuple[str, str]):
    """Easy before medium before hard (by the tested difficulty), then train, test, ood."""
    options = parse_task_options(key[1])
    difficulty = str(options.get("difficulty", ""))
    return (DIFFICULTY_ORDER.get(difficulty, 9), difficulty, key[0], SPLIT_ORDER.get(str(options.get("split")), 9),
            key[1])


def procedural_table(rows: list[dict], cells: dict[str, dict]) -> list[str]:
    """Markdown rows: per procedural experiment and test, the rates beside the planner and floor."""
    groups = _grouped([r for r in rows if r["task"] == PROCEDURAL_TASK and r["tested_on"]
                       and not is_shown_here(r["experiment"])])
    if not groups:
        return []
    lines = ["| trained | tested on | seeds | success (sd) | collision | timeout | SPL | planner ceiling (SPL) | "
             "go to target |", "|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(groups, key=_test_order):
        runs = groups[key]
        options = parse_task_options(key[1])
        cell = f"{options.get('difficulty')}/{options.get('split')}"
        rates = np.array([r["success_rate"] for r in runs])
        sd = f" ({rates.std(ddof=1):.0%})" if len(runs) > 1 else ""
        planner, floor = cells.get(f"state_planner/{cell}"), cells.get(f"go_to_target/{cell}")
        ceiling = f"{planner['success']:.0%} ({planner['spl']:.2f})" if planner else "not measured"
        lines.append(f"| `{key[0]}` | {cell} | {len(runs)} | {rates.mean():.0%}{sd} | {_pct(_mean(runs, 'collision_rate'))} "
                     f"| {_pct(_mean(runs, 'timeout_rate'))} | {_mean(runs, 'spl') or 0:.2f} | {ceiling} | "
                     f"{_pct(floor['success']) if floor else 'not measured'} |")
    return lines


def transfer_table(rows: list[dict], ceilings: dict[str, float]) -> list[str]:
    """Markdown rows: per fixed-world experiment tested with other options, its seeds' success at
    home and there, each beside the planner's."""
    groups = _grouped([r for r in rows if r["task"] != PROCEDURAL_TASK and r["tested_on"]])
    if not groups:
        return []
    home = {(r["experiment"], r["config_hash"], r["seed"]): r for r in rows if not r["tested_on"]}
    lines = ["| experiment | tested on | seeds | success in its own test | success tested on | collision | timeout | "
             "planner: task's defaults | planner: tested on |", "|---|---|---|---|---|---|---|---|---|"]
    for (experiment, on), runs in sorted(groups.items()):
        task = runs[0]["task"]
        own = [home[k] for k in ((experiment, r["config_hash"], r["seed"]) for r in runs) if k in home]
        at_home, there = ceilings.get(task), ceilings.get(f"{task} [{on}]")
        lines.append(f"| `{experiment}` | `{on}` | {len(runs)} | {_pct(_mean(own, 'success_rate'))} | "
                     f"{_pct(_mean(runs, 'success_rate'))} | {_pct(_mean(runs, 'collision_rate'))} | "
                     f"{_pct(_mean(runs, 'timeout_rate'))} | {_pct(at_home)} | {_pct(there)} |")
    return lines


def _binned(episodes: list[dict], key: str, bins) -> tuple[list[float], list[float], list[int]]:
    x, y, n = [], [], []
    values = np.array([e[key] for e in episodes], dtype=float)
    success = np.array([e["outcome"] == "success" for e in episodes], dtype=float)
    for lo, hi in zip(bins[:-1], bins[1:]):
        inside = (values >= lo) & (values < hi)
        if inside.sum() >= MIN_EPISODES:
            x.append(float(values[inside].mean()))
            y.append(float(success[inside].mean()))
            n.append(int(inside.sum()))
    return x, y, n


def _difficulty_rank(episodes: list[dict]) -> int:
    """Where an experiment's tests stand in easy, medium, hard (its easiest tested difficulty)."""
    return min(DIFFICULTY_ORDER.get(str(parse_task_options(e["tested_on"]).get("difficulty")), 9) for e in episodes)


def _split(row: dict) -> str:
    return str(parse_task_options(row["tested_on"]).get("split", ""))


def draw_generalization(episodes: list[dict], path: Path, experiments: set[str]) -> bool:
    """The figure of success against obstacle count and arena side over the test episodes of
    ``experiments`` (the procedural ones); False (nothing written) if none records its world."""
    by_experiment: dict[str, list[dict]] = {}
    for e in episodes:
        if (e["experiment"] in experiments and e["tested_on"] and e["moving_obstacles"] is not None
                and e["arena_side"] is not None):
            by_experiment.setdefault(e["experiment"], []).append(e)
    if not by_experiment:
        return False
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 4), dpi=100, sharey=True)
    panels = (("moving_obstacles", OBSTACLE_BINS, "moving obstacles in the world"),
              ("arena_side", ARENA_BINS, "arena's longer side (m)"))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for (key, bins, label), ax in zip(panels, axes):
        for i, experiment in enumerate(sorted(by_experiment, key=lambda e: (_difficulty_rank(by_experiment[e]), e))):
            episodes_of = by_experiment[experiment]
            ood = [_split(e) == "ood" for e in episodes_of]
            for out, style, where in ((False, "-", "train and test worlds"), (True, "--", "ood worlds")):
                part = [e for e, o in zip(episodes_of, ood) if o == out]
                x, y, _ = _binned(part, key, bins)
                if x:
                    ax.plot(x, y, style, marker="o", markerfacecolor="white" if out else None, linewidth=1.5,
                            color=colours[i % len(colours)], label=f"{experiment}: {where} ({len(part)} episodes)")
        ax.set_xlabel(label)
        ax.set_ylim(0, 1.02)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("test success")
    axes[1].legend(loc="upper right", fontsize=7)
    fig.suptitle("Test success in procedural worlds, every seed (solid: train and test worlds; dashed: ood "
                 f"worlds; bins of {MIN_EPISODES}+ episodes)", fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        save_figure(fig, path, metadata={"Software": None})
    finally:
        plt.close(fig)
    return True


def generalization_section(rows: list[dict], episodes: list[dict], cells: dict[str, dict],
                           ceilings: dict[str, float], figure: Path | None, figure_link: str,
                           baselines: dict[str, dict] | None = None) -> list[str]:
    """The section's Markdown lines ([] if the table holds no test with other options); draws the
    figure into ``figure`` (None: no figure); ``baselines``: DWA's results in the study worlds."""
    procedural, transfer = procedural_table(rows, cells), transfer_table(rows, ceilings)
    generalist, ablation = generalist_table(rows, cells, ceilings, baselines), ablation_table(rows)
    if not procedural and not transfer and not generalist:
        return []
    lines = ["", "## Generalization", ""]
    if procedural:
        lines += ["Trained on a difficulty's train worlds of `DynNav-Procedural-v1` (`configs/procedural/`), tested "
                  "on 100 episodes of its held-out test, train and ood worlds (`docs/procedural.md`); means over "
                  "seeds, beside the full-state planner and the go-to-target floor (200 episodes each).",
                  "", *procedural]
        procedural_experiments = {r["experiment"] for r in rows if r["task"] == PROCEDURAL_TASK
                                  and not r["experiment"].startswith(ABLATION)}
        if figure is not None and draw_generalization(episodes, figure, procedural_experiments):
            lines += ["", f"![Test success against obstacle count and arena size]({figure_link})"]
    if generalist:
        lines += ["", "One navigator for every difficulty (`docs/generalist.md`): taught by the full-state planner "
                  "(behaviour cloning, then DAgger: `generalist-dagger`), then Double DQN with the teacher's "
                  "demonstrations kept (`generalist-finetune`); greedy test success on 100 episodes of each cell, "
                  "means over seeds, beside the planners (200 episodes each) and the per-difficulty navigators.",
                  "", *generalist]
    if ablation:
        lines += ["", "The generalist's student, its observation and encoders (`agents.imitation.ablation`, "
                  "`docs/generalist.md`): each row fitted from scratch on the labelled episodes of one imitation run, "
                  "seen through its own sensors; 100 held-out test episodes per difficulty and seed.", "", *ablation]
    if transfer:
        lines += ["", "Fixed-world navigators tested with other task options, the same seeds in their own test and "
                  "there (5.3 with more boxes: its state keeps two obstacle places, the two nearest; noise: "
                  "`dynnav_tasks/noise.py`).", "", *transfer]
    return lines
