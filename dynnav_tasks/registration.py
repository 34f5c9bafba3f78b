"""How the tasks are registered with gymnasium, so gymnasium's own tools work on them.

ManiSkill's ``register_env`` (used by every task file) registers a task twice: with ManiSkill
and with gymnasium. ``register_with_gymnasium`` replaces the gymnasium entry of each dynnav
task so that:

* ``gymnasium.make(id)`` returns the task as ManiSkill does (batched torch tensors); the
  task ends its episodes after 200 steps itself, so no ManiSkill time-limit wrapper (which
  gymnasium cannot re-create) is added, and ``env.spec.make()`` re-creates the env, wrappers
  included, when they record their arguments (``wrappers.NumpyWrapper`` does);
* ``gymnasium.make_vec(id, num_envs=n)`` (its default mode) calls ``make_vector_task``, which
  builds ``n`` plain gymnasium sub-environments (``NumpyWrapper``: numpy, unbatched) in a
  ``SyncVectorEnv``, so the vector env's observations have shape ``(n, state size)``: a vector
  env batches its sub-environments itself, and a sub-environment that was batched already
  would add a second batch axis;
* gymnasium's own modes make each sub-environment with ``gymnasium.make``, the batched one, so
  they take ``NumpyWrapper`` as their first wrapper::

      gym.make_vec(id, num_envs=n, vectorization_mode="async", wrappers=[dynnav_tasks.NumpyWrapper])

Forking: gymnasium's ``AsyncVectorEnv`` creates one env in the parent process to read the
spaces, closes it and then forks its workers. A SAPIEN scene that is still waiting for Python's
garbage collector at that moment would be collected in the child, whose copy of the Vulkan
renderer has lost its threads, and the child would hang. ``NavEnv.close`` therefore frees its
scene at once, and a garbage collection runs before every fork.
"""

from __future__ import annotations

import gc
import os
from functools import partial

import gymnasium as gym
from mani_skill.utils.registration import REGISTERED_ENVS

from .wrappers import NumpyWrapper


def make_task(task_id: str, **kwargs) -> gym.Env:
    """gymnasium's entry point of every dynnav task: the task as ManiSkill makes it."""
    return REGISTERED_ENVS[task_id].make(**kwargs)


def make_vector_task(task_id: str, num_envs: int = 1, **kwargs) -> gym.vector.SyncVectorEnv:
    """gymnasium's vector entry point of every dynnav task (``make_vec``'s default mode):
    ``num_envs`` plain sub-environments, ``NumpyWrapper(gymnasium.make(task_id, **kwargs))``."""
    if isinstance(num_envs, bool) or not isinstance(num_envs, int) or num_envs < 1:
        raise ValueError(f"num_envs must be a positive integer, got {num_envs!r}")
    return gym.vector.SyncVectorEnv([partial(_make_plain, task_id, kwargs)] * num_envs)


def _make_plain(task_id: str, kwargs: dict) -> gym.Env:
    return NumpyWrapper(gym.make(task_id, **kwargs))


def make_plain_task(task_id: str, **kwargs) -> gym.Env:
    """The plain gymnasium env of a task (``NumpyWrapper``: numpy, unbatched), for a spec whose
    entry point must be a string (``"dynnav_tasks.registration:make_plain_task"`` with
    ``task_id`` in its kwargs), such as a Minari data set's. (Importing this module imports
    ``dynnav_tasks``, which registers the tasks, so a fresh process can make one from the string.)"""
    return _make_plain(task_id, kwargs)


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
            vector_entry_point=partial(make_vector_task, task_id),
        )


if hasattr(os, "register_at_fork"):
    os.register_at_fork(before=gc.collect)
