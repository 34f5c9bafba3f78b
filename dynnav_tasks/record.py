"""Record episodes of a dynnav task to a Rerun file (or a viewer).

    python -m dynnav_tasks.record --task DynNav-VisualStaticTarget-v1 --episodes 2 --out runs/visual.rrd
    rerun runs/visual.rrd        # open it (the viewer ships with rerun-sdk)

The policy is random. Camera worlds record the camera frame too (``--obs-mode`` defaults to
``rgb+state`` for them, ``state`` otherwise). Saving needs no viewer; ``--spawn`` also opens
one where a display exists.
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
    """registered task id (see dynnav_tasks.TASK_IDS)"""
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


def record_random(env, recorder, episodes: int, seed: int) -> list[tuple[str, int]]:
    """Roll out a random policy, logging every step; return (outcome, length) per episode."""
    rng = np.random.default_rng(seed)
    results = []
    for ep in range(episodes):
        env.reset(seed=seed + ep)
        recorder.start_episode(env, ep)
        steps, done = 0, False
        while not done:
            action = int(rng.integers(env.action_space.n))
            _, reward, terminated, truncated, info = env.step(action)
            recorder.log_step(env, action=action, reward=float(reward))
            steps += 1
            done = bool(terminated or truncated)
        results.append((recorder.end_episode(info), steps))
    return results


def main(args: Args) -> None:
    from mani_skill.utils.wrappers.gymnasium import CPUGymWrapper

    import dynnav_tasks
    from dynnav_tasks.recording import Recorder

    try:
        dynnav_tasks.check_choice(args.task, dynnav_tasks.TASK_IDS, "task id")
        recorder = Recorder(args.out, spawn=args.spawn)  # checks the output path before any work
        obs_mode = args.obs_mode or ("rgb+state" if args.task in dynnav_tasks.VISUAL_TASK_IDS else "state")
        env = CPUGymWrapper(dynnav_tasks.make(args.task, obs_mode=obs_mode))
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    with recorder:
        results = record_random(env, recorder, args.episodes, args.seed)
    env.close()
    for ep, (outcome, steps) in enumerate(results):
        print(f"episode {ep}: {outcome} after {steps} steps")
    if args.out is not None:
        print(f"wrote {args.out} ({args.out.stat().st_size / 1e6:.2f} MB); open it with: rerun {args.out}")


if __name__ == "__main__":
    main(tyro.cli(Args))
