"""The way to the target through the static map: what a robot with a map and a global planner knows.

A robot in a building has the static map (from SLAM) and a global planner that routes through
it; its local planner follows that route (Nav2's global and local planners, BARN entries).
``WaySense`` gives a task that reading: the length of the way from the robot to the target
through the world's static layout (walls and static blocks, on ``WayGrid``'s occupancy grid
inflated by the robot's radius and the planners' margin), and the bearing of the point
``AHEAD`` (0.5 m) further along it. It knows no moving obstacle's place or motion: it is the
map, not the full-state planner's foresight.

* where the straight segment from the robot to the target is free on the grid, the way is
  that segment: its length is the distance and the point ahead lies on it (the target itself
  when nearer than ``AHEAD``);
* otherwise the way follows the grid's shortest way (``WayGrid.to``): its length from the
  robot's cell and the point ``AHEAD`` further along it. A robot in a cell the inflated map
  marks occupied (closer to a wall than the margin) reads from the nearest free cell, its
  distance to that cell added;
* a moving target: the way is planned anew when the target has left the ``REPLAN`` (0.5 m)
  square it was planned to, as a global planner replans now and then, not every step; the
  ways of a world are kept, so a target that comes back costs nothing.

The reading is three values, ``(length, sin, cos)`` of the bearing (> 0 to the left, as the
target's bearing), in ``egocentric.py``'s ``way`` part.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np
from scipy import ndimage

from .baselines.way_grid import WayGrid
from .robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH

CLEARANCE = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH) + 0.03
"""metres from every wall and block the way keeps the robot's centre: its footprint's circle
and the full-state planner's 3 cm margin (``StatePlanner.clearance``)"""
AHEAD = 0.5
"""metres along the way to the point whose bearing is read (``way_grid.AIM_AHEAD`` cells)"""
REPLAN = 0.5
"""metres: a moving target's way is planned again once it leaves this square"""


class WaySense:
    """The way through one world's static layout, read from the robot's pose (module docstring)."""

    def __init__(self, world, clearance: float = CLEARANCE):
        self.grid = WayGrid(world, clearance, lists=False)  # a few reads per step: numpy grids, no lists to build
        self._fields: dict[tuple[int, int], object] = {}

    @cached_property
    def _nearest(self) -> np.ndarray:
        """(2, nx, ny): for every cell, the nearest free cell (itself when free), where a robot too
        close to a wall reads from; computed when the straight way is first blocked."""
        if not self.grid.free.any():
            return np.indices(self.grid.free.shape)
        return ndimage.distance_transform_edt(~self.grid.free, return_indices=True)[1]

    def read(self, x: float, y: float, yaw: float, tx: float, ty: float) -> tuple[float, float, float]:
        """(length of the way from (x, y) to the target (tx, ty) in m, sin and cos of the
        bearing, relative to the heading ``yaw``, of the point ``AHEAD`` along it)."""
        d = math.hypot(tx - x, ty - y)
        if d <= AHEAD or self.grid.line_free((x, y), (tx, ty)):
            return d, *_sin_cos(math.atan2(ty - y, tx - x) - yaw)
        field = self._field(tx, ty)
        i, j = self.grid.cell_of(x, y)
        fi, fj = int(self._nearest[0][i, j]), int(self._nearest[1][i, j])
        cx, cy = self.grid.center(fi, fj) if (fi, fj) != (i, j) else (x, y)
        length = field.distance(cx, cy) + math.hypot(cx - x, cy - y)
        ax, ay = field.aim(cx, cy)
        return length, *_sin_cos(math.atan2(ay - y, ax - x) - yaw)

    def _field(self, tx: float, ty: float):
        key = (math.floor(tx / REPLAN), math.floor(ty / REPLAN))
        field = self._fields.get(key)
        if field is None:
            field = self._fields[key] = self.grid.to((tx, ty))
        return field


def _sin_cos(angle: float) -> tuple[float, float]:
    return math.sin(angle), math.cos(angle)
