"""Stable-Baselines3's SAC or PPO on a dynnav task with the continuous drive, then a test.

    python examples/sb3_continuous_drive.py                      # SAC on world 5.2, 100k steps
    python examples/sb3_continuous_drive.py --algo ppo --steps 300000
    python examples/sb3_continuous_drive.py --task DynNav-MovingObstacles-v1 --seed 2

The task is made by ``gym.make`` with ``control_mode="diff_drive_vel"`` (a ``Box(2)`` action:
linear and angular velocity, docs/drive.md) and wrapped in ``dynnav_tasks.NumpyWrapper``; that is
all the glue SB3 needs. The reward is the task's default (``distance_orientation_always``) with a
collision costing -50 instead of -20, and the discount is the study's 0.97, as in ``make demo``:
with the default -20 and SB3's gamma 0.99 a crash soon after the start costs less than the
distance penalties of a long search, and both algorithms learn to crash (0% success in our
runs). Everything else is SB3's defaults.

After training, the deterministic policy runs ``--test-episodes`` episodes with the seeds
100000, 100001, ... (never used in training: SB3 resets with the training seed once, then the
task draws its own) and the script prints the share of successes, collisions and timeouts.
Requires the ``bench`` extra (``pip install -e ".[bench]"``; ``make setup`` installs it).
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

import gymnasium as gym
import torch

import dynnav_tasks
from dynnav_tasks.outcomes import outcome_of

ALGORITHMS = ("sac", "ppo")
TEST_SEED = 100_000
"""the first test episode's reset seed"""
TASK_OPTIONS = dict(control_mode="diff_drive_vel", reward_params={"collision_reward": -50.0})
"""the continuous drive, and a collision costing -50 (see the module's docstring)"""
GAMMA = 0.97


def make_env(task: str) -> gym.Env:
    """The task with the continuous drive, in the plain gymnasium API."""
    return dynnav_tasks.NumpyWrapper(gym.make(task, **TASK_OPTIONS))


def make_training_env(task: str, envs: int):
    """``envs`` copies of the task for SB3 to collect from, stepped in turn in this process (one
    is the task itself)."""
    if envs == 1:
        return make_env(task)
    from stable_baselines3.common.env_util import make_vec_env

    return make_vec_env(lambda: make_env(task), n_envs=envs)


def make_model(algo: str, env, seed: int, **overrides):
    """An SB3 SAC or PPO with its defaults, the study's discount and ``overrides``."""
    from stable_baselines3 import PPO, SAC

    if algo not in ALGORITHMS:
        raise ValueError(f"unknown algorithm {algo!r}; choose one of {', '.join(ALGORITHMS)}")
    model_class = SAC if algo == "sac" else PPO
    return model_class("MlpPolicy", env, gamma=GAMMA, seed=seed, device="cpu", verbose=0, **overrides)


def test(model, env: gym.Env, episodes: int) -> Counter:
    """Run the deterministic policy for ``episodes`` episodes; count their outcomes."""
    outcomes = Counter()
    for i in range(episodes):
        obs, _ = env.reset(seed=TEST_SEED + i)
        while True:
            action, _ = model.predict(obs, deterministic=True)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                outcomes[outcome_of(info, terminated)] += 1
                break
    return outcomes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--algo", choices=ALGORITHMS, default="sac")
    parser.add_argument("--task", default="DynNav-MovingTarget-v1", help="a dynnav task id (world 5.2 by default)")
    parser.add_argument("--steps", type=int, default=100_000, help="training steps (environment steps)")
    parser.add_argument("--envs", type=int, default=1, help="copies of the task to collect from (PPO: e.g. 8)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--test-episodes", type=int, default=100)
    args = parser.parse_args()
    if min(args.steps, args.test_episodes, args.envs) < 1:
        parser.error("--steps, --test-episodes and --envs must be at least 1")

    torch.set_num_threads(1)
    model = make_model(args.algo, make_training_env(args.task, args.envs), args.seed)
    start = time.perf_counter()
    model.learn(total_timesteps=args.steps, progress_bar=True)
    seconds = time.perf_counter() - start
    print(f"{args.algo.upper()} on {args.task} (diff_drive_vel), seed {args.seed}: "
          f"{args.steps} steps in {seconds:.0f} s ({args.steps / seconds:.0f} steps/s)")
    env = make_env(args.task)
    outcomes = test(model, env, args.test_episodes)
    n = args.test_episodes
    print(f"test, {n} episodes: success {outcomes['success'] / n:.0%}, "
          f"collision {outcomes['collision'] / n:.0%}, timeout {outcomes['timeout'] / n:.0%}")
    env.close()


if __name__ == "__main__":
    main()
