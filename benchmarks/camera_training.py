"""Camera-run speed and memory: world 5.5c with the stacked-frame auto-encoder (thesis Exp. 3).

    python benchmarks/camera_training.py [--steps 3000] [--frames 4] [--no-pin]

Measured in the same run, on one core, random actions, resets included:

1. the laser task alone (``obs_mode="state"``): the baseline;
2. the camera task alone: a 32x32 frame rendered every step, gray frames stacked;
3. + encoding: every observation stored in the frame replay and encoded by the auto-encoder
   (as after the first update of Alg. 2; the weights do not change the cost);
4. + one Double-DQN update per step on a minibatch of 128 from the frame replay: a full
   training step.

It also times one auto-encoder batch of 256 frames (so one scheduled update of iterations x
batches), and prints the observation memory's size for the default capacity (100,000
observations) for one RGB frame and for the stack.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from machine import describe, pin_one_core  # noqa: E402

TASK = "DynNav-VisualMovingTargets-v1"


def run(steps: int, frames: int, mode: str) -> float:
    """Steps/s of ``mode``: state, camera, encode or train."""
    from agents.training.config_io import make
    from agents.training.envs import make_env_from
    from agents.training.experience import make_experience
    from agents.core.learner import DQNLearner
    from agents.core.replay import Batch
    from agents.core.networks import MLPQNetwork

    config = make(task=TASK, camera_frames=0 if mode == "state" else frames, buffer_size=max(steps + 1000, 5000),
                  batch_size=128, algorithm="ddqn")
    env = make_env_from(config)
    experience = make_experience(env, config) if mode in ("encode", "train") else None
    if experience is not None:
        experience.srl.updates_done = 1  # encode every frame, as after the first update
    learner = None
    if mode == "train":
        specs = experience.features.input_specs
        learner = DQNLearner(MLPQNetwork(specs[0][0][0], 3), Batch(128, specs), double=True)
    rng = np.random.default_rng(0)
    actions = rng.integers(0, 3, size=steps + 200)

    def loop(n: int, offset: int) -> None:
        obs, _ = env.reset(seed=offset)
        if experience is not None:
            experience.begin(obs)
        for k in range(n):
            obs, _, terminated, truncated, _ = env.step(int(actions[k]))
            if experience is not None:
                experience.step(int(actions[k]), 0.0, obs, bool(terminated))
                if learner is not None and len(experience) >= 128:
                    experience.sample_into(learner.batch, rng)
                    learner.update()
            if terminated or truncated:
                obs, _ = env.reset()
                if experience is not None:
                    experience.begin(obs)

    loop(200, 0)  # warm up (the renderer's first frame, the replay's first batch)
    t0 = time.perf_counter()
    loop(steps, 1)
    rate = steps / (time.perf_counter() - t0)
    env.close()
    return rate


def autoencoder_batch_seconds(frames: int, repeats: int = 10) -> tuple[float, object]:
    from agents.training.config_io import make
    from agents.srl.state_representation import SRLSettings, StateRepresentation

    settings = SRLSettings.from_config(make(task=TASK, camera_frames=frames))
    srl = StateRepresentation(settings, seed=0)
    batch = np.random.default_rng(0).integers(0, 256, size=(settings.batch_size, *settings.frame_shape), dtype=np.uint8)
    srl.trainer.train_batch(batch)
    t0 = time.perf_counter()
    for _ in range(repeats):
        srl.trainer.train_batch(batch)
    return (time.perf_counter() - t0) / repeats, settings


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=3000, help="steps per figure (default 3000)")
    parser.add_argument("--frames", type=int, default=4, help="stacked gray frames (default 4; 1 = one RGB frame)")
    parser.add_argument("--no-pin", action="store_true", help="do not pin the process to one core")
    args = parser.parse_args()
    pinned = "not pinned" if args.no_pin else pin_one_core()
    from agents.training.threads import limit_threads

    import torch  # noqa: F401  (so that limit_threads sets torch too)

    limit_threads(1)
    print(describe(pinned))
    print(f"{TASK}, {args.frames} frame(s), {args.steps} steps per figure, random actions, resets included\n")
    rows = [
        ("laser task alone (state)", run(args.steps, args.frames, "state")),
        ("camera task alone (32x32 frames, stacked)", run(args.steps, args.frames, "camera")),
        ("+ frame replay and encoding", run(args.steps, args.frames, "encode")),
        ("+ one Double-DQN update per step (batch 128)", run(args.steps, args.frames, "train")),
    ]
    width = max(len(r[0]) for r in rows)
    print(f"{'':<{width}}  {'steps/s':>8}  {'ms/step':>8}")
    for name, rate in rows:
        print(f"{name:<{width}}  {rate:>8.0f}  {1000 / rate:>8.2f}")

    seconds, settings = autoencoder_batch_seconds(args.frames)
    n = settings.iterations * settings.batches
    print(f"\nauto-encoder: one batch of {settings.batch_size} frames {seconds * 1000:.0f} ms; one scheduled update "
          f"({settings.iterations} iterations x {settings.batches} batches) about {n * seconds:.0f} s, "
          f"{settings.updates} updates about {settings.updates * n * seconds:.0f} s")

    from agents.core.frame_replay import FrameReplay

    print("\nobservation memory for 100,000 observations (frames uint8, latents and state parts float32):")
    for label, shape, latent, state in (("one RGB frame, latent 10, no state parts", (32, 32, 3), 10, 0),
                                        ("4 gray frames, latent 15, no state parts", (32, 32, 4), 15, 0),
                                        ("one RGB frame, latent 10, 24 state values (5.5b)", (32, 32, 3), 10, 24)):
        memory = FrameReplay(100_000, shape, state, latent)
        print(f"  {label}: {memory.nbytes / 1e6:.0f} MB")


if __name__ == "__main__":
    main()
