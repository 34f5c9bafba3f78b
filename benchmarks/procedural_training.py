"""Training speed on procedural worlds: the fast mode's steps/s beside the random policy's in the same run.

    python benchmarks/procedural_training.py [--config configs/procedural/generalist-finetune.yaml] [--episodes 600]
        [--train-frequency 4 10]

The config's task (the generalist's: a mixture of the three difficulties' train worlds, with
the way through the static layout in the state) is stepped first by a random policy (the
environment alone, resets included, on this process's core), then trained in the fast mode
(``--fast``: this process collects, a second one learns) for ``--episodes`` episodes from a
fresh network, without a teacher, once per ``--train-frequency`` given (the config's by
default): the learner's work per collected step is what bounds the rate when it, not the
collector, is the slower of the two processes. Both rates count every step and every reset;
the training rate is its run's steps over its training wall-clock (``metrics.csv``),
checkpoints excluded.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from machine import describe  # noqa: E402

from agents.dqn import train  # noqa: E402
from agents.training.config_io import load_yaml  # noqa: E402
from agents.training.envs import make_env_from  # noqa: E402
from agents.training.threads import limit_threads  # noqa: E402


def random_rate(config, steps: int) -> float:
    """Steps per second of a random policy in ``config``'s task, resets included."""
    env = make_env_from(config)
    rng = np.random.default_rng(0)
    try:
        env.reset(seed=0)
        t0, episode = time.perf_counter(), 0
        for _ in range(steps):
            _, _, terminated, truncated, _ = env.step(int(rng.integers(3)))
            if terminated or truncated:
                episode += 1
                env.reset(seed=episode)
        return steps / (time.perf_counter() - t0)
    finally:
        env.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", default="configs/procedural/generalist-finetune.yaml")
    parser.add_argument("--episodes", type=int, default=600)
    parser.add_argument("--random-steps", type=int, default=20000)
    parser.add_argument("--batch-size", type=int, default=None, help="override the config's minibatch")
    parser.add_argument("--train-frequency", type=int, nargs="+", default=None,
                        help="steps per update to time, one run each (default: the config's)")
    args = parser.parse_args()
    limit_threads(1)
    print(describe("not pinned: the fast mode uses both cores"))
    base = load_yaml(args.config)
    base = dataclasses.replace(base, dqn=dataclasses.replace(base.dqn, batch_size=args.batch_size or base.dqn.batch_size))
    plain = dataclasses.replace(base, demos=dataclasses.replace(base.demos, init_from=None, demonstrations=None,
                                                                pretrain_updates=0))
    print(f"task: {base.task} {base.env.task_kwargs}")
    rate = random_rate(plain, args.random_steps)
    print(f"random policy:          {rate:7.0f} steps/s ({args.random_steps} steps)")
    for frequency in args.train_frequency or [base.dqn.train_frequency]:
        config = dataclasses.replace(plain, dqn=dataclasses.replace(plain.dqn, train_frequency=frequency))
        steps, seconds = fast_rate(config, args.episodes)
        d = config.dqn
        print(f"fast-mode training:     {steps / seconds:7.0f} steps/s ({args.episodes} episodes, {steps} steps, "
              f"batch {d.batch_size} every {d.train_frequency} steps, network {list(d.hidden_sizes)}); "
              f"training / random: {steps / seconds / rate:.2f}")


def fast_rate(config, episodes: int) -> tuple[int, float]:
    """(steps, training seconds) of ``episodes`` episodes of ``config`` in the fast mode, from a fresh network."""
    with tempfile.TemporaryDirectory() as tmp:
        config = dataclasses.replace(config, episodes=episodes, seed=1,
                                     run=dataclasses.replace(config.run, fast=True, runs_dir=tmp, progress=False,
                                                             checkpoint_every=episodes),
                                     test=dataclasses.replace(config.test, eval_after_training=False))
        run_dir = train(config)
        with open(Path(run_dir) / "metrics.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        return int(rows[-1]["global_step"]), float(rows[-1]["wall_time_s"])


if __name__ == "__main__":
    main()
