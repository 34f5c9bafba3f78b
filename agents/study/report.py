"""RESULTS.md from sweeps or single runs: test results per experiment beside the study's.

    python -m agents.study.report sweeps/laser [more sweep or run folders] --out RESULTS.md \
        [--discussion docs/results/discussion.md]

Runs are grouped by experiment (the sweep's experiment name, else the run's ``name``). Per
experiment, over the seeds whose test phase has run:

* success: mean of the seeds' test success rates (100 episodes each, epsilon 0). 95% interval:
  a t-interval over the seeds' rates (mean +- t(0.975, k-1) * sd / sqrt(k)) with two or more
  seeds, which counts seed-to-seed variation; the Wilson interval of the single seed's episodes
  with one seed.
* steps: mean over seeds of the average steps of successful test episodes.
* converge: the first training episode at which the success rate over the last 100 episodes
  reaches 90% of its value over the run's last 100 episodes (only full 100-episode windows;
  "never" if the run ends at 0%); mean over seeds.
* wall-clock: mean per run of training time (metrics.csv's wall_time_s, summed over restarts)
  plus the test phase.
* ceiling: the success rate of ``dynnav_tasks.baselines.state_planner`` (a planner that sees the full
  state) on the experiment's task, from ``--ceilings`` (default docs/results/ceilings.json next
  to the report, written by ``python -m dynnav_tasks.baselines.state_planner --out ...``).

The study's numbered cells (a success rate stated as a number, not read off a curve) get a
table of their own: per cell, the best row among the study's experiment and its named variants,
the experiments whose names start with its name (``moving_obstacles_5_3_ddqn`` competes for
``moving_obstacles_5_3``). Rows whose interval is wider than 20 points are listed with the
seeds that would narrow it if the seeds' rates kept their spread; with ``--configs``, the
configs with fewer than 5 finished seeds are listed too (``--configs`` takes files and folders).

Figures (``--figures``, default docs/results next to the report): reward and Q-loss curves of
the experiments the study compared, each the 100-episode moving average of the mean over seeds.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path

import numpy as np
import yaml

from agents.files import atomic_write_bytes
from agents.training.stats import wilson_interval
from agents.training.plots import moving_average, read_metrics
from agents.study.cells import (cells_table, find_configs, format_ceiling, load_ceilings, short_of_seeds, study_rate,
                           t975, wide_intervals)
from agents.study.numbers import ALIASES, FIGURES, THESIS

WINDOW = 100


def find_runs(paths: list[str | Path]) -> list[Path]:
    """Run directories (config.yaml + metrics.csv) given directly or found inside the folders."""
    runs = []
    for p in map(Path, paths):
        if not p.exists():
            raise ValueError(f"{str(p)!r} does not exist")
        if (p / "config.yaml").is_file() and (p / "metrics.csv").is_file():
            runs.append(p)
        else:
            runs += sorted(m.parent for m in p.rglob("metrics.csv") if (m.parent / "config.yaml").is_file())
    runs = list(dict.fromkeys(r.resolve() for r in runs))
    if not runs:
        raise ValueError(f"no run directories (config.yaml + metrics.csv) in {', '.join(map(str, paths))}")
    return runs


def episodes_to_converge(success: np.ndarray, window: int = WINDOW) -> int | None:
    """First episode (1-based) whose moving success rate reaches 90% of the final one."""
    if len(success) < window:
        return None
    rate = moving_average(success, window)[window - 1:]
    final = rate[-1]
    if not final > 0:
        return None
    return int(np.argmax(rate >= 0.9 * final - 1e-12)) + window


def load_run(run_dir: Path) -> dict:
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    info_path = run_dir / "sweep_run.json"
    info = json.loads(info_path.read_text()) if info_path.is_file() else {}
    name = info.get("experiment") or ALIASES.get(config.get("name"), config.get("name"))
    metrics = read_metrics(run_dir / "metrics.csv")
    run = dict(dir=run_dir, experiment=name, seed=config.get("seed"), task=config.get("task"),
               planned=config.get("episodes"), metrics=metrics, trained=len(metrics.get("episode", [])))
    eval_path = run_dir / "eval.json"
    if eval_path.is_file():
        ev = json.loads(eval_path.read_text())
        s = ev["summary"]
        run.update(finished=True, success=s["success_rate"], n=s["episodes"], steps=s["avg_steps_success"],
                   converge=episodes_to_converge(metrics["success"]) if metrics else None,
                   wall=float(metrics["wall_time_s"][-1]) + float(info.get("eval_s", 0.0)) if metrics else None)
    else:
        run["finished"] = False
    return run


def finished(runs: list[dict]) -> list[dict]:
    """The runs that have their test (eval.json): the only ones the tables and figures show."""
    return [r for r in runs if r["finished"]]


def summarize(runs: list[dict]) -> dict:
    # per seed in seed order (2 before 10), whatever order the folders were found in
    done = sorted(finished(runs), key=lambda r: (r["seed"] is None, r["seed"] or 0))
    out = dict(seeds=len(done), unfinished=[r for r in runs if not r["finished"]])
    if not done:
        return out
    rates = np.array([r["success"] for r in done])
    mean = float(rates.mean())
    if len(done) >= 2:
        half = t975(len(done) - 1) * rates.std(ddof=1) / math.sqrt(len(done))
        lo, hi, how = max(0.0, mean - half), min(1.0, mean + half), "t"
    else:
        lo, hi = wilson_interval(round(done[0]["success"] * done[0]["n"]), done[0]["n"])
        how = "Wilson"
    steps = [r["steps"] for r in done if r["steps"] is not None]
    conv = [r["converge"] for r in done]
    walls = [r["wall"] for r in done if r["wall"] is not None]
    out.update(success=mean, ci=(lo, hi), ci_kind=how, per_seed=rates.tolist(),
               sd=float(rates.std(ddof=1)) if len(done) >= 2 else None,
               steps=float(np.mean(steps)) if steps else None,
               converge=(float(np.mean(conv)) if all(c is not None for c in conv) else None),
               never=sum(c is None for c in conv), wall=float(np.mean(walls)) if walls else None,
               episodes=int(np.mean([r["trained"] for r in done])))
    return out


def mean_curve(runs: list[dict], key: str) -> np.ndarray:
    """Per-episode mean over the runs (runs of different lengths: over those that got there)."""
    curves = [r["metrics"][key] for r in runs if r["metrics"]]
    if not curves:
        return np.array([])
    n = max(len(c) for c in curves)
    stack = np.full((len(curves), n), np.nan)
    for i, c in enumerate(curves):
        stack[i, :len(c)] = c
    counts = np.sum(np.isfinite(stack), axis=0)
    sums = np.nansum(stack, axis=0)
    return np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)


def draw_figure(path: Path, title: str, members: list[tuple[str, str, list[dict]]]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(8, 5), dpi=100)
    for (key, ylabel), ax in zip((("loss", "Q-loss (mean per episode)"), ("return", "accumulated reward")), axes):
        for label, runs in ((m[1], m[2]) for m in members):
            curve = mean_curve(runs, key)
            if len(curve):
                ax.plot(np.arange(1, len(curve) + 1), moving_average(curve, WINDOW), linewidth=1.5,
                        label=f"{label} ({len(runs)} seed{'s' * (len(runs) != 1)})")
        ax.set_xlabel("episode")
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        if key == "loss":
            ax.set_yscale("log")
    axes[1].legend(loc="lower right", fontsize=7)
    fig.suptitle(f"{title}\n{WINDOW}-episode moving average of the mean over seeds", fontsize=10)
    fig.tight_layout()
    tmp = path.with_name(f".{path.name}.tmp.png")
    fig.savefig(tmp)
    plt.close(fig)
    os.replace(tmp, path)


def _pct(x) -> str:
    return "-" if x is None else f"{x:.0%}"


def render(groups: dict[str, list[dict]], figures: list[tuple[str, str]], sources: list[str],
           discussion: str = "", ceilings: dict[str, float] | None = None,
           configs: dict[str, str] | None = None) -> str:
    ceilings = ceilings or {}
    order = [e for e in THESIS if e in groups] + sorted(e for e in groups if e not in THESIS)
    summaries = {e: summarize(groups[e]) for e in order}
    tasks = {e: groups[e][0]["task"] for e in order}
    lines = ["# Results", "",
             "Test success (100 episodes per run in the study's configs, epsilon 0) per experiment, beside the study's number. "
             "Made by `python -m agents.study.report " + " ".join(sources) + "`; the method is in `agents/study/report.py`: "
             "success is the mean over seeds with a 95% t-interval over the seeds' rates (Wilson interval of the "
             "episodes when there is one seed); steps are those of successful test episodes; *converge* is the "
             "first training episode at which the 100-episode success rate reaches 90% of its final value; "
             "wall-clock is training plus test per run on one core (sum of episode times, checkpoints and "
             "auto-encoder updates not counted); *ceiling* is the success rate of a planner that sees the full "
             "state (`dynnav_tasks.baselines.state_planner`) in the same world.", ""]
    if any(study_rate(e) is not None for e in THESIS):
        lines += cells_table(summaries, tasks, ceilings) + ["", "## Every experiment", ""]
    lines += ["| experiment | task | seeds | success (95% CI) | study | ceiling | steps | converge (episodes) | study | "
              "wall-clock | per seed |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    unfinished = []
    for e in order:
        s = summaries[e]
        t = THESIS.get(e, dict(success="not in the study", converge="-"))
        unfinished += s["unfinished"]
        task = tasks[e]
        ceiling = format_ceiling(ceilings.get(task))
        if not s["seeds"]:
            lines.append(f"| `{e}` | {task} | 0 | not finished | {t.get('success', '-')} | {ceiling} | | | "
                         f"{t.get('converge', '-')} | | |")
            continue
        lo, hi = s["ci"]
        conv = "never" if s["converge"] is None else f"{s['converge']:.0f}"
        if s["converge"] is None and s["never"] < s["seeds"]:
            conv = f"never in {s['never']} of {s['seeds']}"
        lines.append(
            f"| `{e}` | {task} | {s['seeds']} | {s['success']:.0%} ({lo:.0%}-{hi:.0%}, {s['ci_kind']}) | "
            f"{t.get('success', '-')} | {ceiling} | {'-' if s['steps'] is None else format(s['steps'], '.1f')} | {conv} (of "
            f"{s['episodes']}) | {t.get('converge', '-')} | {'-' if s['wall'] is None else format(s['wall'], '.0f') + ' s'} | "
            f"{' '.join(_pct(x) for x in s['per_seed'])} |")
    if any(e in THESIS for e in order):
        lines += ["", "Where the study's numbers come from (`agents/study/numbers.py`):", ""]
        lines += [f"* `{e}`: {THESIS[e]['source']}" for e in order if e in THESIS]
    missing = [e for e in THESIS if e not in groups]
    if missing:
        lines += ["", "Experiments of the study with a config but no run in these folders yet: "
                  + ", ".join(f"`{e}`" for e in missing) + "."]
    lines += wide_intervals(summaries)
    lines += short_of_seeds(summaries, configs or {})
    if unfinished:
        lines += ["", "## Runs still in progress", "", "Left out of the table above; `python -m agents.study.sweep` "
                  "with the same arguments continues them from their checkpoints.", ""]
        lines += [f"* `{r['experiment']}` seed {r['seed']}: {r['trained']} of {r['planned']} episodes" for r in unfinished]
    if discussion.strip():
        lines += ["", discussion.strip()]
    if figures:
        lines += ["", "## Learning curves", ""]
        for rel, title in figures:
            lines += [f"![{title}]({rel})", ""]
    return "\n".join(lines) + "\n"


def write_report(paths: list[str | Path], out: str | Path = "RESULTS.md", figures_dir: str | Path | None = None,
                 discussion: str | Path | None = None, ceilings: str | Path | None = None,
                 configs: list[str | Path] | None = None) -> Path:
    """Write the report; ``discussion``: a Markdown file inserted after the table (written by hand);
    ``ceilings``: the planner's JSON (default docs/results/ceilings.json next to ``out``, if there);
    ``configs``: config files or folders of them, each config listed if it has fewer than MIN_SEEDS
    finished seeds."""
    out = Path(out)
    config_paths = find_configs(configs) if configs is not None else {}
    if ceilings is not None and not Path(ceilings).is_file():
        raise ValueError(f"ceilings file {str(ceilings)!r} does not exist")
    ceiling_rates = load_ceilings(ceilings if ceilings is not None else out.parent / "docs" / "results" / "ceilings.json")
    text = ""
    if discussion is not None:
        if not Path(discussion).is_file():
            raise ValueError(f"discussion file {str(discussion)!r} does not exist")
        text = Path(discussion).read_text()
    figures_dir = Path(figures_dir) if figures_dir else out.parent / "docs" / "results"
    groups: dict[str, list[dict]] = {}
    for run_dir in find_runs(paths):
        run = load_run(run_dir)
        groups.setdefault(run["experiment"], []).append(run)
    figures_dir.mkdir(parents=True, exist_ok=True)
    out.parent.mkdir(parents=True, exist_ok=True)
    written = []
    for stem, title, members in FIGURES:
        # a comparison needs two curves
        present = [(e, label, done) for e, label in members if (done := finished(groups.get(e, [])))]
        if len(present) >= 2:
            path = figures_dir / f"{stem}.png"
            draw_figure(path, title, present)
            written.append((os.path.relpath(path.resolve(), out.parent.resolve()), title))
    atomic_write_bytes(out, render(groups, written, [str(p) for p in paths], text, ceiling_rates,
                                   config_paths).encode())
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m agents.study.report", description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="+", help="sweep folders or run directories")
    parser.add_argument("--out", default="RESULTS.md", help="report file (default RESULTS.md)")
    parser.add_argument("--figures", default=None, help="folder for the PNGs (default docs/results next to --out)")
    parser.add_argument("--discussion", default=None,
                        help="Markdown file inserted after the table: why results differ from the study's")
    parser.add_argument("--ceilings", default=None,
                        help="the planner's success rates per task (python -m dynnav_tasks.baselines.state_planner --out FILE); "
                             "default docs/results/ceilings.json next to --out, if it exists")
    parser.add_argument("--configs", nargs="+", default=None, metavar="CONFIG",
                        help="config files or folders of them (searched recursively): list the configs with fewer "
                             "than 5 finished seeds")
    args = parser.parse_args(argv)
    try:
        out = write_report(args.paths, args.out, args.figures, args.discussion, args.ceilings, args.configs)
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1:])
