"""The laser ring: PhysX ray casts in the robot's laser plane.

The study's ring (the default) has 16 rays over the full circle and a 5 m range; the task
options ``laser_rays``, ``laser_fov_deg`` and ``laser_range`` (``LaserConfig``) change them.
Ray ``k`` of ``n`` points, relative to the robot's heading (counter-clockwise):

* full circle (``laser_fov_deg=360``): at ``360 k / n`` degrees: ray 0 straight ahead, as
  in the study;
* a field of view ``fov`` below 360: at ``-fov/2 + fov k / (n - 1)`` degrees, from the
  right edge to the left edge with both edges included, as a ROS ``LaserScan`` from
  ``angle_min`` to ``angle_max`` (one ray alone points straight ahead).

A reading is the distance in metres from the robot's centre to the first surface the ray
meets, capped at the range when it meets nothing; readings are not normalised.

A ray that started inside the robot's own collision shapes would hit them at distance 0, so
each ray starts just outside the footprint rectangle along its own direction, and the part
of the ray inside the footprint is added back.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np
import sapien

NUM_LASERS = 16
"""rays of the study's ring (the default)"""
LASER_RANGE = 5.0
"""metres: the study's range (the default)"""
MAX_LASER_RAYS = 4096
"""the most rays a ring may have (a 2D lidar has at most a few thousand)"""
MIN_LASER_RANGE = 0.5
"""metres: the shortest range; every ray must reach beyond the robot's own footprint (0.3 m)"""
MAX_LASER_RANGE = 100.0
"""metres: the longest range (no arena is 30 m across)"""
_START_MARGIN = 0.005  # m beyond the footprint's edge


def _number(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return float(value)


@dataclass(frozen=True)
class LaserConfig:
    """The laser ring of a task: its task options ``laser_rays``, ``laser_fov_deg`` and
    ``laser_range`` (the defaults are the study's ring)."""

    rays: int = NUM_LASERS
    """task option ``laser_rays``: how many rays, 1 to ``MAX_LASER_RAYS``"""
    fov_deg: float = 360.0
    """task option ``laser_fov_deg``: the field of view in degrees, in (0, 360]; 360 is the
    full circle, less is a fan centred on the heading (see the module docstring)"""
    max_range: float = LASER_RANGE
    """task option ``laser_range``: the reading of a ray that meets nothing (m), from
    ``MIN_LASER_RANGE`` to ``MAX_LASER_RANGE``"""

    @classmethod
    def of(cls, laser_rays=NUM_LASERS, laser_fov_deg=360.0, laser_range=LASER_RANGE) -> "LaserConfig":
        """The config of the task options, validated: a ValueError names a bad option."""
        if isinstance(laser_rays, bool) or not isinstance(laser_rays, numbers.Integral):
            raise ValueError(f"laser_rays must be an integer from 1 to {MAX_LASER_RAYS}, got {laser_rays!r}")
        if not 1 <= laser_rays <= MAX_LASER_RAYS:
            raise ValueError(f"laser_rays must be from 1 to {MAX_LASER_RAYS}, got {laser_rays!r}")
        fov = _number(laser_fov_deg, "laser_fov_deg")
        if not 0.0 < fov <= 360.0:
            raise ValueError(f"laser_fov_deg must be > 0 and <= 360 (degrees), got {laser_fov_deg!r}")
        reach = _number(laser_range, "laser_range")
        if not MIN_LASER_RANGE <= reach <= MAX_LASER_RANGE:
            raise ValueError(f"laser_range must be from {MIN_LASER_RANGE} to {MAX_LASER_RANGE} m (a ray starts "
                             f"beyond the robot's own footprint), got {laser_range!r}")
        return cls(int(laser_rays), fov, reach)

    @property
    def full_circle(self) -> bool:
        """Do the rays cover the whole circle (``fov_deg`` 360)?"""
        return self.fov_deg == 360.0

    def angles(self) -> np.ndarray:
        """Each ray's direction relative to the robot's heading (rad), in ray order."""
        n = self.rays
        if self.full_circle:
            return 2 * math.pi * np.arange(n) / n  # the study's ring, to the last bit
        if n == 1:
            return np.zeros(1)
        fov = math.radians(self.fov_deg)
        return -fov / 2 + fov * np.arange(n) / (n - 1)


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
    """Casts the rays of ``config`` (default: the study's 16) around a planar robot pose in a
    PhysX CPU scene."""

    def __init__(
        self,
        physx_system: sapien.physx.PhysxCpuSystem,
        half_length: float,
        half_width: float,
        height: float,
        config: LaserConfig = LaserConfig(),
    ):
        self.px = physx_system
        self.config = config
        self.height = float(height)
        self.max_range = float(config.max_range)
        self.angles = config.angles()
        num_rays = len(self.angles)
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
        """Readings for a robot at (x, y) facing ``yaw``; a float32 array, one per ray."""
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
