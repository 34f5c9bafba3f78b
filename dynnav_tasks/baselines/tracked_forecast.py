"""What a robot that reads only its sensors can forecast of the moving boxes, for a planner.

The full-state planner (``state_planner.ObstacleForecast``) knows how every box moves: its
route, its turning points, its area. A robot that reads the egocentric state knows much less:
the ``k`` nearest boxes, where they are and how far each moved in the last step. A
``TrackedForecast`` gives the planner that much and no more:

* only the ``k`` boxes nearest the robot (by centre, as ``egocentric.py`` picks them) exist;
  the others are unseen;
* each moves on at the velocity of its last step (0 on the first step of an episode), and its
  place grows less certain by ``SPREAD`` metres per step ahead, so that a box that turns or
  slows can still be avoided when it stays near its line.

Planning with it measures how far a navigator that reads the egocentric state can get with
perfect planning: the part of a learner's gap to the full-state planner that its observation
explains (``StatePlanner(tracked=k)``, ``--tracked K`` on the planner's command line).
"""

from __future__ import annotations

from typing import Optional

import numpy as np

SPREAD = 0.03
"""metres per step ahead by which a tracked box's possible place grows on every side"""
UNSEEN = 1e6
"""where an unseen box is put (no search node comes near)"""


class TrackedForecast:
    """The ``k`` nearest boxes at constant velocity (module docstring), as ``ObstacleForecast`` boxes."""

    def __init__(self, world, k: int, spread: float = SPREAD):
        self.k, self.spread = int(k), float(spread)
        halves = []
        for group in world.obstacles:
            if group.moving:
                halves += [np.asarray(group.half_size, float)] * group.count
        self.half = np.array(halves).reshape(-1, 2)
        self.previous: Optional[np.ndarray] = None

    def reset(self) -> None:
        self.previous = None

    def boxes(self, xy: np.ndarray, horizon: int, robot=None) -> np.ndarray:
        """(horizon + 1, n, 2, 2): for step t, the box each obstacle may cover between steps t - 1
        and t, grown by its half size; unseen obstacles far away. ``robot``: its (x, y)."""
        n = len(xy)
        out = np.full((horizon + 1, n, 2, 2), UNSEEN)
        velocity = xy - self.previous if self.previous is not None else np.zeros_like(xy)
        self.previous = xy.copy()
        if n == 0 or self.k == 0:
            return out
        nearest = np.argsort(((xy - np.asarray(robot, float)) ** 2).sum(1), kind="stable")[:self.k]
        t = np.arange(horizon + 1)[:, None, None]
        centres = xy[nearest][None] + t * velocity[nearest][None]  # (horizon + 1, k, 2)
        reach = self.half[nearest][None] + t * self.spread
        lo, hi = centres - reach, centres + reach
        lo[1:], hi[1:] = np.minimum(lo[:-1], lo[1:]), np.maximum(hi[:-1], hi[1:])  # swept between steps
        out[:, nearest, 0], out[:, nearest, 1] = lo, hi
        return out
