"""Stable-Baselines3's SAC or PPO on a dynnav task with the continuous drive, then a test.

    python examples/sb3_continuous_drive.py                           # SAC on world 5.2, the recipe
    python examples/sb3_continuous_drive.py --algo ppo --envs 8 --steps 1000000
    python examples/sb3_continuous_drive.py --reward study            # the study's reward (learns to stall)
    python examples/sb3_continuous_drive.py --algo ppo --save ppo-5.2 # then: dynnav-benchmark --policy ppo-5.2.zip ...

The task is made by ``gym.make`` with ``control_mode="diff_drive_vel"`` (a ``Box(2)`` action:
linear and angular velocity, docs/drive.md) and wrapped in ``dynnav_tasks.NumpyWrapper``; that is
all the glue SB3 needs. The recipe (docs/sb3.md) changes the reward, not the algorithm:

* ``--reward progress`` (the default): ``reward_mode="progress"``, the metres gained on the
  target each step (potential-based shaping, so a crash never pays more than arriving), +20 on
  arriving and -20 on a collision. ``--reward study``: the task's default reward
  (``distance_orientation_always``) with a collision costing -50, under which every step costs
  and SB3's learners settle for stalling or crashing;
* rewards normalised by ``VecNormalize`` (``norm_obs=False``, so the saved model reads the task's
  own observations and scores in ``dynnav-benchmark`` as it is); ``--no-normalize`` turns it off;
* the discount 0.99 (``--gamma``), SB3's own.

After training, the deterministic policy runs ``--test-episodes`` episodes with the seeds
1000000, 1000001, ... (the benchmark's: never used in training, where SB3 resets with the training
seed once and the task draws its own) and the script prints the share of successes, collisions and
timeouts. Requires the ``bench`` extra (``pip install -e ".[bench]"``; ``make setup`` installs it).
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
TEST_SEED = 1_000_000
"""the first test episode's reset seed (dynnav-benchmark's)"""
REWARDS = {
    "progress": dict(reward_mode="progress"),
    "study": dict(reward_params={"collision_reward": -50.0}),
}
"""the task options of each --reward (see the module's docstring)"""
GAMMA = 0.99


def make_env(task: str, reward: str = "progress") -> gym.Env:
    """The task with the continuous drive and ``reward``'s options, in the plain gymnasium API."""
    if reward not in REWARDS:
        raise ValueError(f"unknown reward {reward!r}; choose one of {', '.join(REWARDS)}")
    return dynnav_tasks.NumpyWrapper(gym.make(task, control_mode="diff_drive_vel", **REWARDS[reward]))


def make_training_env(task: str, envs: int, reward: str = "progress", normalize: bool = False, gamma: float = GAMMA):
    """``envs`` copies of the task for SB3 to collect from, stepped in turn in this process, their
    rewards normalised by ``VecNormalize`` when ``normalize`` (one plain copy without it)."""
    if envs == 1 and not normalize:
        return make_env(task, reward)
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import VecNormalize

    vec = make_vec_env(lambda: make_env(task, reward), n_envs=envs)
    return VecNormalize(vec, norm_obs=False, norm_reward=True, gamma=gamma) if normalize else vec


def make_model(algo: str, env, seed: int, **overrides):
    """An SB3 SAC or PPO with its defaults and ``overrides`` (the discount ``GAMMA`` unless given)."""
    from stable_baselines3 import PPO, SAC

    if algo not in ALGORITHMS:
        raise ValueError(f"unknown algorithm {algo!r}; choose one of {', '.join(ALGORITHMS)}")
    model_class = SAC if algo == "sac" else PPO
    overrides.setdefault("gamma", GAMMA)
    return model_class("MlpPolicy", env, seed=seed, device="cpu", verbose=0, **overrides)


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
    parser.add_argument("--reward", choices=tuple(REWARDS), default="progress", help="the task's reward (see above)")
    parser.add_argument("--normalize", action=argparse.BooleanOptionalAction, default=True,
                        help="normalise the rewards with VecNormalize")
    parser.add_argument("--gamma", type=float, default=GAMMA, help="the discount")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--test-episodes", type=int, default=100)
    parser.add_argument("--save", default=None, help="also save the model to this path (SB3 adds .zip)")
    args = parser.parse_args()
    if min(args.steps, args.test_episodes, args.envs) < 1:
        parser.error("--steps, --test-episodes and --envs must be at least 1")
    if not 0 < args.gamma <= 1:
        parser.error(f"--gamma must be in (0, 1]; got {args.gamma}")

    torch.set_num_threads(1)
    train_env = make_training_env(args.task, args.envs, args.reward, args.normalize, args.gamma)
    model = make_model(args.algo, train_env, args.seed, gamma=args.gamma)
    start = time.perf_counter()
    model.learn(total_timesteps=args.steps, progress_bar=True)
    seconds = time.perf_counter() - start
    print(f"{args.algo.upper()} on {args.task} (diff_drive_vel, reward {args.reward}, normalize {args.normalize}, "
          f"gamma {args.gamma}, {args.envs} env(s)), seed {args.seed}: "
          f"{args.steps} steps in {seconds:.0f} s ({args.steps / seconds:.0f} steps/s)")
    if args.save:
        model.save(args.save)
        print(f"saved {args.save}.zip" if not args.save.endswith(".zip") else f"saved {args.save}")
    env = make_env(args.task, args.reward)
    outcomes = test(model, env, args.test_episodes)
    n = args.test_episodes
    print(f"test, {n} episodes: success {outcomes['success'] / n:.0%}, "
          f"collision {outcomes['collision'] / n:.0%}, timeout {outcomes['timeout'] / n:.0%}")
    env.close()


if __name__ == "__main__":
    main()
