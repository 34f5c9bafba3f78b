"""Planner speed: ``dynnav_tasks.baselines.state_planner`` with its plain-Python collision check beside the
same planner with a numpy check (one array expression over the boxes per search node, the first
way one writes it), measured in the same run on the same episodes.

    python benchmarks/state_planner.py [--task DynNav-OverlappingAreas-v1] [--episodes 3]

Both variants must take the same actions (the check is the same distance test); the script
says so, and prints seconds per episode and per step. The search calls the check for every
node it expands (up to ``max_expansions`` = 30000 per step, three children each), with a
handful of boxes: numpy's fixed cost per call is larger than the work.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from dynnav_tasks.baselines import state_planner  # noqa: E402
from machine import describe, pin_one_core  # noqa: E402


def numpy_hits(x, y, boxes, clearance_sq) -> bool:
    """The baseline: the same test written as one numpy expression over the boxes."""
    if not boxes:
        return False
    b = np.asarray(boxes)
    dx = np.maximum(np.maximum(b[:, 0] - x, x - b[:, 2]), 0)
    dy = np.maximum(np.maximum(b[:, 1] - y, y - b[:, 3]), 0)
    return bool((dx * dx + dy * dy).min() < clearance_sq)


class ActionLog:
    """Wraps ``StatePlanner.act`` to record the actions and the time spent planning."""

    def __init__(self):
        self.actions, self.seconds = [], 0.0
        self._act = state_planner.StatePlanner.act

    def __call__(self, planner, state, yaw):
        t = time.perf_counter()
        action = self._act(planner, state, yaw)
        self.seconds += time.perf_counter() - t
        self.actions.append(action)
        return action


def timed_run(task: str, seeds, hits) -> ActionLog:
    log, original = ActionLog(), state_planner._hits
    state_planner._hits, state_planner.StatePlanner.act = hits, lambda p, s, y: log(p, s, y)
    try:
        state_planner.run_planner(task, seeds)
    finally:
        state_planner._hits, state_planner.StatePlanner.act = original, log._act
    return log


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--task", default="DynNav-OverlappingAreas-v1", help="task to plan in")
    parser.add_argument("--episodes", type=int, default=3, help="episodes per variant (seeds 0..n-1)")
    args = parser.parse_args()
    print(describe(pin_one_core()))
    print(f"{args.task}, {args.episodes} episodes per variant, numpy {np.__version__}\n")
    seeds = range(args.episodes)
    print(f"{'collision check':<32} {'s/episode':>10} {'ms/step':>10} {'steps':>7}")
    logs = []
    for name, hits in (("numpy (baseline)", numpy_hits), ("plain Python (the planner's)", state_planner._hits)):
        log = timed_run(args.task, seeds, hits)
        logs.append(log)
        print(f"{name:<32} {log.seconds / args.episodes:>10.2f} {log.seconds / len(log.actions) * 1e3:>10.1f} "
              f"{len(log.actions):>7}")
    same = logs[0].actions == logs[1].actions
    print(f"\nsame actions: {'yes' if same else 'NO'}; the planner takes "
          f"{logs[1].seconds / logs[0].seconds:.2f}x the baseline's time")


if __name__ == "__main__":
    main()
