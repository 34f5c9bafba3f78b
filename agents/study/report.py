"""RESULTS.md and its figures from the run table: test results per experiment beside the study's.

    python -m agents.study.report [--table results] [--out RESULTS.md]

Reads only the run table (agents/study/table.py; ``results/runs.csv.gz`` in this repository), so
the same table gives the same RESULTS.md byte for byte wherever it is run. Per experiment, over
its runs (one per seed):

* success: mean of the seeds' test success rates (100 episodes each in the study, epsilon 0).
  95% interval: a t-interval over the seeds' rates (mean +- t(0.975, k-1) * sd / sqrt(k)) with
  two or more seeds, which counts seed-to-seed variation; the Wilson interval of the single
  seed's episodes with one seed.
* steps: mean over seeds of the average steps of successful test episodes.
* converge: mean over seeds of the run's convergence episode (the table's ``converge_episode``:
  the first training episode at which the 100-episode success rate reaches 90% of its final
  value); "never" if a seed never got there.
* wall-clock: mean per run of training time (summed over restarts) plus the test phase.
* per seed: each seed's success rate; with more than MAX_LISTED_SEEDS seeds, their range and median.
* ceiling: the success rate of ``dynnav_tasks.baselines.state_planner`` (a planner that sees the
  full state) on the experiment's task, from ``--ceilings`` (default docs/results/ceilings.json
  next to the report, written by ``python -m dynnav_tasks.baselines.state_planner --out ...``).

The study's numbered cells get a table of their own (agents/study/cells.py), and the tests in
other worlds (rows with a ``tested_on``: procedural navigators on their test and ood worlds, 5.3's
navigator with more and faster boxes) a section of their own (agents/study/generalization.py,
with the procedural planner and floor from ``--procedural-ceilings``, default
docs/results/procedural_ceilings.json next to the report). The discussion of
why the numbers differ from the study's is a page of its own (``--discussion``, default
docs/results/discussion.md next to the report), linked, not pasted. Figures (``--figures``,
default docs/results next to the report): agents/study/figures.py. Navigators among pedestrians
get the crowd section and DWA in the study's worlds a table (agents/study/baselines.py), from
``--baselines`` (default docs/results/baselines.json next to the report).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

import numpy as np

from agents.files import atomic_write_bytes
from agents.study.cells import (cells_table, find_configs, format_ceiling, load_ceilings, load_cells, memory_section,
                                short_of_seeds, study_rate, t975, wide_intervals)
from agents.study.figures import SUCCESS_PANELS, block_size, caption, write_figures
from agents.study.baselines import crowd_section, dwa_section, load_baselines
from agents.study.generalist import figures_of as generalist_figures
from agents.study.generalist import runs_once
from agents.study.generalization import generalization_section
from agents.study.numbers import FIGURES, THESIS
from agents.study.table import DEFAULT_TABLE, RUNS, read_table
from agents.training.stats import wilson_interval

DISCUSSION = "docs/results/discussion.md"
"""the discussion page, relative to the report's folder"""


def group_runs(rows: list[dict]) -> dict[str, list[dict]]:
    """experiment -> its runs in seed order (their tests in their own task; the tests with other
    task options are the generalization section's)."""
    groups: dict[str, list[dict]] = {}
    for r in sorted(rows, key=lambda r: (r["experiment"], r["seed"], r["config_hash"])):
        if r.get("tested_on"):
            continue
        groups.setdefault(r["experiment"], []).append(r)
    return groups


def summarize(runs: list[dict]) -> dict:
    """The row of one experiment: mean success with its interval, steps, convergence, wall-clock."""
    runs = sorted(runs, key=lambda r: r["seed"])
    out = dict(seeds=len(runs))
    if not runs:
        return out
    rates = np.array([r["success_rate"] for r in runs])
    mean = float(rates.mean())
    if len(runs) >= 2:
        half = t975(len(runs) - 1) * rates.std(ddof=1) / math.sqrt(len(runs))
        lo, hi, how = max(0.0, mean - half), min(1.0, mean + half), "t"
    else:
        lo, hi = wilson_interval(round(runs[0]["success_rate"] * runs[0]["test_episodes"]), runs[0]["test_episodes"])
        how = "Wilson"
    steps = [r["avg_steps_success"] for r in runs if r["avg_steps_success"] is not None]
    conv = [r["converge_episode"] for r in runs]
    out.update(success=mean, ci=(lo, hi), ci_kind=how, per_seed=rates.tolist(),
               sd=float(rates.std(ddof=1)) if len(runs) >= 2 else None,
               steps=float(np.mean(steps)) if steps else None,
               converge=float(np.mean(conv)) if all(c is not None for c in conv) else None,
               never=sum(c is None for c in conv), wall=float(np.mean([r["wall_clock_s"] for r in runs])),
               episodes=int(np.mean([r["episodes_done"] for r in runs])))
    return out


MAX_LISTED_SEEDS = 10
"""rows with more seeds than this show their seeds' range and median, not every rate"""


def _pct(x) -> str:
    return "-" if x is None else f"{x:.0%}"


def _per_seed(rates: list[float]) -> str:
    """Every seed's rate, or with more than MAX_LISTED_SEEDS seeds their range and median."""
    if len(rates) <= MAX_LISTED_SEEDS:
        return " ".join(_pct(x) for x in rates)
    return f"{_pct(min(rates))}-{_pct(max(rates))}, median {_pct(float(np.median(rates)))}"


def short_task(task: str) -> str:
    """A task id without the suite's ``DynNav-`` and its version ``-v1`` (the table's header says so)."""
    return task.removeprefix("DynNav-").removesuffix("-v1")


def _experiment_row(name: str, task: str, s: dict, ceiling: str) -> str:
    t = THESIS.get(name, dict(success="-", converge="-"))
    lo, hi = s["ci"]
    conv = "never" if s["converge"] is None else f"{s['converge']:.0f}"
    if s["converge"] is None and s["never"] < s["seeds"]:
        conv = f"never in {s['never']} of {s['seeds']}"
    steps = "-" if s["steps"] is None else format(s["steps"], ".1f")
    return (f"| `{name}` | {short_task(task)} | {s['seeds']} | {s['success']:.0%} ({lo:.0%}-{hi:.0%}, {s['ci_kind']}) | "
            f"{t.get('success', '-')} | {ceiling} | {steps} | {conv} (of {s['episodes']}) | {t.get('converge', '-')} | "
            f"{s['wall']:.0f} s | {_per_seed(s['per_seed'])} |")


def render(groups: dict[str, list[dict]], figures: list[tuple[str, str]] = (), table: str = "results/runs.csv.gz",
           discussion: str | None = None, ceilings: dict[str, float] | None = None,
           configs: dict[str, str] | None = None, figure_caption: str = "", generalization: list[str] = ()) -> str:
    """The report's Markdown: ``groups`` experiment -> run rows; ``figures`` (relative path, title);
    ``table`` and ``discussion`` as the report names them (paths relative to it); ``generalization``:
    that section's lines."""
    ceilings = ceilings or {}
    order = [e for e in THESIS if e in groups] + sorted(e for e in groups if e not in THESIS)
    summaries = {e: summarize(groups[e]) for e in order}
    tasks = {e: groups[e][0]["task"] for e in order}
    lines = ["# Results", "",
             f"Test success per experiment (100 test episodes per run in the study's configs, epsilon 0), beside "
             f"the study's number. Made from the run table `{table}` by `python -m agents.study.report`; the method "
             "is in `agents/study/report.py`: success is the mean over seeds with a 95% t-interval over the seeds' "
             "rates (Wilson interval of the episodes with one seed); steps are those of successful test episodes; "
             "*converge* is the first training episode at which the 100-episode success rate reaches 90% of its "
             "final value; wall-clock is training plus test per run on one core; *ceiling* is the success rate of "
             "a planner that sees the full state (`dynnav_tasks.baselines.state_planner`) in the same world. "
             "Experiments are the config files of `configs/study/`; a name that extends a study's experiment "
             "(`5.3-g0.1` extends `5.3`) is a variant of it."]
    if discussion:
        lines += ["", f"Why our numbers differ from the study's, cell by cell: [the discussion]({discussion})."]
    lines.append("")
    if any(study_rate(e) is not None for e in THESIS):
        lines += cells_table(summaries, tasks, ceilings) + ["", "## Every experiment", ""]
    lines += ["| experiment | task (DynNav-...-v1) | seeds | success (95% CI) | study | ceiling | steps | converge (episodes) | study | "
              "wall-clock | per seed |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    lines += [_experiment_row(e, tasks[e], summaries[e], format_ceiling(ceilings.get(tasks[e]))) for e in order]
    if any(e in THESIS for e in order):
        lines += ["", "Where the study's numbers come from (`agents/study/numbers.py`): "
                  + "; ".join(f"`{e}` {THESIS[e]['source']}" for e in order if e in THESIS) + "."]
    missing = [e for e in THESIS if e not in groups]
    if missing:
        lines += ["", "Experiments of the study without a run in the table yet: "
                  + ", ".join(f"`{e}`" for e in missing) + "."]
    mixed = [e for e in order if len({r["config_hash"] for r in groups[e]}) > 1]
    if mixed:
        lines += ["", "Experiments whose runs were made with more than one config (the config was edited "
                  "between them; their rows mix both): " + ", ".join(
                      f"`{e}` ({', '.join(sorted({r['config_hash'] for r in groups[e]}))})" for e in mixed) + "."]
    lines += memory_section(summaries, tasks, ceilings)
    lines += wide_intervals(summaries)
    lines += short_of_seeds(summaries, configs or {})
    lines += list(generalization)
    if figures:
        lines += ["", "## Learning curves", ""]
        if figure_caption:
            lines += [f"Each curve: the {figure_caption}.", ""]
        for rel, title in figures:
            lines += [f"![{title}]({rel})", ""]
    return "\n".join(lines).rstrip("\n") + "\n"


def _relative(path: Path, start: Path) -> str:
    return Path(os.path.relpath(path.resolve(), start.resolve())).as_posix()


def write_report(table: str | Path = DEFAULT_TABLE, out: str | Path = "RESULTS.md", figures_dir: str | Path | None = None,
                 discussion: str | None = None, ceilings: str | Path | None = None,
                 configs: list[str | Path] | None = None, procedural_ceilings: str | Path | None = None,
                 baselines: str | Path | None = None) -> Path:
    """Write the report and its figures from a table folder. ``discussion``: the discussion page's
    path relative to the report (default DISCUSSION, linked if the file is there); ``ceilings``: the
    planner's JSON (default docs/results/ceilings.json next to ``out``, if there); ``configs``:
    config files or folders of them, each listed if it has fewer than MIN_SEEDS runs;
    ``procedural_ceilings``: the procedural planner and floor (default
    docs/results/procedural_ceilings.json next to ``out``, if there); ``baselines``: DWA in the
    study's worlds and the scripted robots among pedestrians (default docs/results/baselines.json
    next to ``out``, if there).
    Everything is read and checked before anything is written."""
    out = Path(out)
    rows = read_table(table)
    if not rows:
        raise ValueError(f"no runs in {Path(table) / RUNS}; add some with `python -m agents.study.table add RUN_DIR`")
    config_paths = find_configs(configs) if configs is not None else {}
    if ceilings is not None and not Path(ceilings).is_file():
        raise ValueError(f"ceilings file {str(ceilings)!r} does not exist")
    ceiling_rates = load_ceilings(ceilings if ceilings is not None else out.parent / "docs" / "results" / "ceilings.json")
    if procedural_ceilings is not None and not Path(procedural_ceilings).is_file():
        raise ValueError(f"procedural ceilings file {str(procedural_ceilings)!r} does not exist")
    cells = load_cells(procedural_ceilings if procedural_ceilings is not None
                       else out.parent / "docs" / "results" / "procedural_ceilings.json")
    episodes = read_table(table, episodes=True) if any(r["tested_on"] for r in rows) else []
    if baselines is not None and not Path(baselines).is_file():
        raise ValueError(f"baselines file {str(baselines)!r} does not exist")
    robots = load_baselines(baselines if baselines is not None
                            else out.parent / "docs" / "results" / "baselines.json")
    if discussion is not None and not (out.parent / discussion).is_file():
        raise ValueError(f"discussion page {str(out.parent / discussion)!r} does not exist (the path is "
                         "relative to the report's folder)")
    link = discussion if discussion is not None else DISCUSSION if (out.parent / DISCUSSION).is_file() else None
    groups = group_runs(rows)
    block = block_size(rows)  # one curve block for every figure, checked before anything is written
    curves = runs_once(rows)  # every run once, for the figures of runs tested with options only
    figures_dir = Path(figures_dir) if figures_dir else out.parent / "docs" / "results"
    out.parent.mkdir(parents=True, exist_ok=True)
    written = [(_relative(p, out.parent), title) for p, title in write_figures(groups, FIGURES, figures_dir)
               + write_figures(curves, generalist_figures(curves), figures_dir, SUCCESS_PANELS)]
    table_path = Path(table) / RUNS
    inside = table_path.resolve().is_relative_to(out.parent.resolve())
    table_name = _relative(table_path, out.parent) if inside else table_path.as_posix()
    figure = figures_dir / "generalization.png"
    extra = generalization_section(rows, episodes, cells, ceiling_rates, figure, _relative(figure, out.parent), robots)
    extra += dwa_section(robots, ceiling_rates) + crowd_section(rows, robots)
    text = render(groups, written, table_name, link, ceiling_rates, config_paths,
                  caption(block) if written else "", extra)
    atomic_write_bytes(out, text.encode())
    return out


def main(argv: list[str] | None = None) -> None:
    """The command line: ``python -m agents.study.report [--table results] [--out RESULTS.md]``."""
    parser = argparse.ArgumentParser(prog="python -m agents.study.report", description=__doc__.split("\n\n")[0])
    parser.add_argument("--table", default=DEFAULT_TABLE,
                        help=f"run table folder (agents.study.table; default {DEFAULT_TABLE})")
    parser.add_argument("--out", default="RESULTS.md", help="report file (default RESULTS.md)")
    parser.add_argument("--figures", default=None, help="folder for the PNGs (default docs/results next to --out)")
    parser.add_argument("--discussion", default=None,
                        help=f"the discussion page to link, relative to --out's folder (default {DISCUSSION} if there)")
    parser.add_argument("--ceilings", default=None,
                        help="the planner's success rates per task (python -m dynnav_tasks.baselines.state_planner "
                             "--out FILE); default docs/results/ceilings.json next to --out, if it exists")
    parser.add_argument("--procedural-ceilings", default=None,
                        help="the procedural planner's and floor's rates per difficulty and split (their --out); "
                             "default docs/results/procedural_ceilings.json next to --out, if it exists")
    parser.add_argument("--baselines", default=None,
                        help="DWA's and the crowd robots' results (dynnav_tasks.baselines.dwa and crowd_robot --out); default "
                             "docs/results/baselines.json next to --out, if it exists")
    parser.add_argument("--configs", nargs="+", default=None, metavar="CONFIG",
                        help="config files or folders of them (searched recursively): list the configs with fewer "
                             "than 5 runs in the table")
    args = parser.parse_args(argv)
    try:
        out = write_report(args.table, args.out, args.figures, args.discussion, args.ceilings, args.configs,
                           args.procedural_ceilings, args.baselines)
    except (ValueError, OSError) as err:
        raise SystemExit(f"error: {err}")
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1:])
