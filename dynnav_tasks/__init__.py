"""dynnav_tasks: ManiSkill navigation tasks in dynamic worlds.

Importing the package registers every task with ManiSkill and gymnasium::

    import gymnasium as gym
    import dynnav_tasks

    env = gym.make("DynNav-MovingTarget-v1", obs_mode="state")   # batched torch, as ManiSkill
    env = dynnav_tasks.NumpyWrapper(env)                          # plain gymnasium: numpy, unbatched

``dynnav_tasks.make`` does the same as ``gym.make`` and, for an unknown task id, lists the
valid ones. ``TASK_IDS`` are the thesis's nine fixed worlds; ``PROCEDURAL_TASK_IDS`` the tasks
that generate a new world every episode (``DynNav-Procedural-v1``); ``CROWD_TASK_IDS`` the tasks
with pedestrians (``DynNav-Crowd-v1``); ``MAP_TASK_IDS`` those of a building's occupancy map
(``DynNav-Map-v1``). ``gym.make_vec(task_id, num_envs=n)`` gives observations of shape
``(n, state size)``; gymnasium's "sync" and "async" modes do with
``wrappers=[dynnav_tasks.NumpyWrapper]`` (see ``registration.py``). ``outcome_of(info,
terminated)`` names how an episode ended (``outcomes.py``).
"""

from __future__ import annotations

from mani_skill.utils.registration import REGISTERED_ENVS

from . import robot  # noqa: F401  (registers the agent)
from . import tasks  # noqa: F401  (registers the tasks)
from .errors import check_choice
from .nav_env import NavEnv
from .outcomes import OUTCOMES, outcome_of
from .registration import register_with_gymnasium
from .snapshot import StepSnapshot
from .wrappers import NumpyWrapper

_NAV_TASKS = tuple(uid for uid, spec in REGISTERED_ENVS.items() if issubclass(spec.cls, NavEnv))
PROCEDURAL_TASK_IDS = tuple(uid for uid in _NAV_TASKS if issubclass(REGISTERED_ENVS[uid].cls, tasks.ProceduralEnv))
"""The tasks whose world is generated anew every episode (``tasks/procedural.py``)."""
CROWD_TASK_IDS = tuple(uid for uid in _NAV_TASKS if issubclass(REGISTERED_ENVS[uid].cls, tasks.CrowdEnv))
"""The tasks of pedestrians crossing the robot's way (``tasks/crowd.py``)."""
MAP_TASK_IDS = tuple(uid for uid in _NAV_TASKS if issubclass(REGISTERED_ENVS[uid].cls, tasks.MapEnv))
"""The tasks that play a building's occupancy map (``tasks/building_map.py``)."""
TASK_IDS = tuple(uid for uid in _NAV_TASKS if uid not in PROCEDURAL_TASK_IDS + CROWD_TASK_IDS + MAP_TASK_IDS)
"""The thesis's worlds, in its order (5.1, 5.2, 5.3, 5.4a-c, 5.5a-c): one fixed world each."""
VISUAL_TASK_IDS = tuple(uid for uid in TASK_IDS if REGISTERED_ENVS[uid].cls.camera_world)
"""The camera worlds of the thesis (5.5a-c)."""
ALL_TASK_IDS = TASK_IDS + PROCEDURAL_TASK_IDS + CROWD_TASK_IDS + MAP_TASK_IDS
"""Every dynnav task id: the thesis's worlds, the procedural ones, the crowds."""
register_with_gymnasium(ALL_TASK_IDS)

__all__ = [
    "ALL_TASK_IDS", "CROWD_TASK_IDS", "MAP_TASK_IDS", "NavEnv", "NumpyWrapper", "OUTCOMES", "PROCEDURAL_TASK_IDS", "StepSnapshot", "TASK_IDS",
    "VISUAL_TASK_IDS", "check_choice", "make", "outcome_of",
]


def make(task_id: str, **kwargs):
    """``gymnasium.make(task_id, **kwargs)`` with a clear error for an unknown task id."""
    import gymnasium as gym

    check_choice(task_id, ALL_TASK_IDS, "task id")
    return gym.make(task_id, **kwargs)
