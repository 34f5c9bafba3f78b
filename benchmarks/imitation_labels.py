"""What a label costs: the full-state planner's time per decision in each difficulty's train worlds,
beside a student's decision (the generalist's MLP on the egocentric state) and an environment step,
measured in the same run on the same core.

    python benchmarks/imitation_labels.py [--episodes 6] [--no-pin]

The teacher plans every step of an episode (its forecast follows the boxes from step to step),
so a labelled episode costs its steps times the planner's time per decision; the line per
difficulty gives both, and the labels per second one core makes. ``agents.imitation``'s
collector runs one such loop per process.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from machine import describe, pin_one_core  # noqa: E402

import gymnasium as gym  # noqa: E402
import torch  # noqa: E402

import dynnav_tasks  # noqa: E402,F401
from agents.core.networks import MLPQNetwork  # noqa: E402
from dynnav_tasks.baselines.state_planner import PlannerController  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=6, help="planner episodes per difficulty")
    parser.add_argument("--no-pin", action="store_true", help="do not pin to one core")
    args = parser.parse_args()
    pinned = "not pinned" if args.no_pin else pin_one_core()
    torch.set_num_threads(1)
    print(describe(pinned))
    net = MLPQNetwork(42, 3, (256, 256)).eval()
    print(f"{'difficulty':<10} {'label ms':>9} {'student ms':>10} {'step ms':>8} {'steps/episode':>13} "
          f"{'labels/s':>9} {'success':>8}")
    for difficulty in ("easy", "medium", "hard"):
        env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Procedural-v1", difficulty=difficulty, way=True))
        teacher, label_s, student_s, step_s, steps, wins = PlannerController(), 0.0, 0.0, 0.0, 0, 0
        for seed in range(args.episodes):
            obs, _ = env.reset(seed=seed)
            teacher.start(env.unwrapped)
            while True:
                t0 = time.perf_counter()
                action = teacher.act(env.unwrapped)
                t1 = time.perf_counter()
                with torch.inference_mode():
                    net(torch.as_tensor(obs)[None]).argmax()
                t2 = time.perf_counter()
                obs, _, terminated, truncated, info = env.step(action)
                t3 = time.perf_counter()
                label_s, student_s, step_s, steps = label_s + t1 - t0, student_s + t2 - t1, step_s + t3 - t2, steps + 1
                if terminated or truncated:
                    wins += bool(info["success"])
                    break
        env.close()
        print(f"{difficulty:<10} {1000 * label_s / steps:>9.1f} {1000 * student_s / steps:>10.3f} "
              f"{1000 * step_s / steps:>8.2f} {steps / args.episodes:>13.0f} {steps / (label_s + step_s):>9.0f} "
              f"{wins / args.episodes:>8.0%}")
    print(f"(means over {args.episodes} planner episodes per difficulty; np {np.__version__}, torch {torch.__version__})")


if __name__ == "__main__":
    main()
