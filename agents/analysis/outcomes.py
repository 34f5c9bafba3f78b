"""Test outcomes broken down by what each episode drew: the chosen target's start and, in worlds
whose obstacles run on a route (5.3), the obstacles' speed.

    python -m agents.analysis.outcomes RUN_DIR [RUN_DIR ...] [--speed-bins 0.1]

Reads each run's ``eval.json`` (the test phase's episodes and their seeds), resets the run's
task with every episode's seed to read what that episode drew (no policy is run: a reset with
the same seed draws the same world), and prints success / collision / timeout rates per group
over all the given runs together. A timeout *standing still* is one whose robot ended within
1 cm of where it stood STILL_STEPS steps before the end: turning in place, since a forward
step moves it 0.15 m (read from the episode's trajectory in eval.json).
"""

from __future__ import annotations

import argparse
import json
from collections import Counter, defaultdict
from pathlib import Path

OUTCOMES = ("success", "collision", "timeout")
STILL = "timeout standing still"
STILL_STEPS = 20
STILL_TOLERANCE = 0.01  # m


def standing_still(trajectory: list | None, steps: int = STILL_STEPS, tolerance: float = STILL_TOLERANCE) -> bool:
    """Whether the robot's last ``steps`` positions all lie within ``tolerance`` m of its last one
    (False for a trajectory shorter than that, or none)."""
    if not trajectory or len(trajectory) <= steps:
        return False
    x, y = trajectory[-1]
    return all((px - x) ** 2 + (py - y) ** 2 <= tolerance ** 2 for px, py in trajectory[-1 - steps:])


def route_speed(env) -> float | None:
    """The episode's obstacle speed (m per step) when the task's moving obstacles follow a route."""
    from dynnav_tasks.motion import Route

    speeds = [m.speed for m in env.unwrapped.obstacle_motions if isinstance(m.motion, Route)]
    return max(speeds) if speeds else None


def speed_bin(speed: float | None, width: float) -> float | None:
    """The lower edge of the bin of ``width`` that holds ``speed`` (None stays None)."""
    return None if speed is None else round(int(speed / width) * width, 6)


def load_evals(run_dirs: list[str | Path]) -> tuple[str, list[tuple[Path, dict]]]:
    """The one task the runs test and each run's (directory, eval.json contents); a run without a test
    phase or runs of different tasks are refused."""
    evals = []
    for d in run_dirs:
        path = Path(d) / "eval.json"
        if not path.is_file():
            raise FileNotFoundError(f"{path} not found: give run directories whose test phase has run "
                                    "(python -m agents.dqn --eval --checkpoint RUN writes it)")
        evals.append((Path(d), json.loads(path.read_text())))
    tasks = {e["task"] for _, e in evals}
    if len(tasks) != 1:
        raise ValueError(f"the runs test different tasks ({', '.join(sorted(tasks))}): give runs of one task")
    return tasks.pop(), evals


def breakdown(run_dirs: list[str | Path], width: float = 0.1) -> dict[tuple, Counter]:
    """(speed bin's lower edge or None, target start) -> Counter of outcomes over the runs' test episodes,
    and under STILL the timeouts that ended standing still (also counted as timeouts)."""
    import gymnasium as gym

    import dynnav_tasks  # noqa: F401  (registers the tasks)

    task, evals = load_evals(run_dirs)
    env = gym.make(task)
    groups: dict[tuple, Counter] = defaultdict(Counter)
    try:
        for _, e in evals:
            for ep in e["episodes"]:
                env.reset(seed=ep["seed"])
                low = speed_bin(route_speed(env), width)
                counts = groups[(low, tuple(ep["target_start"]))]
                counts[ep["outcome"]] += 1
                if ep["outcome"] == "timeout" and standing_still(ep.get("trajectory")):
                    counts[STILL] += 1
    finally:
        env.close()
    return dict(groups)


def render(groups: dict[tuple, Counter], width: float) -> str:
    lines = ["| obstacle speed (m/step) | target | episodes | success | collision | timeout | timeout standing still |",
             "|---|---|---|---|---|---|---|"]
    for (low, target) in sorted(groups, key=lambda k: (k[0] if k[0] is not None else -1, k[1])):
        c = groups[(low, target)]
        n = sum(v for k, v in c.items() if k != STILL)
        speed = "-" if low is None else f"{low:.2f}-{low + width:.2f}"
        rates = " | ".join(f"{c[o] / n:.0%}" for o in (*OUTCOMES, STILL))
        lines.append(f"| {speed} | ({target[0]:g}, {target[1]:g}) | {n} | {rates} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="run directories (with eval.json)")
    parser.add_argument("--speed-bins", type=float, default=0.1, help="width of the speed bins (m per step)")
    args = parser.parse_args(argv)
    if args.speed_bins <= 0:
        parser.error(f"--speed-bins must be positive, got {args.speed_bins}")
    try:
        groups = breakdown(args.runs, args.speed_bins)
    except (FileNotFoundError, ValueError) as err:
        raise SystemExit(f"agents.analysis.outcomes: {err}") from None
    print(render(groups, args.speed_bins))


if __name__ == "__main__":
    main()
