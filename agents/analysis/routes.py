"""Test outcomes by route: where each test path first crosses a line of the arena.

    python -m agents.analysis.routes RUN_DIR [RUN_DIR ...] --line y=1 --edges 0.35 3

Reads each run's ``eval.json`` (the test episodes' trajectories) and groups the episodes by the
other coordinate at the first point of the path on or past the line (``--line y=1``: the first
point with y >= 1, grouped by its x; ``--line x=2``: the first with x >= 2, grouped by its y).
``--edges`` splits that coordinate into bins; a path that never reaches the line is its own group.
Per group: episodes, success / collision / timeout rates, the mean steps of the successes and
the mean return. Nothing is simulated: it is the recorded paths only.
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from pathlib import Path

from agents.analysis.outcomes import OUTCOMES, load_evals

NEVER = "never"


def parse_line(text: str) -> tuple[int, float]:
    """'y=1' -> (1, 1.0): the axis (0 for x, 1 for y) and the line's value on it."""
    axis, sep, value = text.replace(" ", "").partition("=")
    if not sep or axis not in ("x", "y"):
        raise ValueError(f"--line {text!r}: write it as x=VALUE or y=VALUE, e.g. y=1")
    try:
        return (0 if axis == "x" else 1), float(value)
    except ValueError:
        raise ValueError(f"--line {text!r}: {value!r} is not a number") from None


def crossing(trajectory: list, axis: int, value: float) -> float | None:
    """The other coordinate at the path's first point with coordinate ``axis`` >= ``value`` (None if none)."""
    for point in trajectory or ():
        if point[axis] >= value:
            return float(point[1 - axis])
    return None


def bin_labels(edges: list[float]) -> list[str]:
    """The bins' labels in order: '< a', 'a-b', ..., '>= z' ('any' without edges)."""
    if not edges:
        return ["any"]
    return [f"< {edges[0]:g}", *(f"{a:g}-{b:g}" for a, b in zip(edges, edges[1:])), f">= {edges[-1]:g}"]


def bin_label(position: float | None, edges: list[float]) -> str:
    """The label of the bin of ``edges`` that holds ``position``; NEVER for None."""
    if position is None:
        return NEVER
    return bin_labels(edges)[sum(position >= e for e in edges)]


def by_route(run_dirs: list[str | Path], axis: int, value: float, edges: list[float]) -> dict[str, list[dict]]:
    """Bin label -> the test episodes (eval.json records) of all the runs whose path crosses there."""
    _, evals = load_evals(run_dirs)
    groups: dict[str, list[dict]] = defaultdict(list)
    for _, e in evals:
        for ep in e["episodes"]:
            groups[bin_label(crossing(ep.get("trajectory"), axis, value), edges)].append(ep)
    return dict(groups)


def render(groups: dict[str, list[dict]], axis: int, value: float, edges: list[float]) -> str:
    other = "yx"[axis]
    lines = [f"| {other} where the path first reaches {'xy'[axis]} >= {value:g} | episodes | success | collision "
             "| timeout | steps per success | mean return |", "|---|---|---|---|---|---|---|"]
    for label in [*bin_labels(edges), NEVER]:
        eps = groups.get(label)
        if not eps:
            continue
        rates = " | ".join(f"{sum(ep['outcome'] == o for ep in eps) / len(eps):.0%}" for o in OUTCOMES)
        steps = [ep["steps"] for ep in eps if ep["outcome"] == "success"]
        mean_steps = f"{sum(steps) / len(steps):.1f}" if steps else "-"
        lines.append(f"| {label} | {len(eps)} | {rates} | {mean_steps} | {sum(ep['ret'] for ep in eps) / len(eps):.1f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="run directories (with eval.json)")
    parser.add_argument("--line", required=True, help="x=VALUE or y=VALUE: the line the paths cross")
    parser.add_argument("--edges", type=float, nargs="*", default=[],
                        help="bin edges along the line, increasing (m)")
    args = parser.parse_args(argv)
    try:
        axis, value = parse_line(args.line)
    except ValueError as err:
        parser.error(str(err))
    if any(b <= a for a, b in zip(args.edges, args.edges[1:])):
        parser.error(f"--edges must increase, got {' '.join(f'{e:g}' for e in args.edges)}")
    try:
        groups = by_route(args.runs, axis, value, args.edges)
    except (FileNotFoundError, ValueError) as err:
        raise SystemExit(f"agents.analysis.routes: {err}") from None
    print(render(groups, axis, value, args.edges))


if __name__ == "__main__":
    main()
