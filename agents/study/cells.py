"""The report's sections on the study's numbered cells and on seeds (see agents/study/report.py).

* the cells table: per success rate the study states as a number, the best row among the study's
  experiment and its named variants, beside the planner's ceiling;
* the rows whose 95% interval over seeds is wider than MAX_WIDTH, with the seeds that would
  narrow it;
* the configs with fewer than MIN_SEEDS runs in the table;
* the rows with memory (a name ending in ``-gru`` or ``-lstm``: the recurrent Q-network of
  docs/memory.md) beside the feed-forward row they extend and the ceiling.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from agents.study.numbers import THESIS

# t(0.975, df) for df = 1..30; larger df use 1.96
T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145,
        2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048,
        2.045, 2.042]
MIN_SEEDS = 5
"""seeds a row needs before it can meet a cell of the study"""
MAX_WIDTH = 0.20
"""a row whose 95% interval over seeds is wider than this is listed with the seeds it would need"""
MEMORY_SUFFIXES = ("-gru", "-lstm")
"""an experiment named ``<row><suffix>`` is ``<row>`` with a recurrent Q-network"""


def t975(df: int) -> float:
    """The t distribution's 97.5% quantile with ``df`` degrees of freedom (1.96 above 30)."""
    return T975[df - 1] if df <= len(T975) else 1.96


def interval_width(seeds: int, sd: float) -> float:
    """The full width of the t-interval over ``seeds`` rates with spread ``sd``, before the interval
    is clipped to 0-100% for display (a row at 7% with a 23-point interval shows as 0-18%)."""
    return 2 * t975(seeds - 1) * sd / math.sqrt(seeds)


def seeds_for_width(sd: float, width: float = MAX_WIDTH, limit: int = 200) -> int | None:
    """The fewest seeds whose t-interval (2 t(0.975, n-1) sd / sqrt(n)) is at most ``width`` if the
    seeds' rates keep the spread ``sd``; None if more than ``limit``."""
    for n in range(2, limit + 1):
        if interval_width(n, sd) <= width + 1e-12:
            return n
    return None


def format_ceiling(x) -> str:
    """A ceiling to a tenth of a point: 99.5% is not 100%."""
    return "-" if x is None else f"{x * 100:.1f}".removesuffix(".0") + "%"


def study_rate(experiment: str) -> float | None:
    """The study's success rate of a numbered cell (e.g. "93% (Sec. 6.1...)" -> 0.93); None for
    the experiments whose success the study does not state as a number."""
    text = THESIS.get(experiment, {}).get("success", "")
    digits = text.split("%")[0]
    return float(digits) / 100 if "%" in text and digits.isdigit() else None


def cell_of(experiment: str) -> str | None:
    """The study's experiment a run competes with: itself, or the longest study name it extends
    as ``<study name>-<suffix>`` (``5.3-g0.1`` competes for ``5.3``)."""
    if experiment in THESIS:
        return experiment
    owners = [e for e in THESIS if experiment.startswith(e + "-")]
    return max(owners, key=len) if owners else None


def load_ceilings(path: str | Path | None) -> dict[str, float]:
    """task id -> the planner's success rate, from a JSON file the planner wrote (empty if none)."""
    if path is None or not Path(path).is_file():
        return {}
    try:
        data = json.loads(Path(path).read_text())
        return {task: float(v["success"]) for task, v in data.items()}
    except (ValueError, KeyError, TypeError, AttributeError) as err:
        raise ValueError(f"ceilings file {str(path)!r} is not what dynnav_tasks.baselines.state_planner --out writes: {err}")


def cells_table(summaries: dict[str, dict], tasks: dict[str, str], ceilings: dict[str, float]) -> list[str]:
    """Per numbered cell of the study: its best row (the study's method or a named variant)."""
    lines = ["## The study's numbered cells", "",
             "Per success rate the study states as a number: our best experiment for it, the study's own "
             "configuration or a named variant (an experiment whose name extends the study's), with its "
             f"95% interval over seeds; a row with {MIN_SEEDS} seeds or more is preferred, and only such a row can "
             "meet the study's number. The ceiling is what a planner that sees the full state reaches "
             "(`python -m dynnav_tasks.baselines.state_planner`).", "",
             "| study's experiment | study | our best row | seeds | success (95% CI) | ceiling | at or above |",
             "|---|---|---|---|---|---|---|"]
    for cell in THESIS:
        target = study_rate(cell)
        if target is None:
            continue
        rows = [e for e, s in summaries.items() if cell_of(e) == cell and s["seeds"]]
        if not rows:
            lines.append(f"| `{cell}` | {target:.0%} | not run | 0 | - | - | - |")
            continue
        enough = [e for e in rows if summaries[e]["seeds"] >= MIN_SEEDS]
        best = max(enough or rows, key=lambda e: summaries[e]["success"])
        s = summaries[best]
        lo, hi = s["ci"]
        ceiling = ceilings.get(tasks[best])
        met = "no" if s["success"] < target - 1e-9 else "yes" if s["seeds"] >= MIN_SEEDS else f"needs {MIN_SEEDS} seeds"
        lines.append(f"| `{cell}` | {target:.0%} | `{best}` | {s['seeds']} | {s['success']:.1%} ({lo:.0%}-{hi:.0%}) | "
                     f"{format_ceiling(ceiling)} | {met} |")
    return lines


def wide_intervals(summaries: dict[str, dict]) -> list[str]:
    """The rows whose 95% interval over seeds is wider than MAX_WIDTH, with the seeds that would narrow it."""
    wide = [(e, s) for e, s in summaries.items()
            if s.get("sd") is not None and interval_width(s["seeds"], s["sd"]) > MAX_WIDTH]
    if not wide:
        return []
    lines = ["", f"## Intervals wider than {MAX_WIDTH * 100:.0f} points", "",
             f"Rows whose 95% interval over seeds is wider than {MAX_WIDTH * 100:.0f} points (its full width, "
             "before it is clipped to 0-100%), and how many seeds "
             "would narrow it below that if the seeds' rates kept their spread (`python -m agents.study.sweep CONFIG "
             "--seeds N` adds the missing ones):", ""]
    for e, s in wide:
        lo, hi = s["ci"]
        need = seeds_for_width(s["sd"])
        need = f"about {max(need, MIN_SEEDS)}" if need is not None else "more than 200"
        width = interval_width(s["seeds"], s["sd"])
        lines.append(f"* `{e}`: {s['seeds']} seeds, {lo:.0%}-{hi:.0%}, {width * 100:.0f} points wide "
                     f"(standard deviation {s['sd'] * 100:.0f} "
                     f"points over seeds): {need} seeds")
    return lines


def short_of_seeds(summaries: dict[str, dict], configs: dict[str, str]) -> list[str]:
    """The configs (experiment -> path) with fewer than MIN_SEEDS runs in the table."""
    seeds = {e: summaries[e]["seeds"] if e in summaries else 0 for e in configs}
    short = sorted((p, seeds[e]) for e, p in configs.items() if seeds[e] < MIN_SEEDS)
    if not short:
        return []
    lines = ["", f"## Configs with fewer than {MIN_SEEDS} seeds", "",
             f"Configs with fewer than {MIN_SEEDS} runs in the table (`python -m agents.study.sweep CONFIG "
             f"--seeds {MIN_SEEDS}` runs the missing ones and continues those in progress):", ""]
    return lines + [f"* `{p}`: {n} finished" for p, n in short]


def memory_section(summaries: dict[str, dict], tasks: dict[str, str], ceilings: dict[str, float]) -> list[str]:
    """The rows with memory: per experiment ``<row>-gru`` (or ``-lstm``), the study's number for its
    cell, the feed-forward ``<row>``, the memory row and the planner's ceiling."""
    rows = [e for e in summaries if e.endswith(MEMORY_SUFFIXES) and summaries[e]["seeds"]]
    if not rows:
        return []
    lines = ["", "## Memory", "",
             "Rows with a recurrent Q-network (`dqn.recurrent`, docs/memory.md), each beside the feed-forward row "
             "it extends (its name without `-gru` or `-lstm`), the study's number and the ceiling.", "",
             "| with memory | study | feed-forward: seeds, success | with memory: seeds, success (95% CI) | ceiling |",
             "|---|---|---|---|---|"]
    for e in rows:
        base = e[:e.rindex("-")]
        cell = cell_of(e)
        target = study_rate(cell) if cell else None
        ff = summaries.get(base)
        ff_text = f"{ff['seeds']}, {ff['success']:.1%}" if ff and ff["seeds"] else "not run"
        s = summaries[e]
        lo, hi = s["ci"]
        lines.append(f"| `{e}` | {'-' if target is None else f'{target:.0%}'} | {ff_text} | "
                     f"{s['seeds']}, {s['success']:.1%} ({lo:.0%}-{hi:.0%}) | {format_ceiling(ceilings.get(tasks[e]))} |")
    return lines


def find_configs(paths: list[str | Path]) -> dict[str, str]:
    """experiment name (the file's stem, as agents.study.sweep names it) -> path, for each config file given
    and every YAML under each folder given."""
    found = {}
    for path in map(Path, paths):
        if not path.exists():
            raise ValueError(f"config path {str(path)!r} does not exist")
        for p in sorted(path.rglob("*.yaml")) if path.is_dir() else [path]:
            found[p.stem] = p.as_posix()
    return found


def load_cells(path: str | Path | None) -> dict[str, dict]:
    """The entries of a procedural ceilings file (``controller/difficulty/split`` -> rates), {} if none."""
    if path is None or not Path(path).is_file():
        return {}
    try:
        data = json.loads(Path(path).read_text())
        return {k: dict(success=float(v["success"]), spl=float(v.get("spl", 0.0))) for k, v in data.items()}
    except (ValueError, KeyError, TypeError, AttributeError) as err:
        raise ValueError(f"procedural ceilings file {str(path)!r} is not what the baselines' --out writes: {err}")
