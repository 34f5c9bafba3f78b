"""How the tasks are registered with gymnasium, so gymnasium's own tools work on them.

ManiSkill's ``register_env`` (used by every task file) registers a task twice: with ManiSkill
and with gymnasium. ``register_with_gymnasium`` replaces the gymnasium entry of each dynnav
task so that:

* ``gymnasium.make(id)`` returns the task as ManiSkill does (batched torch tensors); the
  task ends its episodes after 200 steps itself, so no ManiSkill time-limit wrapper (which
  gymnasium cannot re-create) is added, and ``env.spec.make()`` re-creates the env, wrappers
  included, when they record their arguments (``wrappers.NumpyWrapper`` does);
* ``gymnasium.make_vec(id, num_envs=n)`` in any of its modes ("sync", "async", or the default)
  builds ``n`` plain gymnasium sub-environments (``NumpyWrapper``: numpy, unbatched), so the
  vector env's observations have shape ``(n, state size)``: a vector env batches its
  sub-environments itself, and a sub-environment that was batched already would add a
  second batch axis.

Forking: gymnasium's ``AsyncVectorEnv`` creates one env in the parent process to read the
spaces, closes it and then forks its workers. A SAPIEN scene that is still waiting for Python's
garbage collector at that moment would be collected in the child, whose copy of the Vulkan
renderer has lost its threads, and the child would hang. ``NavEnv.close`` therefore frees its
scene at once, and a garbage collection runs before every fork.
"""

from __future__ import annotations

import gc
import os
import sys
from functools import partial

import gymnasium as gym
from mani_skill.utils.registration import REGISTERED_ENVS


def _called_by_make_vec(depth: int = 4) -> bool:
    """Is this call inside gymnasium's ``make_vec`` making one of its sub-environments?"""
    frame = sys._getframe(1)
    for _ in range(depth):
        frame = frame.f_back
        if frame is None:
            return False
        if frame.f_code.co_name == "create_single_env" and frame.f_globals.get("__name__") == "gymnasium.envs.registration":
            return True
    return False


def make_task(task_id: str, **kwargs) -> gym.Env:
    """gymnasium's entry point of every dynnav task (see the module docstring)."""
    from .wrappers import NumpyWrapper

    env = REGISTERED_ENVS[task_id].make(**kwargs)
    return NumpyWrapper(env) if _called_by_make_vec() else env


def register_with_gymnasium(task_ids) -> None:
    """(Re-)register ``task_ids`` with gymnasium as the module docstring describes."""
    for task_id in task_ids:
        old = gym.registry.pop(task_id, None)
        gym.register(
            task_id,
            entry_point=partial(make_task, task_id),
            max_episode_steps=None,  # the task truncates at its own max_episode_steps (200)
            disable_env_checker=True,
            kwargs=dict(old.kwargs) if old is not None else {},
            additional_wrappers=(),
            vector_entry_point=None,  # make_vec's default mode: sync, as for any gymnasium env
        )


if hasattr(os, "register_at_fork"):
    os.register_at_fork(before=gc.collect)
