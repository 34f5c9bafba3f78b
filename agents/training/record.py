"""Record episodes of a dynnav task to a Rerun file (or a viewer): a random policy, or a
trained agent's greedy policy with its Q-values.

    python -m agents.training.record --task DynNav-VisualStaticTarget-v1 --episodes 2 --out runs/visual.rrd
    python -m agents.training.record --checkpoint runs/<run> --episodes 5 --out runs/trained.rrd
    python -m agents.training.record --checkpoint pretrained:5.3 --out runs/5.3.rrd   # a pretrained navigator
    rerun runs/visual.rrd        # open it (the viewer ships with rerun-sdk)

Without ``--checkpoint`` the policy is random, and camera worlds record the camera frame too
(``--obs-mode`` defaults to ``rgb+state`` for them, ``state`` otherwise). With a checkpoint of
``agents.dqn`` the trained agent drives greedily on its own task and settings, and its
Q-values (and, for auto-encoder camera runs, the latent and the reconstruction) are recorded
every step. Saving needs no viewer; ``--spawn`` also opens one where a display exists.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
import tyro

from agents.files import DiskFullError
from agents.training.rollout import greedy, open_recorder, random_actions, rollout


@dataclass
class Args:
    """Record episodes of a dynnav task (random or trained policy) to a Rerun file."""

    task: str = "DynNav-MovingTarget-v1"
    """registered task id (see dynnav_tasks.TASK_IDS); with --checkpoint, the checkpoint's task is used"""
    checkpoint: Optional[str] = None
    """an agents.dqn checkpoint (or run directory), or pretrained:NAME, whose greedy policy drives"""
    out: Optional[Path] = Path("dynnav.rrd")
    """Rerun file to write"""
    episodes: int = 2
    """number of episodes to record"""
    seed: int = 0
    """seed of the first episode; episode i uses seed + i"""
    obs_mode: Optional[str] = None
    """observation mode of the random policy's task (default: rgb+state for camera worlds, state otherwise)"""
    spawn: bool = False
    """also open a Rerun viewer"""


def record_episodes(env, recorder, episodes: int, seed: int, act=None, views=None,
                    on_reset=None) -> list[tuple[str, int]]:
    """Roll out episodes on seeds seed, seed + 1, ..., logging every step; return (outcome, steps) per
    episode. ``act(obs) -> (action, Q-values)`` (``agents.training.rollout.greedy``); None: random actions.
    ``on_reset(obs)`` sees each episode's first observation (a trained policy's ``reset``)."""
    act = act or random_actions(int(env.action_space.n), np.random.default_rng(seed))
    results = [rollout(env, seed + i, act, on_reset, recorder=recorder, index=i, views=views) for i in range(episodes)]
    return [(e.outcome, e.length) for e in results]


def record(args: Args) -> list[tuple[str, int]]:
    """Record ``args.episodes`` episodes; return (outcome, steps) per episode."""
    import dynnav_tasks

    if args.checkpoint is not None:
        from agents.training.policy_loading import load_policy

        policy = load_policy(args.checkpoint)
        task, env, views = policy.config.task, policy.env, policy.views
        recorder = open_recorder(args.out, task, spawn=args.spawn, required=True)
        act, on_reset = greedy(policy.q_values, int(env.action_space.n)), lambda obs: policy.reset()
        print(f"{task}: greedy policy of {args.checkpoint}")
    else:
        dynnav_tasks.check_choice(args.task, dynnav_tasks.ALL_TASK_IDS, "task id")
        recorder = open_recorder(args.out, args.task, spawn=args.spawn, required=True)  # checks the path before any work
        obs_mode = args.obs_mode or ("rgb+state" if args.task in dynnav_tasks.VISUAL_TASK_IDS else "state")
        env, views, act = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(args.task, obs_mode=obs_mode)), None, None
        on_reset = None
    try:
        with recorder:
            return record_episodes(env, recorder, args.episodes, args.seed, act, views, on_reset)
    finally:
        env.close()


def main(args: Args | None = None) -> None:
    """``python -m agents.training.record`` / ``dynnav-record``."""
    if args is None:
        args = tyro.cli(Args)
    try:
        results = record(args)
    except (ValueError, DiskFullError) as err:
        raise SystemExit(f"error: {err}")
    for i, (outcome, steps) in enumerate(results):
        print(f"episode {i}: {outcome} after {steps} steps")
    if args.out is not None:
        print(f"wrote {args.out} ({args.out.stat().st_size / 1e6:.2f} MB); open it with: rerun {args.out}")


if __name__ == "__main__":
    main()
