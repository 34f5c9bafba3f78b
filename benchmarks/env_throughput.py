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
API), and for the laser tasks also ``gym.make`` + ManiSkill's ``CPUGymWrapper``. The last
lines give the slowest task with lasers (state observations) as a share of the raw SAPIEN
loop of the same run, measured first and last (the faster of the two counts).

The process is pinned to one CPU core and to one torch thread unless ``--no-pin``;
``--no-camera`` leaves out the rows that render camera frames (the slow part of a run).
The last lines also say what share of its core the process had (CPU time / wall time): well
under 100% means other processes ran on the same core, and the figures (and their shares,
measured at different moments) then depend on them; ``--cpu-time`` counts the process's CPU
time instead of wall-clock time, which other processes change much less.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time

import numpy as np

from machine import cpu_name, pin_one_core

clock = time.perf_counter
"""what the figures count: wall-clock time, or the process's CPU time with ``--cpu-time``"""


def gym_steps_per_second(task_id: str, steps: int, wrapper=None, **kwargs) -> float:
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
    t0 = clock()
    for a in actions:
        _, _, terminated, truncated, _ = env.step(a)
        if terminated or truncated:
            env.reset()
    rate = steps / (clock() - t0)
    env.close()
    return rate


def raw_sapien_steps_per_second(steps: int) -> float:
    """PhysX step + 16 rays + 2 kinematic obstacle updates, in a physics-only SAPIEN scene."""
    import sapien

    px = sapien.physx.PhysxCpuSystem()
    px.timestep = 0.05
    scene = sapien.Scene([px])
    for cx, cy, hx, hy in [(1.25, 4.55, 3.35, 0.05), (1.25, -2.05, 3.35, 0.05), (4.55, 1.25, 0.05, 3.35), (-2.05, 1.25, 0.05, 3.35)]:
        b = scene.create_actor_builder()
        b.add_box_collision(half_size=[hx, hy, 0.25])
        b.set_physx_body_type("static")
        b.build().set_pose(sapien.Pose([cx, cy, 0.25]))
    obstacles = []
    for i in range(2):
        b = scene.create_actor_builder()
        b.add_box_collision(half_size=[0.25, 0.25, 0.25])
        b.set_physx_body_type("kinematic")
        e = b.build()
        e.set_pose(sapien.Pose([1.0, 1.0 + 2 * i, 0.25]))
        obstacles.append(e.find_component_by_type(sapien.physx.PhysxRigidDynamicComponent))
    b = scene.create_actor_builder()
    b.add_box_collision(half_size=[0.225, 0.19, 0.1])
    b.set_physx_body_type("dynamic")
    robot = b.build()
    robot.set_pose(sapien.Pose([-1.0, -1.0, 0.16]))
    angles = 2 * math.pi * np.arange(16) / 16
    dirs = np.stack([np.cos(angles), np.sin(angles), np.zeros(16)], axis=1).astype(np.float32)
    origins = np.array([-1.0, -1.0, 0.3], dtype=np.float32) + 0.3 * dirs
    t0 = clock()
    for k in range(steps):
        y = 1.0 + 0.5 * math.sin(0.05 * k)
        for i, body in enumerate(obstacles):
            body.set_kinematic_target(sapien.Pose([1.0, y + 2 * i, 0.25]))
        px.step()
        for o, d in zip(origins, dirs):
            px.raycast(o, d, 4.7)
    return steps / (clock() - t0)


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
    print(f"{args.steps} steps per figure, random actions, resets included, {'CPU' if args.cpu_time else 'wall-clock'} time\n")

    from mani_skill.utils.wrappers.gymnasium import CPUGymWrapper

    numpy_wrapper = dynnav_tasks.NumpyWrapper
    wall0, cpu0 = time.perf_counter(), time.process_time()
    raw_first = raw_sapien_steps_per_second(args.steps)
    rows = [("raw SAPIEN loop (PhysX step + 16 rays + 2 kinematic updates)", raw_first)]
    rows.append(("ManiSkill PushCube-v1 (state, CPU)", gym_steps_per_second("PushCube-v1", args.steps, obs_mode="state", render_backend="cpu")))
    laser = {}
    for task_id in dynnav_tasks.TASK_IDS:
        laser[task_id] = gym_steps_per_second(task_id, args.steps, numpy_wrapper)
        rows.append((f"{task_id} (state, NumpyWrapper)", laser[task_id]))
    for task_id in dynnav_tasks.TASK_IDS:
        rows.append((f"{task_id} (state, CPUGymWrapper)", gym_steps_per_second(task_id, args.steps, CPUGymWrapper)))
    for task_id in dynnav_tasks.VISUAL_TASK_IDS if not args.no_camera else ():
        rows.append((f"{task_id} (rgb 32x32)", gym_steps_per_second(task_id, args.steps, numpy_wrapper, obs_mode="rgb")))
    if not args.no_camera:
        task_id = dynnav_tasks.VISUAL_TASK_IDS[-1]
        rows.append((f"{task_id} (rgb 640->32)", gym_steps_per_second(task_id, max(args.steps // 20, 100), numpy_wrapper, obs_mode="rgb", camera_render_size=640)))

    raw_last = raw_sapien_steps_per_second(args.steps)
    raw = max(raw_first, raw_last)  # the faster of the two: the shares are not flattered by a slow moment
    rows[0] = (rows[0][0], raw)
    push = rows[1][1]
    width = max(len(name) for name, _ in rows)
    print(f"{'environment':<{width}}  {'steps/s':>9}  {'x PushCube':>10}  {'% raw SAPIEN':>12}")
    for name, rate in rows:
        print(f"{name:<{width}}  {rate:>9.0f}  {rate / push:>10.1f}  {100 * rate / raw:>11.1f}%")
    slowest = min(laser, key=laser.get)
    share = (time.process_time() - cpu0) / (time.perf_counter() - wall0)
    print(f"\nraw SAPIEN loop: {raw_first:.0f} steps/s first, {raw_last:.0f} steps/s last; the table uses the faster")
    print(f"this process had {100 * share:.0f}% of its core over the run (CPU time / wall time)")
    print(f"slowest laser task: {slowest} at {laser[slowest]:.0f} steps/s = "
          f"{100 * laser[slowest] / raw:.1f}% of the raw SAPIEN loop ({raw:.0f} steps/s) of this run")


if __name__ == "__main__":
    main()
