"""Memory's cost: the recurrent Q-network's training beside the feed-forward agent's, measured in
the same run (docs/memory.md).

    python benchmarks/memory_training.py [--updates 300] [--steps 1500] [--cell gru]

1. Learning alone, per environment step (``--inputs`` values in, 15: the latent of 5.5c's four
   stacked frames; replay memories of random episodes of 20 to 80 steps). Feed-forward (the
   study's camera runs): a Double-DQN update on 128 transitions every step with the 2 x 128 MLP,
   and its Q-values for acting. Recurrent (configs/study/*-gru.yaml): a Double-DQN update on 32
   sequences of 10 burn-in + 20 steps every 4th step with a 128 encoder and a GRU of 128, and one
   step of the GRU for acting.
2. Whole training steps on world 5.5c with four stacked frames, as configs/study/5.5c-frames-4-g0.1.yaml
   and its -gru variant set them (random actions; every frame rendered, stored and encoded as
   after the auto-encoder's first update; the Q-values of every step; the updates at the
   configs' train_frequency), ``--steps`` each after a warm-up.

Times are CPU seconds of this process (``time.process_time``), so other work on the machine
changes them little. The process is pinned to one core; torch and numpy's BLAS run one thread each.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from agents.core.frame_replay import FrameReplay  # noqa: E402
from agents.core.learner import DQNLearner  # noqa: E402
from agents.core.networks import MLPQNetwork  # noqa: E402
from agents.core.recurrent import RecurrentLearner, RecurrentQNetwork  # noqa: E402
from agents.core.replay import Batch  # noqa: E402
from agents.core.sequence_replay import SequenceBatch, sample_sequences_into  # noqa: E402
from agents.training.threads import limit_threads  # noqa: E402
from machine import describe, pin_one_core  # noqa: E402

N_ACTIONS, MEMORY = 3, 50_000
TASK = "DynNav-VisualMovingTargets-v1"
CONFIGS = Path(__file__).resolve().parents[1] / "configs" / "study"
NO_FRAME = np.zeros(0, np.uint8)


def filled_memory(inputs: int) -> FrameReplay:
    """Random episodes of 20-80 steps, every observation once (inputs as state parts)."""
    rng = np.random.default_rng(0)
    memory = FrameReplay(MEMORY, (0,), state_dim=inputs, latent_dim=0)
    while memory.size < MEMORY - 100:
        memory.start(NO_FRAME, rng.normal(size=inputs).astype(np.float32))
        length = int(rng.integers(20, 81))
        for t in range(length):
            memory.add(int(rng.integers(N_ACTIONS)), float(rng.normal()), NO_FRAME,
                       rng.normal(size=inputs).astype(np.float32), terminated=t == length - 1)
    return memory


def seconds_each(fn, n: int) -> float:
    for _ in range(min(20, n)):
        fn()
    t0 = time.process_time()
    for _ in range(n):
        fn()
    return (time.process_time() - t0) / n


def training_step_seconds(config_path, steps: int, cell: str) -> float:
    """CPU seconds per training step of the config (random actions, as after the auto-encoder's
    first update): render, store, encode, Q-values, and the config's updates."""
    from agents.core.policy import build_learner, build_q_network
    from agents.training.config_io import load_yaml, replace
    from agents.training.envs import make_env_from
    from agents.training.experience import make_experience

    config = load_yaml(config_path)
    if config.dqn.recurrent:
        config = replace(config, recurrent=cell)
    env = make_env_from(config)
    experience = make_experience(env, config)
    experience.srl.updates_done = 1  # encode every frame, as after the first update
    specs = experience.features.input_specs
    learner = build_learner(config, build_q_network(config, specs, 3), specs)
    rng = np.random.default_rng(0)
    actions = rng.integers(0, 3, size=steps + 300)
    every = config.dqn.train_frequency

    def loop(n: int, offset: int) -> None:
        obs, _ = env.reset(seed=offset)
        x = experience.begin(obs)
        learner.reset()
        for k in range(n):
            learner.q_values(x)
            obs, _, terminated, truncated, _ = env.step(int(actions[k]))
            x = experience.step(int(actions[k]), 0.0, obs, bool(terminated))
            if k % every == 0 and len(experience) >= 200:
                experience.sample_into(learner.batch, rng)
                learner.update()
            if terminated or truncated:
                obs, _ = env.reset()
                x = experience.begin(obs)
                learner.reset()

    loop(300, 0)  # warm up: the renderer's first frame, enough transitions for a minibatch
    t0 = time.process_time()
    loop(steps, 1)
    seconds = (time.process_time() - t0) / steps
    env.close()
    return seconds


def feed_forward(memory: FrameReplay, inputs: int, rng):
    torch.manual_seed(0)
    learner = DQNLearner(MLPQNetwork(inputs, N_ACTIONS, (128, 128)), Batch(128, [((inputs,), np.float32)]),
                         double=True, learning_rate=3e-4)

    def update():
        memory.sample_into(learner.batch, rng)
        learner.update()

    x = np.zeros(inputs, np.float32)
    return update, lambda: learner.q_values(x)


def recurrent(memory: FrameReplay, inputs: int, rng, cell: str):
    torch.manual_seed(0)
    net = RecurrentQNetwork(inputs, N_ACTIONS, (128,), 128, cell)
    learner = RecurrentLearner(net, SequenceBatch(32, 20, 10, inputs), double=True, learning_rate=3e-4)

    def update():
        sample_sequences_into(memory, learner.batch, rng)
        learner.update()

    x = np.zeros(inputs, np.float32)
    return update, lambda: learner.q_values(x)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--updates", type=int, default=300, help="timed updates per variant")
    parser.add_argument("--inputs", type=int, default=15, help="Q-network input size (15: 5.5c's latent)")
    parser.add_argument("--cell", choices=("gru", "lstm"), default="gru")
    parser.add_argument("--steps", type=int, default=1500, help="whole training steps per agent (0: skip)")
    args = parser.parse_args()
    limit_threads(1)
    print(describe(pin_one_core()))
    print(f"torch {torch.__version__}, {args.inputs} inputs, {N_ACTIONS} actions, Double DQN, Adam\n")
    memory = filled_memory(args.inputs)
    rows = []
    for name, (update, act), every in (
            ("feed-forward: 128 transitions, every step", feed_forward(memory, args.inputs, np.random.default_rng(1)), 1),
            (f"{args.cell}: 32 x (10 + 20) steps, every 4th step",
             recurrent(memory, args.inputs, np.random.default_rng(1), args.cell), 4)):
        u, a = seconds_each(update, args.updates), seconds_each(act, 20 * args.updates)
        rows.append(u / every + a)
        print(f"{name:<45} update {u * 1e3:6.2f} ms, act {a * 1e3:5.3f} ms -> {rows[-1] * 1e3:6.2f} ms "
              f"of learning per environment step")
    print(f"memory costs {rows[1] / rows[0]:.2f}x the feed-forward agent's learning time per environment step\n")
    if args.steps:
        print(f"whole training steps on {TASK}, 4 stacked frames ({args.steps} steps each):")
        whole = [training_step_seconds(CONFIGS / f"5.5c-frames-4-g0.1{suffix}.yaml", args.steps, args.cell)
                 for suffix in ("", "-gru")]
        for name, sec in zip(("feed-forward (5.5c-frames-4-g0.1)", f"{args.cell} (5.5c-frames-4-g0.1-gru)"), whole):
            print(f"  {name:<40} {1 / sec:7.0f} steps per CPU second ({sec * 1e3:.2f} ms per step)")
        print(f"a training step with memory costs {whole[1] / whole[0]:.2f}x the feed-forward one")


if __name__ == "__main__":
    main()
