"""Environment throughput: steps/s of every dynnav task under a random policy, beside two
baselines measured in the same run on the same core:

* ManiSkill's own ``PushCube-v1`` (obs_mode="state", CPU simulation), and
* a raw SAPIEN loop: one PhysX step, 16 ray casts and 2 kinematic obstacle pose updates per
  iteration, with no ManiSkill and no gymnasium (the floor under any task's step).

The camera worlds are measured a second time with ``obs_mode="rgb"`` (a 32x32 frame rendered
every step), and once rendering 640x640 and averaging down to 32x32 as the thesis did.

    python benchmarks/env_throughput.py [--steps 5000] [--no-pin] [--no-camera] [--cpu-time]

Every figure is steps per second (wall-clock unless ``--cpu-time``), resets included, through
the wrappers a user gets: ``gym.make`` + ``dynnav_tasks.NumpyWrapper`` (the plain gymnasium
API), and for the laser tasks also ``gym.make`` + ManiSkill's ``CPUGymWrapper``. Each row's
"% raw SAPIEN" divides its steps/s by those of the raw loop run in turns with it (250 raw
iterations before every 250 steps), so that a load from other processes on the same core
weighs on both alike; the raw row gives the median of those raw figures. The last line gives
the slowest task with lasers (state observations) as a share of the raw SAPIEN loop.

The process is pinned to one CPU core and to one torch thread unless ``--no-pin``;
``--no-camera`` leaves out the rows that render camera frames (the slow part of a run).
The run also says what share of its core the process had (CPU time / wall time): well under
100% means other processes ran on the same core; ``--cpu-time`` counts the process's CPU time
instead of wall-clock time, which such a load changes much less.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import time

import numpy as np

from machine import cpu_name, pin_one_core

clock = time.perf_counter
"""what the figures count: wall-clock time, or the process's CPU time with ``--cpu-time``"""
CHUNK = 250
"""steps of a task measured at a time, in turns with as many iterations of the raw loop"""


class RawLoop:
    """The raw SAPIEN loop: PhysX step + 16 rays + 2 kinematic obstacle updates per iteration,
    in a physics-only SAPIEN scene."""

    def __init__(self):
        import sapien

        self.sapien = sapien
        self.px = px = sapien.physx.PhysxCpuSystem()
        px.timestep = 0.05
        self.scene = scene = sapien.Scene([px])
        for cx, cy, hx, hy in [(1.25, 4.55, 3.35, 0.05), (1.25, -2.05, 3.35, 0.05), (4.55, 1.25, 0.05, 3.35), (-2.05, 1.25, 0.05, 3.35)]:
            b = scene.create_actor_builder()
            b.add_box_collision(half_size=[hx, hy, 0.25])
            b.set_physx_body_type("static")
            b.build().set_pose(sapien.Pose([cx, cy, 0.25]))
        self.obstacles = []
        for i in range(2):
            b = scene.create_actor_builder()
            b.add_box_collision(half_size=[0.25, 0.25, 0.25])
            b.set_physx_body_type("kinematic")
            e = b.build()
            e.set_pose(sapien.Pose([1.0, 1.0 + 2 * i, 0.25]))
            self.obstacles.append(e.find_component_by_type(sapien.physx.PhysxRigidDynamicComponent))
        b = scene.create_actor_builder()
        b.add_box_collision(half_size=[0.225, 0.19, 0.1])
        b.set_physx_body_type("dynamic")
        robot = b.build()
        robot.set_pose(sapien.Pose([-1.0, -1.0, 0.16]))
        angles = 2 * math.pi * np.arange(16) / 16
        self.dirs = np.stack([np.cos(angles), np.sin(angles), np.zeros(16)], axis=1).astype(np.float32)
        self.origins = np.array([-1.0, -1.0, 0.3], dtype=np.float32) + 0.3 * self.dirs
        self.k = 0

    def run(self, steps: int) -> float:
        """Run ``steps`` iterations; the time they took (``clock``)."""
        Pose, px, obstacles = self.sapien.Pose, self.px, self.obstacles
        t0 = clock()
        for k in range(self.k, self.k + steps):
            y = 1.0 + 0.5 * math.sin(0.05 * k)
            for i, body in enumerate(obstacles):
                body.set_kinematic_target(Pose([1.0, y + 2 * i, 0.25]))
            px.step()
            for o, d in zip(self.origins, self.dirs):
                px.raycast(o, d, 4.7)
        self.k += steps
        return clock() - t0


def raw_sapien_steps_per_second(steps: int) -> float:
    """Steps/s of a fresh ``RawLoop``."""
    return steps / RawLoop().run(steps)


def gym_steps_per_second(task_id: str, steps: int, wrapper=None, raw: RawLoop | None = None, **kwargs):
    """Steps/s of ``task_id`` under a random policy (resets included). With ``raw``: also the
    steps/s of the raw loop run in turns with the task (``CHUNK`` iterations of it before each
    ``CHUNK`` steps), so that both meet the same load of the core; returns (task, raw)."""
    import gymnasium as gym
    from mani_skill.utils.wrappers.gymnasium import CPUGymWrapper

    env = (wrapper or CPUGymWrapper)(gym.make(task_id, **kwargs))
    env.reset(seed=0)
    space = env.action_space
    space.seed(0)
    actions = [space.sample() for _ in range(steps)]
    for a in actions[:100]:  # warm up
        _, _, terminated, truncated, _ = env.step(a)
        if terminated or truncated:
            env.reset()
    env.reset(seed=1)
    task_time = raw_time = 0.0
    for start in range(0, steps, CHUNK):
        chunk = actions[start:start + CHUNK]
        if raw is not None:
            raw_time += raw.run(len(chunk))
        t0 = clock()
        for a in chunk:
            _, _, terminated, truncated, _ = env.step(a)
            if terminated or truncated:
                env.reset()
        task_time += clock() - t0
    env.close()
    return (steps / task_time, steps / raw_time) if raw is not None else steps / task_time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=5000, help="steps per measurement (default 5000)")
    parser.add_argument("--no-pin", action="store_true", help="do not pin the process to one core")
    parser.add_argument("--no-camera", action="store_true", help="leave out the rows that render camera frames")
    parser.add_argument("--cpu-time", action="store_true", help="count the process's CPU time, not wall-clock time")
    args = parser.parse_args()
    global clock
    clock = time.process_time if args.cpu_time else time.perf_counter

    pinned = "not pinned" if args.no_pin else pin_one_core()
    import torch

    torch.set_num_threads(1)
    import mani_skill
    import sapien

    import dynnav_tasks

    print(f"machine: {cpu_name()}, {os.cpu_count()} cores ({pinned}), torch threads 1")
    print(f"python {platform.python_version()}, sapien {sapien.__version__}, mani_skill {mani_skill.__version__}, torch {torch.__version__}")
    counted = "CPU" if args.cpu_time else "wall-clock"
    print(f"{args.steps} steps per figure, random actions, resets included, {counted} time\n")

    from mani_skill.utils.wrappers.gymnasium import CPUGymWrapper

    numpy_wrapper = dynnav_tasks.NumpyWrapper
    raw = RawLoop()
    raw.run(200)  # warm up
    wall0, cpu0 = time.perf_counter(), time.process_time()
    rows = []  # (name, steps/s, steps/s of the raw loop in turns with it)

    def measure(name, task_id, steps=args.steps, wrapper=numpy_wrapper, **kwargs):
        rows.append((name, *gym_steps_per_second(task_id, steps, wrapper, raw=raw, **kwargs)))
        return rows[-1][1] / rows[-1][2]

    measure("ManiSkill PushCube-v1 (state, CPU)", "PushCube-v1", wrapper=None, obs_mode="state", render_backend="cpu")
    laser = {}  # task id -> its share of the raw loop
    for task_id in dynnav_tasks.TASK_IDS:
        laser[task_id] = measure(f"{task_id} (state, NumpyWrapper)", task_id)
    for task_id in dynnav_tasks.TASK_IDS:
        measure(f"{task_id} (state, CPUGymWrapper)", task_id, wrapper=None)
    for task_id in dynnav_tasks.VISUAL_TASK_IDS if not args.no_camera else ():
        measure(f"{task_id} (rgb 32x32)", task_id, obs_mode="rgb")
    if not args.no_camera:
        task_id = dynnav_tasks.VISUAL_TASK_IDS[-1]
        measure(f"{task_id} (rgb 640->32)", task_id, max(args.steps // 20, 100), obs_mode="rgb", camera_render_size=640)

    raws = [r for _, _, r in rows]
    raw_rate = statistics.median(raws)
    rows.insert(0, ("raw SAPIEN loop (PhysX step + 16 rays + 2 kinematic updates)", raw_rate, raw_rate))
    push = rows[1][1]
    width = max(len(name) for name, _, _ in rows)
    print(f"{'environment':<{width}}  {'steps/s':>9}  {'x PushCube':>10}  {'% raw SAPIEN':>12}")
    for name, rate, beside in rows:
        print(f"{name:<{width}}  {rate:>9.0f}  {rate / push:>10.1f}  {100 * rate / beside:>11.1f}%")
    share = (time.process_time() - cpu0) / (time.perf_counter() - wall0)
    slowest = min(laser, key=laser.get)
    print(f"\n% raw SAPIEN: the row's steps/s over those of the raw loop run in turns with it ({CHUNK} iterations "
          f"before every {CHUNK} steps); the raw row gives their median ({min(raws):.0f} to {max(raws):.0f})")
    print(f"this process had {100 * share:.0f}% of its core over the run (CPU time / wall time)")
    rate = next(r for name, r, _ in rows if name == f"{slowest} (state, NumpyWrapper)")
    print(f"slowest laser task: {slowest} at {rate:.0f} steps/s = {100 * laser[slowest]:.1f}% of the raw SAPIEN loop "
          f"run in turns with it")


if __name__ == "__main__":
    main()
