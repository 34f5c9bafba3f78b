"""Declarative description of a navigation world: arena, obstacles, targets, start area.

A task file builds one ``World`` from these pieces; ``NavEnv`` turns it into a SAPIEN scene.
Coordinates are metres in the world frame (right-handed, z up). Obstacles are boxes standing
on the floor, tall enough (0.5 m) for the laser plane (0.30 m) to hit them; targets are flat
discs with no collision shape. In the camera worlds (``World.target_marker``) a red column,
also with no collision shape, stands on the chosen target so the camera sees it from afar.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .crowd.crowd import Pedestrians
from .motion import Motion, Static

RGBA = tuple[float, float, float, float]

# The palette, as every camera sees it (sRGB, 0-1): ``scene.py`` lights the scene evenly, so a
# surface shows its colour from every side and distance. Walls are coloured by side so a camera can tell
# directions apart, and every colour has its own gray level (ITU-R 601 luma, the one
# ``wrappers.to_gray`` uses) so gray frames tell them apart too:
#   target 0.30 < static box 0.43 < west 0.48 < north 0.56 < east 0.63 < south 0.69
#   < pedestrian 0.75 < moving box 0.80 < floor 0.88
WALL_COLORS: dict[str, RGBA] = {
    "north": (0.20, 0.70, 0.75, 1.0),  # y = y_max: teal
    "south": (0.98, 0.63, 0.24, 1.0),  # y = y_min: orange
    "east": (0.45, 0.78, 0.32, 1.0),  # x = x_max: green
    "west": (0.68, 0.32, 0.80, 1.0),  # x = x_min: purple
}
STATIC_OBSTACLE_COLOR: RGBA = (0.26, 0.42, 0.90, 1.0)  # blue, as in the thesis
MOVING_OBSTACLE_COLOR: RGBA = (0.94, 0.84, 0.20, 1.0)  # yellow, as in the thesis
TARGET_COLOR: RGBA = (1.0, 0.0, 0.0, 1.0)  # red: the disc and, in camera worlds, its marker
PEDESTRIAN_COLOR: RGBA = (0.95, 0.65, 0.70, 1.0)  # pink
FLOOR_COLOR: RGBA = (0.88, 0.88, 0.87, 1.0)


@dataclass(frozen=True)
class Arena:
    """A rectangular floor closed by four walls whose inner faces lie on the given ranges."""

    x_range: tuple[float, float]
    y_range: tuple[float, float]
    wall_thickness: float = 0.1
    wall_height: float = 0.5

    @property
    def center(self) -> np.ndarray:
        return np.array([sum(self.x_range) / 2, sum(self.y_range) / 2])

    @property
    def size(self) -> np.ndarray:
        return np.array([self.x_range[1] - self.x_range[0], self.y_range[1] - self.y_range[0]])

    def walls(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Wall name -> (centre xy, half size xy), walls overlapping at the corners."""
        (x0, x1), (y0, y1), t = self.x_range, self.y_range, self.wall_thickness
        cx, cy = self.center
        hx, hy = (x1 - x0) / 2 + t, (y1 - y0) / 2 + t
        return {
            "north": (np.array([cx, y1 + t / 2]), np.array([hx, t / 2])),
            "south": (np.array([cx, y0 - t / 2]), np.array([hx, t / 2])),
            "east": (np.array([x1 + t / 2, cy]), np.array([t / 2, hy])),
            "west": (np.array([x0 - t / 2, cy]), np.array([t / 2, hy])),
        }


@dataclass(frozen=True)
class Obstacles:
    """One or more box obstacles of one size, placed or moved by ``motion``."""

    half_size: tuple[float, float]
    motion: Motion
    height: float = 0.5

    @property
    def moving(self) -> bool:
        return not isinstance(self.motion, Static)

    @property
    def count(self) -> int:
        return self.motion.count


@dataclass(frozen=True)
class StartArea:
    """Where the robot starts: uniform in the rectangle, heading uniform in ``yaw_range``."""

    x_range: tuple[float, float]
    y_range: tuple[float, float]
    yaw_range: tuple[float, float] = (-math.pi, math.pi)

    def sample(self, rng: np.random.Generator) -> tuple[float, float, float]:
        return (
            float(rng.uniform(*self.x_range)),
            float(rng.uniform(*self.y_range)),
            float(rng.uniform(*self.yaw_range)),
        )


CAMERA_WORLD_BOX_SPEED = (0.05, 0.15)
"""Step lengths (m per step) of the wandering boxes of the camera worlds 5.5b and 5.5c: no
faster than the robot (0.15 m per step), so that a box that can reach the robot was in the
front camera's view for a step or more before (the laser worlds' boxes go up to 0.5 m)."""

STANDARD_ARENA = Arena(x_range=(-2.0, 4.5), y_range=(-2.0, 4.5))
"""6.5 m x 6.5 m: the thesis's target coordinates with room around them."""
STANDARD_START = StartArea(x_range=(-0.9, -0.4), y_range=(-0.9, -0.4), yaw_range=(-math.pi / 4, 3 * math.pi / 4))
"""South-west, 1.1 m or more from the walls, heading into the arena (+-90 deg of north-east):
a robot never starts facing a wall it cannot turn away from in time."""


_MAP_READER = None
"""``map_world.world_from_map``, installed by ``install_map_reader`` when ``dynnav_tasks`` is imported"""


def install_map_reader(reader) -> None:
    """Make ``reader`` (``map_world.world_from_map``) what ``World.from_occupancy_map`` calls."""
    global _MAP_READER
    _MAP_READER = reader


@dataclass(frozen=True)
class World:
    """Everything a navigation task places in its scene.

    ``targets`` lists candidate targets (each a one-body motion); one is chosen uniformly per
    episode. ``obstacles`` lists obstacle groups; the positions of moving obstacles enter the
    state vector in the order listed.
    """

    targets: tuple[Motion, ...]
    obstacles: tuple[Obstacles, ...] = field(default_factory=tuple)
    arena: Arena = STANDARD_ARENA
    start: StartArea = STANDARD_START
    target_marker: bool = False
    """stand a tall red column (visual only, see ``scene.TargetMarker``) on the chosen target, so
    that a camera sees it from anywhere in the arena; the camera worlds set this"""
    pedestrians: Optional[Pedestrians] = None
    """a crowd walking in the arena (``crowd.crowd``): upright cylinders the lasers and the camera
    see, moved each step by their motion model; touching one ends the episode as a human collision"""

    @classmethod
    def from_occupancy_map(cls, path, start=None, target=None, **options) -> "World":
        """The world of a ROS ``map_server`` occupancy map (its YAML file): the map's occupied and
        unknown cells as static boxes, a start and targets given or drawn in its free space, and
        optionally moving boxes and pedestrians (``map_world.world_from_map`` lists the options;
        importing ``dynnav_tasks`` installs it here, as ``map_world`` builds on this module)."""
        if _MAP_READER is None:
            raise RuntimeError("import dynnav_tasks to read occupancy maps")
        return _MAP_READER(path, start, target, **options)

    def __post_init__(self):
        if not self.targets:
            raise ValueError("a World needs at least one target")
        for t in self.targets:
            if t.count != 1:
                raise ValueError(f"each target moves one body; got count={t.count} in {t}")

    def span(self) -> float:
        """Diagonal of the smallest rectangle holding the arena, the start area and every
        target's motion (m): no distance from the robot's centre to the target exceeds it."""
        lows = [np.array([self.arena.x_range[0], self.arena.y_range[0]]),
                np.array([self.start.x_range[0], self.start.y_range[0]])]
        highs = [np.array([self.arena.x_range[1], self.arena.y_range[1]]),
                 np.array([self.start.x_range[1], self.start.y_range[1]])]
        for target in self.targets:
            low, high = target.extent()
            lows.append(np.asarray(low, dtype=np.float64))
            highs.append(np.asarray(high, dtype=np.float64))
        size = np.max(highs, axis=0) - np.min(lows, axis=0)
        return float(math.hypot(*size))

    @property
    def moving_obstacle_count(self) -> int:
        return sum(o.count for o in self.obstacles if o.moving)
