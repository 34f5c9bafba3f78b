"""Crowd throughput: steps/s of DynNav-Crowd-v1 under its baselines and a random policy, beside
the box world 5.3 (DynNav-MovingObstacles-v1) in the same run, on one core.

    python benchmarks/crowd.py [--steps 3000]

Rows: a random policy in 5.3 (the box worlds' floor under any controller), a random policy in
the crowd task with 5, 10 and 20 pedestrians moved by ORCA and by the social force (what the
pedestrians cost), and the crowd task's baselines on 5 ORCA pedestrians: the ORCA robot, the
social-force robot (both on the continuous drive) and DWA on the laser scan. Every figure counts
resets, through ``dynnav_tasks.NumpyWrapper``; a controller's rows include its own decisions.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from machine import describe, pin_one_core


def rate(task_id: str, steps: int, controller=None, **task_kwargs) -> float:
    """Steps per second of ``steps`` steps of ``task_id`` under ``controller`` (a random policy if None)."""
    import dynnav_tasks

    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task_id, **task_kwargs))
    base, rng = env.unwrapped, np.random.default_rng(0)
    try:
        env.reset(seed=0)
        if controller is not None:
            controller.start(base)
        t0, episode = time.perf_counter(), 0
        for _ in range(steps):
            action = controller.act(base) if controller is not None else env.action_space.sample()
            _, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                episode += 1
                env.reset(seed=episode)
                if controller is not None:
                    controller.start(base)
        return steps / (time.perf_counter() - t0)
    finally:
        env.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=3000)
    args = parser.parse_args()
    from agents.training.threads import limit_threads
    from dynnav_tasks.baselines.crowd_robot import CrowdRobot
    from dynnav_tasks.baselines.dwa import DWA

    limit_threads(1)
    print(describe(pin_one_core()))
    n = args.steps
    print(f"{'task / controller':<62} {'steps/s':>8}")
    print(f"{'DynNav-MovingObstacles-v1, random policy':<62} {rate('DynNav-MovingObstacles-v1', n):8.0f}")
    for model in ("orca", "social_force"):
        for humans in (5, 10, 20):
            label = f"DynNav-Crowd-v1, {humans} {model} pedestrians, random policy"
            print(f"{label:<62} {rate('DynNav-Crowd-v1', n, humans=humans, model=model):8.0f}")
    for label, controller in (("ORCA robot", CrowdRobot("orca")), ("social-force robot", CrowdRobot("social_force")),
                              ("DWA on the laser scan", DWA())):
        text = f"DynNav-Crowd-v1, 5 orca pedestrians, {label}"
        print(f"{text:<62} {rate('DynNav-Crowd-v1', n, controller, control_mode='diff_drive_vel'):8.0f}")


if __name__ == "__main__":
    main()
