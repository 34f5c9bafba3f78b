"""Training throughput: environment steps per second while training, beside the same task's
random-policy rate, measured in the same run on one core.

    python benchmarks/training_throughput.py [--episodes-52 150] [--episodes-55c 12] [--no-pin]

* world 5.2 (state vector): the random policy through ``make_env``, then ``agents.dqn.train``
  with one Double-DQN update per step (batch 128, 2 x 128 MLP);
* world 5.5c with 4 stacked gray frames: the random policy (a 32x32 frame rendered every step),
  then training the pixel agent (conv Q-network, random shifts, one update every 4 steps, batch
  32) and the study's auto-encoder agent (latent 15, one update per step, batch 128; its
  auto-encoder trains once after episode 2 on a tiny schedule, and only the episodes after it
  count).

A training rate is the steps of the episodes with Q-updates divided by their wall-clock time
(``metrics.csv``: acting, storing, updating; checkpoints and auto-encoder updates excluded).
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from machine import describe, pin_one_core  # noqa: E402

STATE_TASK, CAMERA_TASK = "DynNav-MovingTarget-v1", "DynNav-VisualMovingTargets-v1"


def random_policy_rate(task: str, frames: int, steps: int) -> float:
    from agents.training.envs import make_env

    env = make_env(task, camera_frames=frames)
    rng = np.random.default_rng(0)
    env.reset(seed=0)
    for _ in range(50):  # warm up (a camera world's first frame)
        if any(env.step(int(rng.integers(3)))[2:4]):
            env.reset()
    t0 = time.perf_counter()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(int(rng.integers(3)))
        if terminated or truncated:
            env.reset()
    rate = steps / (time.perf_counter() - t0)
    env.close()
    return rate


def training_rate(**settings) -> float:
    from agents.training.config_io import make
    from agents.dqn import train

    with tempfile.TemporaryDirectory() as tmp:
        run = train(make(runs_dir=tmp, progress=False, eval_after_training=False, **settings).validate())
        with open(run / "metrics.csv", newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["loss"]]
    steps = sum(int(r["length"]) for r in rows)
    seconds = sum(int(r["length"]) / float(r["steps_per_s"]) for r in rows)
    return steps / seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episodes-52", type=int, default=150, help="training episodes on 5.2 (default 150)")
    parser.add_argument("--episodes-55c", type=int, default=12, help="training episodes on 5.5c (default 12)")
    parser.add_argument("--random-steps", type=int, default=3000, help="random-policy steps per task (default 3000)")
    parser.add_argument("--no-pin", action="store_true", help="do not pin the process to one core")
    args = parser.parse_args()
    pinned = "not pinned" if args.no_pin else pin_one_core()
    import torch

    from agents.training.threads import limit_threads

    limit_threads(1)
    print(describe(pinned))
    print(f"torch {torch.__version__}, {torch.get_num_threads()} thread\n")
    state = dict(task=STATE_TASK, episodes=args.episodes_52, algorithm="ddqn", learning_starts=500,
                 task_kwargs={"turn_forward_step": 0.05}, checkpoint_every=10_000, random_episodes=0,
                 epsilon_decay_episodes=args.episodes_52)
    camera = dict(task=CAMERA_TASK, episodes=args.episodes_55c, camera_frames=4, algorithm="ddqn",
                  checkpoint_every=10_000, buffer_size=20_000, epsilon_decay_episodes=args.episodes_55c)
    rows = []
    base = random_policy_rate(STATE_TASK, 0, args.random_steps)
    rows.append(("5.2 state", "random policy", base, None))
    rows.append(("5.2 state", "Double DQN, one update per step", training_rate(**state), base))
    base = random_policy_rate(CAMERA_TASK, 4, args.random_steps // 3)
    rows.append(("5.5c 4 frames", "random policy", base, None))
    pixels = training_rate(**camera, camera_input="pixels", learning_starts=200, batch_size=32, train_frequency=4)
    rows.append(("5.5c 4 frames", "pixels: conv Q-net, update every 4 steps, batch 32", pixels, base))
    latent = training_rate(**camera, camera_input="latent", learning_starts=200, ae_first_update=2, ae_updates=1,
                           ae_iterations=1, ae_batches=2, ae_batch_size=64)
    rows.append(("5.5c 4 frames", "auto-encoder latent: MLP, update every step, batch 128", latent, base))
    print(f"{'task':<14} {'policy':<55} {'steps/s':>8} {'of random':>9}")
    for task, label, rate, ref in rows:
        share = f"{rate / ref:.0%}" if ref else ""
        print(f"{task:<14} {label:<55} {rate:>8.0f} {share:>9}")


if __name__ == "__main__":
    main()
