"""The same labelled episodes seen through other sensors, without asking the teacher again.

An episode is fixed by its reset seed and its actions: the seed draws the world, the start and
every obstacle's motion, and the sensors never change a step. Playing a rollout's actions again
from its seed in a task made with other observation options (64 or 180 laser rays, the way to
the target or not, more tracked obstacles) gives the very same states, seen another way, and the
teacher's labels still hold. ``reobserve`` does that and checks it: every replay must end as the
original did, at the same step, or it is an error.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from tqdm import tqdm

from agents.core.demonstrations import Rollout
from agents.training.envs import make_env_from


def reobserve(rollouts: list[Rollout], config, progress: bool = False) -> list[Rollout]:
    """``rollouts`` with the observations of ``config``'s task (the same task and worlds, other
    observation options); ValueError if an episode does not replay as it was played."""
    env = make_env_from(config)
    out = []
    try:
        for r in tqdm(rollouts, desc="re-observing", unit="ep", disable=not progress, leave=False):
            obs, _ = env.reset(seed=r.seed)
            observations = [obs]
            for k, action in enumerate(r.actions):
                obs, reward, terminated, truncated, _ = env.step(int(action))
                observations.append(obs)
                last = k == r.steps - 1
                if bool(terminated or truncated) != last or not np.isclose(reward, r.rewards[k], atol=1e-4):
                    raise ValueError(f"episode of seed {r.seed} does not replay in {config.task} with "
                                     f"{config.env.task_kwargs}: step {k} differs (the options must leave the "
                                     f"dynamics and the reward as they were)")
            out.append(dataclasses.replace(r, observations=np.asarray(observations, dtype=np.float32)))
    finally:
        env.close()
    return out
