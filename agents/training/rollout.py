"""One episode of a trained (or random) policy in an environment: the loop that the test phase
and recordings share (training has its own, in ``agents.training.loop``).

    episode = rollout(env, seed, act)                     # act(obs) -> (action, Q-values or None)

``on_reset(obs)`` sees the first observation and ``on_step(action, reward, next_obs,
terminated, truncated, info)`` every step (the test phase notes the path there); a
``recorder`` (``dynnav_tasks.viz.recording.Recorder``) logs every step with its Q-values and
``views(obs)`` (an auto-encoder's latent and reconstruction).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from dynnav_tasks.outcomes import outcome_of


@dataclass
class Episode:
    """What one episode ended with."""

    seed: int
    ret: float
    length: int
    info: dict
    terminated: bool
    outcome: str
    """success, collision, timeout (truncated) or terminated (other envs' endings)"""


def rollout(env, seed: int, act: Callable, on_reset: Optional[Callable] = None, on_step: Optional[Callable] = None,
            recorder=None, index: int = 0, views: Optional[Callable] = None) -> Episode:
    """Play one episode from ``env.reset(seed=seed)``; ``index`` numbers it in a recording."""
    obs, _ = env.reset(seed=seed)
    if on_reset is not None:
        on_reset(obs)
    if recorder is not None:
        recorder.start_episode(env, index)
    ret, length = 0.0, 0
    while True:
        action, q_values = act(obs)
        obs, reward, terminated, truncated, info = env.step(action)
        if on_step is not None:
            on_step(action, float(reward), obs, bool(terminated), bool(truncated), info)
        if recorder is not None:
            recorder.log_step(env, action=action, reward=float(reward), q_values=q_values,
                              **(views(obs) if views is not None else {}))
        ret += float(reward)
        length += 1
        if terminated or truncated:
            break
    if recorder is not None:
        recorder.end_episode(info)
    return Episode(seed, ret, length, info, bool(terminated), outcome_of(info, bool(terminated)))


def greedy(q_values: Callable, n_actions: int, epsilon: float = 0.0, rng: Optional[np.random.Generator] = None):
    """act(obs) for a policy acting greedily on ``q_values(obs)``, at random with probability ``epsilon``."""

    def act(obs):
        q = q_values(obs)
        action = int(np.argmax(q))
        if epsilon > 0 and rng.random() < epsilon:
            action = int(rng.integers(n_actions))
        return action, q

    return act


def random_actions(n_actions: int, rng: np.random.Generator):
    """act(obs) for the random policy."""
    return lambda obs: (int(rng.integers(n_actions)), None)


def open_recorder(path, task: str, spawn: bool = False, required: bool = False):
    """A Rerun recorder writing to ``path`` (None: no recording, unless ``required`` or ``spawn``);
    dynnav tasks only. The path is checked before any work."""
    if path is None and not spawn and not required:
        return None
    from agents.training.envs import is_dynnav

    if not is_dynnav(task):
        raise ValueError(f"--rerun records dynnav tasks (their world, lasers and camera), not {task!r}")
    from dynnav_tasks.viz.recording import Recorder

    return Recorder(path, spawn=spawn)
