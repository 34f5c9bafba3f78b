"""Step rate of the continuous drive (``control_mode="diff_drive_vel"``) beside the discrete
one's, measured in the same run on the same core.

    python benchmarks/continuous_drive.py [--steps 4000] [--task DynNav-MovingObstacles-v1] [--no-pin]

Both envs are the task through ``gym.make`` + ``NumpyWrapper`` under a random policy: the
discrete drive takes actions drawn uniformly from {0, 1, 2}; the continuous one takes (v, w)
drawn uniformly from its box (arcs: the worst case, the joint targets change at every
sub-step). The actions are drawn before the clock starts; only ``env.step`` is timed (resets
are not counted: the two policies end episodes at different rates). The envs step in turns,
``CHUNK`` steps at a time, so that a load from other processes weighs on both alike; each
figure is the median over the chunks. The last line gives the continuous drive's rate as a
share of the discrete one's.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from machine import describe, pin_one_core, timed_steps

CHUNK = 250
"""steps of one env measured at a time, in turns with the other"""


class Stepper:
    """One env under a random policy of pre-drawn actions; ``run(n)`` times n steps."""

    def __init__(self, env, seed: int = 0):
        self.env = env
        env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        space = env.action_space
        if hasattr(space, "n"):
            self.draw = lambda n: rng.integers(space.n, size=n).tolist()
        else:
            self.draw = lambda n: list(rng.uniform(space.low, space.high, size=(n, 2)).astype(np.float32))
        self.times: list[float] = []  # seconds per step, one figure per chunk

    def run(self, n: int) -> None:
        self.times.append(timed_steps(self.env, self.draw(n), self.env.reset) / n)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=4000, help="steps of each drive")
    parser.add_argument("--task", default="DynNav-MovingObstacles-v1")
    parser.add_argument("--no-pin", action="store_true", help="do not pin the process to one core")
    args = parser.parse_args()
    pinned = "not pinned" if args.no_pin else pin_one_core()

    import gymnasium as gym
    import torch

    import dynnav_tasks

    torch.set_num_threads(1)
    print(describe(pinned))
    print(f"task {args.task}, {args.steps} steps per drive in chunks of {CHUNK}, resets not counted")
    steppers = {
        mode: Stepper(dynnav_tasks.NumpyWrapper(gym.make(args.task, control_mode=mode)))
        for mode in ("discrete_drive", "diff_drive_vel")
    }
    for stepper in steppers.values():  # warm up
        stepper.run(CHUNK)
        stepper.times.clear()
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for _ in range(max(1, args.steps // CHUNK)):
        for stepper in steppers.values():
            stepper.run(CHUNK)
    share = (time.process_time() - cpu0) / (time.perf_counter() - wall0)
    rates = {}
    print(f"{'control_mode':<16} {'step us':>8} {'steps/s':>8}")
    for mode, stepper in steppers.items():
        per_step = statistics.median(stepper.times)
        rates[mode] = 1.0 / per_step
        print(f"{mode:<16} {per_step * 1e6:>8.1f} {rates[mode]:>8.0f}")
        stepper.env.close()
    ratio = rates["diff_drive_vel"] / rates["discrete_drive"]
    print(f"the process had {share:.0%} of its core")
    print(f"continuous / discrete step rate: {ratio:.1%} ({'at least' if ratio >= 0.9 else 'below'} 90%)")


if __name__ == "__main__":
    main()
