"""Record episodes of a dynnav task to a Rerun file (or a viewer).

    python -m dynnav_tasks.record --task DynNav-VisualStaticTarget-v1 --episodes 2 --out runs/visual.rrd
    python -m dynnav_tasks.record --checkpoint runs/<run>/checkpoint.pkl --episodes 5 --out runs/trained.rrd
    rerun runs/visual.rrd        # open it (the viewer ships with rerun-sdk)

Without ``--checkpoint`` the policy is random, and camera worlds record the camera frame too
(``--obs-mode`` defaults to ``rgb+state`` for them, ``state`` otherwise). With a checkpoint of
``agents.dqn`` the trained agent drives greedily on its own task and settings, and its
Q-values (and, for camera runs, the auto-encoder's latent and reconstruction) are recorded
every step. Saving needs no viewer; ``--spawn`` also opens one where a
display exists.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
import tyro


@dataclass
class Args:
    task: str = "DynNav-MovingTarget-v1"
    """registered task id (see dynnav_tasks.TASK_IDS); with --checkpoint, the checkpoint's task"""
    checkpoint: Optional[Path] = None
    """an agents.dqn checkpoint (or run directory) whose greedy policy drives"""
    out: Optional[Path] = Path("dynnav.rrd")
    """Rerun file to write"""
    episodes: int = 2
    """number of episodes to record"""
    seed: int = 0
    """seed of the first episode; episode i uses seed + i"""
    obs_mode: Optional[str] = None
    """observation mode (default: rgb+state for camera worlds, state otherwise)"""
    spawn: bool = False
    """also open a Rerun viewer"""


def record_episodes(env, recorder, episodes: int, seed: int, q_function=None, views=None) -> list[tuple[str, int]]:
    """Roll out episodes, logging every step; return (outcome, length) per episode.

    ``q_function(obs)`` gives Q-values to act greedily on (and to record); None: random actions.
    ``views(obs)`` gives more agent outputs to record (an auto-encoder's latent and reconstruction).
    """
    rng = np.random.default_rng(seed)
    results = []
    for ep in range(episodes):
        obs, _ = env.reset(seed=seed + ep)
        recorder.start_episode(env, ep)
        steps, done = 0, False
        while not done:
            q_values = None if q_function is None else q_function(obs)
            action = int(rng.integers(env.action_space.n)) if q_values is None else int(np.argmax(q_values))
            obs, reward, terminated, truncated, info = env.step(action)
            recorder.log_step(env, action=action, reward=float(reward), q_values=q_values,
                              **(views(obs) if views is not None else {}))
            steps += 1
            done = bool(terminated or truncated)
        results.append((recorder.end_episode(info), steps))
    return results


def trained_policy(checkpoint: Path):
    """(env, q_function, views, task id) of an agents.dqn checkpoint (views: None for state runs)."""
    from agents.evaluate import load_policy

    config, env, net, features, _, _ = load_policy(checkpoint)
    return env, (lambda obs: net(features(obs))), getattr(features, "views", None), config.task


def main(args: Args) -> None:
    from mani_skill.utils.wrappers.gymnasium import CPUGymWrapper

    import dynnav_tasks
    from dynnav_tasks.recording import Recorder

    try:
        dynnav_tasks.check_choice(args.task, dynnav_tasks.TASK_IDS, "task id")
        recorder = Recorder(args.out, spawn=args.spawn)  # checks the output path before any work
        q_function = views = None
        if args.checkpoint is not None:
            env, q_function, views, task = trained_policy(args.checkpoint)
            print(f"{task}: greedy policy of {args.checkpoint}")
        else:
            obs_mode = args.obs_mode or ("rgb+state" if args.task in dynnav_tasks.VISUAL_TASK_IDS else "state")
            env = CPUGymWrapper(dynnav_tasks.make(args.task, obs_mode=obs_mode))
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    with recorder:
        results = record_episodes(env, recorder, args.episodes, args.seed, q_function, views)
    env.close()
    for ep, (outcome, steps) in enumerate(results):
        print(f"episode {ep}: {outcome} after {steps} steps")
    if args.out is not None:
        print(f"wrote {args.out} ({args.out.stat().st_size / 1e6:.2f} MB); open it with: rerun {args.out}")


if __name__ == "__main__":
    main(tyro.cli(Args))
