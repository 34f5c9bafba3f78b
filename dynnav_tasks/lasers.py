"""The 16-laser ring: PhysX ray casts in the robot's laser plane.

Ray ``k`` points at ``yaw + 2 pi k / n`` (ray 0 straight ahead, counter-clockwise). A reading
is the distance in metres from the robot's centre to the first surface the ray meets, capped
at ``max_range`` (5 m) when it meets nothing; readings are not normalised.

A ray that started inside the robot's own collision shapes would hit them at distance 0, so
each ray starts just outside the footprint rectangle along its own direction, and the part
of the ray inside the footprint is added back to the reading.
"""

from __future__ import annotations

import math

import numpy as np
import sapien

NUM_LASERS = 16
LASER_RANGE = 5.0
_START_MARGIN = 0.005  # m beyond the footprint's edge


def footprint_exit_distance(angle: float, half_length: float, half_width: float) -> float:
    """Distance from a rectangle's centre to its edge along ``angle`` (rectangle frame)."""
    c, s = abs(math.cos(angle)), abs(math.sin(angle))
    candidates = []
    if c > 1e-12:
        candidates.append(half_length / c)
    if s > 1e-12:
        candidates.append(half_width / s)
    return min(candidates)


class LaserRing:
    """Casts ``num_rays`` rays around a planar robot pose in a PhysX CPU scene."""

    def __init__(
        self,
        physx_system: sapien.physx.PhysxCpuSystem,
        half_length: float,
        half_width: float,
        height: float,
        num_rays: int = NUM_LASERS,
        max_range: float = LASER_RANGE,
    ):
        self.px = physx_system
        self.height = float(height)
        self.max_range = float(max_range)
        self.angles = 2 * math.pi * np.arange(num_rays) / num_rays
        self.start = np.array(
            [footprint_exit_distance(a, half_length, half_width) + _START_MARGIN for a in self.angles]
        )
        n = num_rays
        # per-ray constants as Python floats, and buffers whose rows are passed to PhysX
        self._starts = self.start.tolist()
        self._reaches = [self.max_range - s for s in self._starts]
        self._dirs = np.zeros((n, 3), dtype=np.float32)
        self._origins = np.full((n, 3), self.height, dtype=np.float32)
        self._offsets = np.empty((n, 2))
        self._start_xy = np.repeat(self.start[:, None], 2, axis=1)
        self._xy = np.empty(2)
        self._yaw = None  # the heading the directions and offsets were computed for
        self._rays = list(zip(list(self._origins), list(self._dirs), self._reaches, self._starts))

    def read(self, x: float, y: float, yaw: float) -> np.ndarray:
        """Readings for a robot at (x, y) facing ``yaw``; a float32 array of ``num_rays``."""
        dirs, offsets, xy = self._dirs, self._offsets, self._xy
        if yaw != self._yaw:  # (the same heading, as after a straight move, needs none of this)
            world = self.angles + yaw
            dirs[:, 0] = np.cos(world)
            dirs[:, 1] = np.sin(world)
            np.multiply(self._start_xy, dirs[:, :2], out=offsets)  # start * direction in float64,
            self._yaw = yaw
        xy[0], xy[1] = x, y
        np.add(offsets, xy, out=self._origins[:, :2], casting="same_kind")  # + (x, y), then float32
        raycast, rng = self.px.raycast, self.max_range
        out = []
        for origin, direction, reach, start in self._rays:
            hit = raycast(origin, direction, reach)
            out.append(start + hit.distance if hit is not None else rng)
        return np.array(out, dtype=np.float32)
