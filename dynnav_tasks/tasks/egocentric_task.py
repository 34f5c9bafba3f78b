"""``EgocentricTask``: what the tasks whose state is the egocentric one share (procedural, crowd, map).

The state (``egocentric.py``): the lasers, the target, with ``way`` the way to the target through
the static layout (``way_sense.py``), with ``odometry`` the robot's own last move, the
``obstacle_k`` nearest moving boxes and the ``human_k`` nearest pedestrians. A task mixes this class in before ``NavEnv`` and calls
``set_egocentric_options`` in its ``__init__`` before ``NavEnv.__init__``.
"""

from __future__ import annotations

import numbers
from typing import Optional

import gymnasium as gym
import numpy as np

from ..egocentric import egocentric_layout, egocentric_space, egocentric_state
from ..generation.spec import MAX_MOVING_OBSTACLES, MAX_PEDESTRIANS
from ..snapshot import StepSnapshot
from ..way_sense import WaySense


def _slots(value, name: str, high: int, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not 0 <= value <= high:
        raise ValueError(f"{name} must be an integer from 0 to {high} (the {what} the state describes); got {value!r}")
    return int(value)


class EgocentricTask:
    """The egocentric state of a ``NavEnv`` (module docstring)."""

    obstacle_k: int = 0
    way: bool = False
    human_k: int = 0
    odometry: bool = False

    def set_egocentric_options(self, obstacle_k: int = 0, way: bool = False, human_k: int = 0,
                               odometry: bool = False) -> None:
        """Check and keep the state's options (a ValueError names a bad one)."""
        self.obstacle_k = _slots(obstacle_k, "obstacle_k", MAX_MOVING_OBSTACLES, "moving obstacles")
        self.human_k = _slots(human_k, "human_k", MAX_PEDESTRIANS, "pedestrians")
        if not isinstance(way, bool):
            raise ValueError(f"way must be True or False (the way through the static layout in the state); got {way!r}")
        self.way = way
        if not isinstance(odometry, bool):
            raise ValueError(f"odometry must be True or False (the robot's own move over the last step in the state); "
                             f"got {odometry!r}")
        self.odometry = odometry
        self._way: Optional[WaySense] = None  # the current world's way sense, made on first use
        self._before: Optional[StepSnapshot] = None

    def _take_snapshot(self, step, contact, previous, placed=False) -> StepSnapshot:
        # a simulated step: velocities from the snapshot before it, as the agent perceived it
        self._before = self.observed_snapshot if contact is None else None
        return super()._take_snapshot(step, contact, previous, placed)

    def task_state_vector(self) -> np.ndarray:
        """The egocentric state (``egocentric.py``), float32."""
        s = self.observed_snapshot
        return egocentric_state(s, self._before, self.obstacle_k, self.way_reading(s) if self.way else None,
                                self.human_k, self.odometry)

    def way_reading(self, snapshot: StepSnapshot) -> tuple[float, float, float]:
        """The way to the target through this world's static layout from ``snapshot``'s pose
        (``way_sense.WaySense.read``: length, sin and cos of the bearing ahead on it)."""
        if self._way is None:
            self._way = WaySense(self.world)
        x, y, yaw = snapshot.pose
        return self._way.read(x, y, yaw, *snapshot.target_xy)

    def task_state_space(self) -> gym.spaces.Box:
        """Bounds of the egocentric state (``egocentric.egocentric_space``)."""
        lasers = self._sensing.lasers
        return egocentric_space(len(lasers.angles), lasers.max_range, self.obstacle_k, self.way, self.human_k,
                                self.odometry)

    def task_state_layout(self) -> list[tuple[str, int]]:
        """Names and sizes of the parts of the egocentric state, in order."""
        return egocentric_layout(len(self._sensing.lasers.angles), self.obstacle_k, self.way, self.human_k,
                                self.odometry)
