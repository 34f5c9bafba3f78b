"""Procedural worlds: generation, reset and step rates of DynNav-Procedural-v1 beside the fixed
worlds', measured in the same run on the same core.

    python benchmarks/procedural.py [--worlds 200] [--steps 3000] [--no-pin]

Printed per difficulty (train and ood splits):

* generation ms: ``generate_world(spec, seed)`` alone, over ``--worlds`` new seeds;
* reset ms: ``env.reset(seed=s)`` with a new world every time: generation plus moving the
  pooled bodies into place plus the task's own reset (start, motions, first snapshot); the
  fixed worlds' reset beside it;
* steps/s: ``env.step`` under a random policy, through ``gym.make`` + ``NumpyWrapper``; the
  resets an episode's end calls for are not counted (they are the reset row's).

The fixed worlds DynNav-MovingObstacles-v1 (5.3) and DynNav-MotionAreas-v1 (5.4a), both with
2 moving obstacles in a 6.5 m arena, are measured beside them, and so are generated worlds
spec'd to the same: 2 moving obstacles, a 6-7 m arena, open floor (and the same with
clutter), shown with ``reset(options={"world": w})``. Every env steps in turns, ``CHUNK``
steps at a time, so that a load from other processes weighs on all alike. The last lines give
the generated worlds' step rate as a share of the fixed worlds' at that equal obstacle count.
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import replace

import numpy as np

from machine import describe, pin_one_core, timed_steps

CHUNK = 250
"""steps of one env measured at a time, in turns with the others"""


class Stepper:
    """One env under a random policy; ``run(n)`` steps it n times, resets not counted."""

    def __init__(self, name: str, env, next_reset=None):
        self.name, self.env, self.next_reset = name, env, next_reset or (lambda: {})
        self.env.reset(seed=0, **self.next_reset())
        space = env.action_space
        space.seed(0)
        self.actions = iter(lambda: int(space.sample()), None)
        self.step_time, self.steps = 0.0, 0

    def run(self, n: int) -> None:
        env = self.env
        spent = timed_steps(env, (next(self.actions) for _ in range(n)), lambda: env.reset(**self.next_reset()))
        self.step_time += spent
        self.steps += n

    @property
    def rate(self) -> float:
        return self.steps / self.step_time


def milliseconds(times: list[float]) -> str:
    ms = np.array(times) * 1000
    return f"{np.median(ms):6.2f} median {np.percentile(ms, 95):6.2f} p95 {ms.max():6.2f} max"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--worlds", type=int, default=200, help="new worlds per generation and reset figure (200)")
    parser.add_argument("--steps", type=int, default=3000, help="steps per step-rate figure (3000)")
    parser.add_argument("--no-pin", action="store_true", help="do not pin the process to one core")
    args = parser.parse_args()
    pinned = "not pinned" if args.no_pin else pin_one_core()
    import torch

    torch.set_num_threads(1)
    import gymnasium as gym

    import dynnav_tasks
    from dynnav_tasks.generation import DIFFICULTIES, generate_world, spec_for

    print(describe(pinned) + ", torch threads 1")
    print(f"{args.worlds} new worlds per generation/reset figure, {args.steps} random steps per step rate\n")

    def make(task_id, **kwargs):
        return dynnav_tasks.NumpyWrapper(gym.make(task_id, **kwargs))

    print(f"{'world':<34} {'generation ms':>34}   {'reset ms (generation + reset)':>34}   moving  blocks")
    steppers = []
    for difficulty in DIFFICULTIES:
        for split in ("train", "ood"):
            env = make("DynNav-Procedural-v1", difficulty=difficulty, split=split)
            spec, gen, reset, moving, blocks = env.unwrapped.world_spec, [], [], [], []
            for s in range(args.worlds):
                t0 = time.perf_counter()
                generate_world(spec, 10_000 + s)
                gen.append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                env.reset(seed=s)  # a new world every time (a new seed draws a new world seed)
                reset.append(time.perf_counter() - t0)
                world = env.unwrapped.world
                moving.append(world.moving_obstacle_count)
                blocks.append(sum(1 for o in world.obstacles if not o.moving))
            name = f"Procedural {difficulty} {split}"
            print(f"{name:<34} {milliseconds(gen):>34}   {milliseconds(reset):>34}   "
                  f"{statistics.mean(moving):6.1f}  {statistics.mean(blocks):6.1f}")
            steppers.append(Stepper(f"{name} (mean {statistics.mean(moving):.1f} moving)", env))

    fixed_ids = ("DynNav-MovingObstacles-v1", "DynNav-MotionAreas-v1")
    for task_id in fixed_ids:  # the same world every episode: nothing to generate or move
        env, reset = make(task_id), []
        for s in range(args.worlds):
            t0 = time.perf_counter()
            env.reset(seed=s)
            reset.append(time.perf_counter() - t0)
        world = env.unwrapped.world
        print(f"{task_id + ' (fixed)':<34} {'-':>34}   {milliseconds(reset):>34}   "
              f"{world.moving_obstacle_count:6.1f}  {sum(1 for o in world.obstacles if not o.moving):6.1f}")
        env.close()

    # equal obstacle count: 2 moving obstacles in an arena of about the fixed worlds' 6.5 m
    equal = {}
    for layout in ("open", "clutter"):
        spec = replace(spec_for("easy", "train"), arena_size=(6.0, 7.0), layout=(layout,), moving_obstacles=(2, 2),
                       relative_speed=(0.3, 1.0))
        worlds = iter(generate_world(spec, 50_000 + s) for s in range(10**9))
        env = make("DynNav-Procedural-v1", difficulty="easy")
        equal[layout] = Stepper(f"Procedural, 2 moving, 6-7 m, {layout}", env,
                                lambda w=worlds: {"options": {"world": next(w)}})
        steppers.append(equal[layout])
    fixed = [Stepper(f"{t} (fixed, 2 moving)", make(t)) for t in fixed_ids]
    steppers += fixed
    for s in steppers:  # warm up
        s.run(100)
        s.step_time, s.steps = 0.0, 0
    for _ in range(0, args.steps, CHUNK):
        for s in steppers:
            s.run(CHUNK)

    print(f"\n{'world':<52} {'steps/s':>8}")
    for s in steppers:
        print(f"{s.name:<52} {s.rate:>8.0f}")
    base = statistics.mean(f.rate for f in fixed)
    print(f"\nat an equal obstacle count (2 moving), against the fixed worlds' mean ({base:.0f} steps/s):")
    for layout, s in equal.items():
        print(f"  generated, {layout:<8} {s.rate:6.0f} steps/s = {100 * s.rate / base:5.1f}%")
    for s in steppers:
        s.env.close()


if __name__ == "__main__":
    main()
