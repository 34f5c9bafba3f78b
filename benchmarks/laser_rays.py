"""Laser ring cost: the time of a reading and of a whole step with 16 (the study's), 90 and
360 rays, measured in the same run on the same core, beside the 16-ray baseline.

    python benchmarks/laser_rays.py [--steps 3000] [--reads 3000] [--no-pin]

Printed per ray count (full circle, 5 m range, ``DynNav-MovingObstacles-v1``):

* read us: one ``LaserRing.read`` at a new pose and heading (the directions recomputed, as
  after a turn), in the task's own PhysX scene, alone; per ray: that over the ray count;
* step us: one ``env.step`` under a random policy through ``gym.make`` + ``NumpyWrapper``
  (resets not counted), and steps/s; x 16 rays: the step time over the 16-ray one;
* extra us per ray: (step time - the 16-ray step time) / (rays - 16): what each ray beyond
  the study's 16 adds to a step.

A last row gives 16 rays with every noise option on (``noise.py``: laser noise and dropout,
odometry drift, action noise, speed scales), the cost of the noise itself. The envs step in
turns, ``CHUNK`` steps at a time, so that a load from other processes weighs on all alike.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numpy as np

from machine import describe, pin_one_core, timed_steps

CHUNK = 250
"""steps of one env measured at a time, in turns with the others"""
TASK = "DynNav-MovingObstacles-v1"
RAY_COUNTS = (16, 90, 360)
NOISE = dict(laser_noise_std=0.02, laser_dropout=0.01, odometry_drift_std=0.005, action_noise=0.05,
             robot_speed_scale_min=0.9, robot_speed_scale_max=1.1, obstacle_speed_scale_min=0.8,
             obstacle_speed_scale_max=1.2)


class Stepper:
    """One env under a random policy; ``run(n)`` steps it n times, resets not counted."""

    def __init__(self, env):
        self.env = env
        env.reset(seed=0)
        space = env.action_space
        space.seed(0)
        self.actions = iter(lambda: int(space.sample()), None)
        self.times: list[float] = []  # seconds per step, one figure per chunk

    def run(self, n: int) -> None:
        spent = timed_steps(self.env, (next(self.actions) for _ in range(n)), self.env.reset)
        self.times.append(spent / n)


def read_time(env, rays: int, reads: int) -> float:
    """Seconds per ``LaserRing.read`` of ``rays`` rays at random poses in the env's scene."""
    from dynnav_tasks.lasers import LaserConfig, LaserRing
    from dynnav_tasks.robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT

    ring = LaserRing(env.unwrapped.scene.px, FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT,
                     LaserConfig.of(rays))
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(-1.5, 4.0, reads), rng.uniform(-1.5, 4.0, reads),
                             rng.uniform(-math.pi, math.pi, reads)]).tolist()
    for x, y, yaw in poses[:100]:  # warm up
        ring.read(x, y, yaw)
    t0 = time.perf_counter()
    for x, y, yaw in poses:
        ring.read(x, y, yaw)
    return (time.perf_counter() - t0) / reads


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=3000, help="steps per env")
    parser.add_argument("--reads", type=int, default=3000, help="laser reads per ray count")
    parser.add_argument("--no-pin", action="store_true", help="do not pin the process to one core")
    args = parser.parse_args()
    pinned = "not pinned" if args.no_pin else pin_one_core()
    os.environ.setdefault("MS_RENDERER_LOG_LEVEL", "error")
    import gymnasium as gym
    import sapien
    import torch

    import dynnav_tasks

    torch.set_num_threads(1)
    print(describe(pinned))
    print(f"sapien {sapien.__version__}; {TASK}, state observations, {args.steps} steps per env under a random "
          f"policy (resets not counted), {args.reads} reads per ray count\n")

    envs = {rays: dynnav_tasks.NumpyWrapper(gym.make(TASK, laser_rays=rays)) for rays in RAY_COUNTS}
    envs["16 + noise"] = dynnav_tasks.NumpyWrapper(gym.make(TASK, **NOISE))
    reads = {rays: read_time(envs[rays], rays, args.reads) for rays in RAY_COUNTS}
    steppers = {name: Stepper(env) for name, env in envs.items()}
    for stepper in steppers.values():
        stepper.run(100)  # warm up
        stepper.times.clear()
    for _ in range(max(args.steps // CHUNK, 1)):
        for stepper in steppers.values():
            stepper.run(CHUNK)
    step = {name: statistics.median(s.times) for name, s in steppers.items()}
    base = step[16]

    header = f"{'rays':>11}  {'read us':>8}  {'us/ray':>7}  {'step us':>8}  {'steps/s':>8}  {'x 16 rays':>9}  {'extra us/ray':>12}"
    print(header)
    for name, t in step.items():
        read = reads.get(name)
        read_cols = f"{1e6 * read:>8.1f}  {1e6 * read / name:>7.2f}" if read is not None else f"{'':>8}  {'':>7}"
        extra = f"{1e6 * (t - base) / (name - 16):>12.2f}" if isinstance(name, int) and name > 16 else f"{'':>12}"
        print(f"{name!s:>11}  {read_cols}  {1e6 * t:>8.1f}  {1 / t:>8.0f}  {t / base:>9.2f}  {extra}")
    print("\nstep us: the median over chunks of the mean step time; the 16-ray row is the study's ring (the "
          "baseline)")
    for env in envs.values():
        env.close()


if __name__ == "__main__":
    main()
