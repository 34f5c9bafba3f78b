"""Training speed and test success: dynnav's single-process loop, its fast mode (two processes)
and Stable-Baselines3's DQN, on the same task with matched settings, measured in the same run.

    python benchmarks/fast_learner.py [--config configs/demo.yaml] [--seed 1] [--episodes N]
                                      [--eval-episodes N] [--skip-deterministic] [--camera]

All three train the config's task (task options, reward) with its network (2 x 128 ReLU), gamma,
batch size, replay memory, learning starts, train frequency, target copy interval, learning rate
schedule and epsilon schedule, for the same number of environment steps: dynnav's fast mode
trains the config's episodes first and the other two get its step count (the single-process loop
as episodes, so its count is close, not equal). Each is then tested on the config's test episodes
(greedy, the same seeds). SB3 reads the same scaled observations (``ObsScaler``, as dynnav's
agent) through ``dynnav_tasks.NumpyWrapper``; its schedules are per step where dynnav's are per
episode (epsilon decays over the same share of the steps; the learning rate linearly over all of
them). What cannot be matched: SB3's DQN is not Double DQN, its loss is Huber and it clips the
gradient norm at 10; dynnav uses the config's (the demo: Double DQN, MSE, no clipping).

Steps/s is the training's environment steps divided by its wall-clock (from the first step to
the last update; start-up and the test phase excluded). The ratio is dynnav fast / SB3.
``--camera`` adds the 5.5c 4-frame agents' training steps/s: the auto-encoder agent in the
single-process loop (the fast mode does not train it), the pixel agent in both.
"""

from __future__ import annotations

import argparse
import csv
import os
import shutil
import sys
import tempfile
import time
from dataclasses import replace

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from machine import describe  # noqa: E402


def train_dynnav(config) -> tuple[int, float, float]:
    """(steps, training seconds, test success rate) of one dynnav run."""
    from agents.dqn import train
    from agents.training.test_phase import evaluate_as_configured

    t0 = time.perf_counter()
    run_dir = train(config)
    seconds = time.perf_counter() - t0
    with open(run_dir / "metrics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    steps, train_s = int(rows[-1]["global_step"]), float(rows[-1]["wall_time_s"])
    summary = evaluate_as_configured(config, run_dir, verbose=False)
    print(f"  ({seconds:.1f} s with start-up and checkpoints)")
    return steps, train_s, summary["success_rate"]


def train_sb3(config, steps: int) -> tuple[int, float, float]:
    """(steps, training seconds, test success rate) of SB3's DQN with ``config``'s settings."""
    import gymnasium as gym
    import torch
    from stable_baselines3 import DQN

    from agents.training.envs import ObsScaler, make_env_from
    from agents.training.rollout import rollout

    d, s = config.dqn, config.schedule
    env = make_env_from(config)
    scaler = ObsScaler(env.observation_space, config.env.normalize_obs)
    space = gym.spaces.Box(-np.inf, np.inf, env.observation_space.shape, np.float32)
    env = gym.wrappers.TransformObservation(env, lambda o: scaler(o).astype(np.float32), space)
    lr0 = s.learning_rate
    lr1 = s.learning_rate_end if s.lr_schedule != "constant" else s.learning_rate
    decay_share = min(1.0, (s.random_episodes + s.epsilon_decay_episodes) / config.episodes)
    torch.manual_seed(config.seed)
    model = DQN("MlpPolicy", env, learning_rate=lambda remaining: lr1 + (lr0 - lr1) * remaining,
                buffer_size=d.buffer_size, learning_starts=d.learning_starts, batch_size=d.batch_size,
                gamma=d.gamma, train_freq=d.train_frequency, gradient_steps=1,
                target_update_interval=d.target_update_interval, exploration_fraction=decay_share,
                exploration_initial_eps=s.epsilon_start, exploration_final_eps=s.epsilon_end,
                policy_kwargs=dict(net_arch=list(d.hidden_sizes)), seed=config.seed, device="cpu", verbose=0)
    t0 = time.perf_counter()
    model.learn(total_timesteps=steps)
    seconds = time.perf_counter() - t0
    t = config.test

    def act(obs):
        return int(model.predict(obs, deterministic=True)[0]), None

    episodes = [rollout(env, t.eval_seed + i, act) for i in range(t.eval_episodes)]
    env.close()
    return steps, seconds, float(np.mean([e.outcome == "success" for e in episodes]))


def camera_rate(camera_input: str, episodes: int, fast: bool = False) -> float:
    """Training steps/s of a 5.5c 4-frame agent (its study config, a smaller memory) over the
    episodes with Q-updates, in the single-process loop or (pixels) the fast mode."""
    from agents.dqn import train
    from agents.training.config_io import load_yaml

    path = "configs/study/5.5c-frames-4-pixels.yaml" if camera_input == "pixels" else "configs/study/5.5c-frames-4.yaml"
    config = load_yaml(path)
    extra = dict(ae_first_update=2, ae_updates=1, ae_iterations=1, ae_batches=2, ae_batch_size=64) \
        if camera_input == "latent" else {}
    with tempfile.TemporaryDirectory() as tmp:
        config = replace(config, episodes=episodes,
                         run=replace(config.run, runs_dir=tmp, progress=False, checkpoint_every=10_000, fast=fast),
                         dqn=replace(config.dqn, learning_starts=200, buffer_size=20_000),
                         camera=replace(config.camera, **extra),
                         test=replace(config.test, eval_after_training=False)).validate()
        run = train(config)
        with open(run / "metrics.csv", newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["loss"]]
    return sum(int(r["length"]) for r in rows) / sum(int(r["length"]) / float(r["steps_per_s"]) for r in rows)


def compare(config, skip_deterministic: bool) -> None:
    """Train ``config`` with dynnav's fast mode, its single-process loop and SB3; print the table."""
    rows = []
    print("dynnav fast mode ...")
    fast = train_dynnav(replace(config, run=replace(config.run, fast=True)).validate())
    rows.append(("dynnav, fast mode (2 processes)", *fast))
    if not skip_deterministic:
        print("dynnav single-process loop ...")
        rows.append(("dynnav, single process (deterministic)",
                     *train_dynnav(replace(config, run=replace(config.run, fast=False)).validate())))
    print("Stable-Baselines3 DQN ...")
    sb3 = train_sb3(config, fast[0])
    rows.append(("Stable-Baselines3 DQN", *sb3))
    print(f"\n{'trainer':<42} {'steps':>7} {'train s':>8} {'steps/s':>8} {'test success':>13}")
    for name, steps, seconds, success in rows:
        print(f"{name:<42} {steps:>7} {seconds:>8.1f} {steps / seconds:>8.0f} {success:>13.0%}")
    ratio = (fast[0] / fast[1]) / (sb3[0] / sb3[1])
    print(f"\ndynnav fast mode / SB3: {ratio:.2f}x the training steps per second")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--config", default="configs/demo.yaml", help="the run's config (default: the demo)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--episodes", type=int, default=0, help="training episodes (default: the config's)")
    parser.add_argument("--eval-episodes", type=int, default=0, help="test episodes (default: the config's)")
    parser.add_argument("--skip-deterministic", action="store_true", help="leave out the single-process loop")
    parser.add_argument("--camera", action="store_true", help="also the 5.5c 4-frame agents' steps/s")
    parser.add_argument("--only-camera", action="store_true", help="only the 5.5c 4-frame agents' steps/s")
    parser.add_argument("--camera-episodes", type=int, default=12, help="episodes per camera agent (default 12)")
    args = parser.parse_args()
    import torch

    from agents.training.config_io import load_yaml
    from agents.training.threads import limit_threads

    limit_threads(1)
    print(describe("not pinned: the fast mode uses two"))
    print(f"torch {torch.__version__}, 1 thread per process; load average {os.getloadavg()[0]:.2f} at the start")
    config = load_yaml(args.config)
    tmp = tempfile.mkdtemp(prefix="fast-learner-")
    config = replace(config, seed=args.seed, episodes=args.episodes or config.episodes,
                     run=replace(config.run, runs_dir=tmp, progress=False),
                     test=replace(config.test, eval_after_training=False, eval_picture=False,
                                  eval_episodes=args.eval_episodes or config.test.eval_episodes))
    d = config.dqn
    print(f"{config.task}, {args.config}: {config.episodes} episodes, {d.algorithm}, batch {d.batch_size}, "
          f"train frequency {d.train_frequency}, target copy every {d.target_update_interval} steps, "
          f"seed {config.seed}, {config.test.eval_episodes} test episodes\n")
    try:
        if not args.only_camera:
            compare(config, args.skip_deterministic)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if args.camera or args.only_camera:
        print("\n5.5c, 4 gray frames (training steps/s over the episodes with updates):")
        for label, camera_input, fast in [("auto-encoder agent, single process", "latent", False),
                                          ("pixel agent, single process", "pixels", False),
                                          ("pixel agent, fast mode", "pixels", True)]:
            print(f"  {label:<36} {camera_rate(camera_input, args.camera_episodes, fast):>8.0f} steps/s")
    print(f"\nload average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
