"""The report's tables of the one navigator for every difficulty and of its ablation.

* ``generalist_table``: one row per ``generalist*`` experiment (``configs/procedural/generalist*.yaml``
  and the imitation runs, ``generalist-dagger``), one column per held-out cell: every
  difficulty's test and ood worlds and world 5.3 with its transfer version (``study_world``),
  the mean success over seeds. Beside them: the full-state planner (the ceiling), the planner that
  sees what the egocentric state tells (``state_planner_tracked4``, when measured), the
  per-difficulty Double DQN (``procedural-<difficulty>``, in its own difficulty's cells) and the
  issue's goal (90% of the planner's success in the test worlds, 75% in the ood worlds).
* ``ablation_table``: one row per ``ablation-*`` experiment (``agents.imitation.ablation``): the
  mean test success per difficulty over seeds and the training time (re-observing and fitting).

Experiments are told apart by name: the generalist's start with ``generalist``, the ablation's
with ``ablation-``; ``generalization.procedural_table`` leaves both to these tables.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from dynnav_tasks.task_options import parse_task_options

GENERALIST = "generalist"
ABLATION = "ablation-"
DIFFICULTIES = ("easy", "medium", "hard")
CELLS = [f"difficulty={d},split=test" for d in DIFFICULTIES] + [f"difficulty={d},split=ood" for d in DIFFICULTIES]
STUDY = {"study_world=5.3": "DynNav-MovingObstacles-v1",
         "study_world=5.3-transfer": "DynNav-MovingObstacles-v1 [obstacle_count=4,obstacle_speed_scale=1.5]"}
"""the study-world tests and their planner ceiling's entry in ceilings.json"""
GOAL = {"test": 0.90, "ood": 0.75}
"""the goal: this share of the full-state planner's success"""
FIGURES = [("generalist", "One navigator for every difficulty, and one per difficulty", [
    ("generalist-dagger", "generalist: the episodes DAgger labelled (planner, then student)"),
    ("generalist-finetune", "generalist: Double DQN from the student"),
    ("procedural-easy", "per-difficulty DQN: easy"), ("procedural-medium", "per-difficulty DQN: medium"),
    ("procedural-hard", "per-difficulty DQN: hard")])]
"""the learning-curve figure of the generalist (``figures.SUCCESS_PANELS``: success and return per episode)"""


def figures_of(groups: dict[str, list[dict]]) -> list:
    """``FIGURES`` once the table has a generalist run (the per-difficulty curves alone are no comparison of it)."""
    return FIGURES if any(e.startswith(GENERALIST) for e in groups) else []


def runs_once(rows: list[dict]) -> dict[str, list[dict]]:
    """experiment -> one row per run, in seed order, whatever the run was tested on: a run's
    learning curves are in each of its rows (the procedural runs have no row of their own task
    as it is, every test of theirs names its options)."""
    groups: dict[str, list[dict]] = {}
    seen = set()
    for r in sorted(rows, key=lambda r: (r["experiment"], r["seed"], r["config_hash"], r["tested_on"])):
        key = (r["experiment"], r["config_hash"], r["seed"])
        if key not in seen:
            seen.add(key)
            groups.setdefault(r["experiment"], []).append(r)
    return groups


def is_shown_here(experiment: str) -> bool:
    """Whether an experiment's rows belong to these tables (not the per-difficulty table)."""
    return experiment.startswith(GENERALIST) or experiment.startswith(ABLATION)


def _mean_success(rows: list[dict], experiment: str, on: str) -> tuple[float | None, int]:
    rates = [r["success_rate"] for r in rows if r["experiment"] == experiment and r["tested_on"] == on]
    return (float(np.mean(rates)), len(rates)) if rates else (None, 0)


def _pct(x: float | None) -> str:
    return "-" if x is None else f"{x:.0%}"


def _cell(on: str) -> tuple[str, str]:
    options = parse_task_options(on)
    return str(options["difficulty"]), str(options["split"])


def generalist_table(rows: list[dict], cells: dict[str, dict], ceilings: dict[str, float],
                     baselines: dict[str, dict] | None = None) -> list[str]:
    """Markdown lines of the generalist table ([] without a generalist row); ``baselines``: the
    scripted controllers' results beyond the planner (``agents.study.baselines``), for DWA's row."""
    experiments = sorted({r["experiment"] for r in rows if r["experiment"].startswith(GENERALIST) and r["tested_on"]})
    if not experiments:
        return []
    columns = CELLS + list(STUDY)
    heads = [f"{d} {s}" for d, s in map(_cell, CELLS)] + ["5.3", "5.3 transfer"]
    lines = ["| navigator | seeds | " + " | ".join(heads) + " |", "|---|---|" + "---|" * len(columns)]

    def planner(controller: str) -> list[str]:
        values = [cells.get(f"{controller}/{d}/{s}", {}).get("success") for d, s in map(_cell, CELLS)]
        if controller == "state_planner":
            study = [ceilings.get(STUDY[on]) for on in STUDY]
        else:
            study = [(baselines or {}).get(f"{controller}/{STUDY[on]}", {}).get("success") for on in STUDY]
        return [_pct(v) for v in values + study]

    lines.append("| full-state planner (the ceiling) | - | " + " | ".join(planner("state_planner")) + " |")
    if any(k.startswith("state_planner_tracked4/") for k in cells):
        lines.append("| planner seeing the 4 nearest boxes at constant velocity | - | "
                     + " | ".join(planner("state_planner_tracked4")) + " |")
    if any(k.startswith("dwa/") for k in cells):
        lines.append("| DWA on the laser scan (continuous drive) | - | " + " | ".join(planner("dwa")) + " |")
    per_difficulty, seeds = [], set()
    for on in columns:
        if on in STUDY:
            per_difficulty.append("-")
            continue
        value, n = _mean_success(rows, f"procedural-{_cell(on)[0]}", on)
        per_difficulty.append(_pct(value))
        seeds.add(n)
    lines.append(f"| per-difficulty Double DQN (`procedural-<difficulty>`) | {max(seeds)} | "
                 + " | ".join(per_difficulty) + " |")
    for experiment in experiments:
        values = [_mean_success(rows, experiment, on) for on in columns]
        n = max(k for _, k in values)
        lines.append(f"| `{experiment}` | {n} | " + " | ".join(_pct(v) for v, _ in values) + " |")
    goal = [cells.get(f"state_planner/{d}/{s}", {}).get("success") for d, s in map(_cell, CELLS)]
    lines.append("| goal: 90% (test) / 75% (ood) of the planner | - | "
                 + " | ".join(f"≥ {v * GOAL[s]:.0%}" if v is not None else "-"
                              for v, (_, s) in zip(goal, map(_cell, CELLS))) + " | - | - |")
    return lines


def ablation_table(rows: list[dict]) -> list[str]:
    """Markdown lines of the ablation table ([] without an ablation row)."""
    experiments = sorted({r["experiment"] for r in rows if r["experiment"].startswith(ABLATION)})
    if not experiments:
        return []
    tests = [f"difficulty={d},split=test" for d in DIFFICULTIES]
    lines = ["| row | seeds | easy test | medium test | hard test | mean | training (s, each seed) |",
             "|---|---|---|---|---|---|---|"]
    for experiment in experiments:
        values = [_mean_success(rows, experiment, on) for on in tests]
        own = [r for r in rows if r["experiment"] == experiment and r["tested_on"] == tests[1]]
        mean = np.mean([v for v, _ in values if v is not None]) if any(v is not None for v, _ in values) else None
        cost = np.mean([r["train_s"] for r in own]) if own else None
        lines.append(f"| `{experiment[len(ABLATION):]}` | {max(k for _, k in values)} | "
                     + " | ".join(_pct(v) for v, _ in values) + f" | {_pct(mean)} | "
                     + ("-" if cost is None else f"{cost:.0f}") + " |")
    return lines


def docs_tables(table: str | Path, ceilings: str | Path, procedural_ceilings: str | Path,
                baselines: str | Path | None = None) -> str:
    """The block docs/generalist.md shows between ``<!-- tables -->`` and ``<!-- end tables -->``:
    the generalist table and the ablation table of the run table in ``table`` (what RESULTS.md shows)."""
    from agents.study.baselines import load_baselines
    from agents.study.cells import load_ceilings, load_cells
    from agents.study.table import read_table

    rows = read_table(table)
    generalist = generalist_table(rows, load_cells(procedural_ceilings), load_ceilings(ceilings),
                                  load_baselines(baselines))
    ablation = ablation_table(rows)
    parts = []
    if generalist:
        parts.append("\n".join(["The generalist on every held-out cell (greedy test success, 100 episodes per cell "
                                "and seed, means over seeds):", "", *generalist]))
    if ablation:
        parts.append("\n".join(["The ablation (students fitted on one imitation run's labelled episodes, 100 held-out "
                                "test episodes per difficulty and seed):", "", *ablation]))
    return "\n\n".join(parts)


def main(argv: list[str] | None = None) -> None:
    """``python -m agents.study.generalist``: print the tables docs/generalist.md shows."""
    import argparse

    root = Path(__file__).resolve().parents[2]
    parser = argparse.ArgumentParser(prog="python -m agents.study.generalist", description=main.__doc__)
    parser.add_argument("--table", default=str(root / "results"), help="run table folder (default results/)")
    args = parser.parse_args(argv)
    print(docs_tables(args.table, root / "docs" / "results" / "ceilings.json",
                      root / "docs" / "results" / "procedural_ceilings.json", root / "docs" / "results" / "baselines.json"))


if __name__ == "__main__":
    main()
