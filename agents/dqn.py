"""DQN (thesis Alg. 1) and Double DQN (Appendix A) for dynnav tasks and any gymnasium env
with discrete actions and a state vector.

    python -m agents.dqn --config configs/study/5.2.yaml        # train, then test
    python -m agents.dqn --config configs/study/5.2.yaml --fast # on two processes (agents.training.fast_loop)
    python -m agents.dqn --task CartPole-v1 --episodes 300              # any gymnasium env
    python -m agents.dqn --resume runs/<run>                            # continue a stopped run
    python -m agents.dqn --eval --checkpoint runs/<run>                 # test phase only
    python -m agents.dqn --config ... --rerun runs/train.rrd            # also record (Rerun)
    python -m agents.dqn --config configs/study/5.5a-camera.yaml              # camera + auto-encoder (Alg. 2)
    python -m agents.dqn --config configs/study/5.5c-frames-4-pixels.yaml   # conv Q-network on frames

A run directory ``runs/<task>__<name>__<seed>__<time>/`` receives the resolved config
(config.yaml), one metrics row per episode (metrics.csv), the checkpoint (checkpoint/,
rewritten atomically every ``checkpoint_every`` episodes), the learning curves (reward.png,
loss.png) and the test results (eval.json, eval.md, trajectories.png).

The loop, per environment step (``agents.training.loop``): epsilon-greedy action; store (s, a, r, s',
terminated); once ``learning_starts`` steps are stored, every ``train_frequency`` steps one
gradient step on a minibatch (``agents.core.learner``); hard target copy every
``target_update_interval`` steps (or a soft update after every gradient step). A timeout
(truncation) still bootstraps from Q(s'); a success or a collision (termination) does not.
Epsilon and the learning rate change once per episode.

One process writes a run directory at a time: a second ``--resume`` (or a test phase writing
into it) while the first runs is refused, naming the process; the lock of a killed run does not
block a later ``--resume`` (``agents.training.run_lock``). A full disk stops the run with a
one-line error naming the file and the space needed; the last complete checkpoint stays.

Camera runs with the auto-encoder (``camera_input: latent``, thesis Alg. 2) read its latent
instead of the state vector (agents/srl/state_representation.py): actions are random and the
Q-network does not train until the auto-encoder's first update; the updates run between
episodes on their schedule, and write srl_loss.csv/png and reconstructions/ into the run
directory. Pixel runs (``camera_input: pixels``) train a conv Q-network on the frames from the
first step.
"""

from __future__ import annotations

import sys

from agents.files import DiskFullError
from agents.training.config_io import parse_args
from agents.training import loop
from agents.training.config import Config
from agents.training.fast_loop import train_fast
from agents.training.test_phase import evaluate_as_configured

__all__ = ["main", "train"]


def train(config: Config):
    """Train as ``config`` says and return the run directory: in the single-process loop
    (``agents.training.loop``, replayable from the seed), or with ``run.fast`` on two processes
    (``agents.training.fast_loop``)."""
    if config.run.fast:
        return train_fast(config)
    return loop.train(config)


def main(argv: list[str] | None = None) -> None:
    """``python -m agents.dqn`` / ``dynnav-train``: train (and test) as the flags and config say, or
    only test with ``--eval``; a bad input, a busy run directory or a full disk ends with a
    one-line error."""
    try:
        config = parse_args(argv)
        if config.eval:
            evaluate_as_configured(config, config.checkpoint, rerun=config.run.rerun, out_dir=config.test.eval_out,
                                   device=config.run.device)
            return
        run_dir = train(config)
        if config.test.eval_after_training:
            evaluate_as_configured(config, run_dir, device=config.run.device)
        print(f"\nrun directory: {run_dir}")
        pictures = [p.name for p in sorted(run_dir.glob("*.png"))]
        print(f"  config.yaml, metrics.csv, checkpoint/; pictures: {', '.join(pictures)}")
    except (ValueError, DiskFullError) as err:  # config, task, checkpoint, busy run directory, full disk
        raise SystemExit(f"error: {err}")


def eval_main(argv: list[str] | None = None) -> None:
    """``dynnav-eval``: the test phase of a checkpoint (``python -m agents.dqn --eval ...``)."""
    main(["--eval", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    main(sys.argv[1:])
