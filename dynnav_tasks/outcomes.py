"""How an episode ended: the one classifier of outcomes.

``NavEnv.evaluate`` (``outcome()`` in Python values, the ``info`` of every step) is the single
source of success and failure; ``outcome_of`` only names what it reported on the episode's
last step:

==============  ==========================================================================
outcome         when
==============  ==========================================================================
``success``     ``info["success"]``: the robot reached the target (terminated)
``collision``   ``info["collision"]``: the robot touched a wall or an obstacle (terminated)
``timeout``     neither, and the episode was truncated (the 200-step limit)
``terminated``  neither, but the episode was terminated: another environment's own ending
                (a dynnav task never ends this way)
==============  ==========================================================================

``info`` may be the plain dict of ``NumpyWrapper`` (Python values), the numpy one of
ManiSkill's ``CPUGymWrapper``, or ManiSkill's batched one (one-element tensors); an
environment that reports neither key (not a dynnav task) gives ``timeout`` or ``terminated``.
"""

from __future__ import annotations

from typing import Mapping

OUTCOMES = ("success", "collision", "timeout", "terminated")
"""Every outcome ``outcome_of`` can return; the first three are a dynnav task's."""


def _flag(info: Mapping, key: str) -> bool:
    value = info.get(key, False)
    if hasattr(value, "reshape"):  # a numpy array or a torch tensor of one element
        if value.reshape(-1).shape[0] != 1:
            raise ValueError(f"info[{key!r}] holds {tuple(value.shape)} values: pass one environment's info, "
                             "not a vector environment's")
        value = value.reshape(-1)[0]
    return bool(value)


def outcome_of(info: Mapping, terminated: bool = False) -> str:
    """The outcome (one of ``OUTCOMES``) of an episode whose last step returned ``info``.

    ``terminated``: that step's ``terminated`` flag; only an episode that neither succeeded
    nor collided needs it, to tell another environment's ending from a timeout.
    """
    if _flag(info, "success"):
        return "success"
    if _flag(info, "collision"):
        return "collision"
    return "terminated" if terminated else "timeout"
