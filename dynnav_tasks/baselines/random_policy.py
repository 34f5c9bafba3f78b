"""Roll out a random policy on a dynnav task and print each episode's outcome.

    python -m dynnav_tasks.baselines.random_policy --task DynNav-MovingObstacles-v1 --episodes 5 --seed 0

With ``--control-mode diff_drive_vel`` the actions are (v, w) drawn uniformly from the box.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import gymnasium as gym
import numpy as np
import tyro


@dataclass
class Args:
    task: str = "DynNav-MovingTarget-v1"
    """registered task id (see dynnav_tasks.TASK_IDS)"""
    episodes: int = 10
    """number of episodes to roll out"""
    seed: int = 0
    """seed of the first episode; episode i uses seed + i"""
    reward_mode: str = "distance_orientation_always"
    """one of dynnav_tasks.rewards.SUPPORTED_REWARD_MODES"""
    control_mode: str = "discrete_drive"
    """the robot's drive: "discrete_drive" (three actions) or "diff_drive_vel" (velocities)"""


def main(args: Args) -> None:
    """Roll out ``args.episodes`` random episodes and print a line per episode and a summary."""
    import dynnav_tasks

    try:
        env = dynnav_tasks.NumpyWrapper(
            dynnav_tasks.make(args.task, reward_mode=args.reward_mode, control_mode=args.control_mode))
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    rng = np.random.default_rng(args.seed)
    space = env.action_space
    if isinstance(space, gym.spaces.Discrete):
        def draw():
            return int(rng.integers(space.n))
    else:
        def draw():
            return rng.uniform(space.low, space.high).astype(np.float32)
    print(f"{args.task}: random policy, {args.episodes} episodes, reward_mode={args.reward_mode}, "
          f"control_mode={args.control_mode}")
    print(f"{'episode':>7} {'seed':>6} {'outcome':>9} {'steps':>5} {'return':>8} {'path m':>7} {'to target m':>11}")
    counts, steps_total, t0 = {}, 0, time.perf_counter()
    for ep in range(args.episodes):
        env.reset(seed=args.seed + ep)
        ret, steps, done = 0.0, 0, False
        while not done:
            _, reward, terminated, truncated, info = env.step(draw())
            ret += float(reward)
            steps += 1
            done = bool(terminated or truncated)
        result = dynnav_tasks.outcome_of(info, terminated)
        counts[result] = counts.get(result, 0) + 1
        steps_total += steps
        print(f"{ep:>7} {args.seed + ep:>6} {result:>9} {steps:>5} {ret:>8.2f} "
              f"{float(info['path_length']):>7.2f} {float(info['distance_to_target']):>11.2f}")
    elapsed = time.perf_counter() - t0
    summary = ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
    print(f"outcomes: {summary}; {steps_total} steps in {elapsed:.2f} s ({steps_total / elapsed:.0f} steps/s)")
    env.close()


if __name__ == "__main__":
    main(tyro.cli(Args))
