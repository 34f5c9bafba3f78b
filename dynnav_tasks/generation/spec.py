"""``WorldSpec``: what a generated world may look like, validated field by field.

A spec holds ranges, not values: ``generate_world`` draws one world from it per seed (an
arena size in ``arena_size``, one layout of ``layout``, a moving obstacle count in
``moving_obstacles``, ...). Every field is checked when the spec is made (also by
``dataclasses.replace``); a bad value is a ``GenerationError`` that names the field, says
what was wrong and what is allowed.

Lengths are metres; speeds are multiples of the robot's forward step (0.15 m per control
step), so ``relative_speed=(0.5, 1.0)`` means 0.075-0.15 m per step.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from ..errors import close_matches_message
from ..robot import CAMERA_OFFSET, FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, MAX_FORWARD_STEP, DriveConfig

BLOCK_HALF = 0.25
"""half side (m) of every generated obstacle: static blocks and moving boxes are 0.5 m cubes"""
BLOCK = 2 * BLOCK_HALF
"""side (m) of the block lattice: static blocks sit on cells of this size from the arena's corner"""
MAX_STATIC_BLOCKS = 600
"""no generated world has more static blocks"""
MAX_MOVING_OBSTACLES = 30
"""no generated world has more moving obstacles (bodies)"""
ARENA_SIDE_RANGE = (6.0, 20.0)
"""smallest and largest arena side (m)"""
MAX_LAYOUT_DENSITY = 0.3
"""largest fraction of the arena's block cells that clutter may cover"""
MAX_TARGET_DISTANCE = 20.0
"""longest way (m) from the start to a target: 133 forward steps of an episode's 200"""
AREA_PER_MOVING_OBSTACLE = 2.0
"""floor area (m^2) an arena needs per moving obstacle: an arena of area A holds at most
floor(A / 2.0) of them (18 in a 6 m x 6 m arena)"""

ROBOT_STEP = DriveConfig.forward_step
"""the robot's forward step (m per control step): the unit of ``relative_speed``"""
MAX_RELATIVE_SPEED = MAX_FORWARD_STEP / ROBOT_STEP
"""fastest obstacle, in robot steps: 0.5 m per step, the fastest the collision check allows"""
ROBOT_RADIUS = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)
"""radius (m) of the circle around the robot's whole footprint (0.295 m): the robot fits in it
at every heading"""
CAMERA_HEIGHT = CAMERA_OFFSET[2]
"""height (m) of the front camera's lens above the floor"""

MAX_PEDESTRIANS = 20
"""no generated world has more pedestrians"""
PEDESTRIAN_MODELS = ("orca", "social_force")
"""the pedestrians' motion models (``dynnav_tasks.crowd``)"""

LAYOUTS = ("open", "clutter", "corridors", "rooms")
MOTIONS = ("back_and_forth", "route", "random_in_rect")
TARGET_MOTIONS = ("static", "moving")


class GenerationError(ValueError):
    """A spec, seed or name that no world can be generated from; ``field`` names the culprit."""

    def __init__(self, message: str, field: str | None = None):
        super().__init__(message)
        self.field = field


@dataclass(frozen=True)
class WorldSpec:
    """The distribution a generated world is drawn from (see the module docstring for units)."""

    arena_size: tuple[float, float] = (8.0, 12.0)
    """range of each arena side (m), drawn independently for x and y; within 6-20 m"""
    layout: tuple[str, ...] = ("clutter",)
    """the static layouts to draw from (one per world, uniformly; a name may repeat to weigh
    it): "open" (no blocks), "clutter" (scattered blocks and small clusters), "corridors"
    (parallel walls of blocks with doorways), "rooms" (a grid of rooms, a doorway in every
    shared wall). A single name is accepted and stored as a one-name tuple"""
    layout_density: tuple[float, float] = (0.05, 0.12)
    """range of the fraction of block cells covered by clutter (0-0.3): all of it in "clutter",
    half of it inside "corridors" and "rooms" (never in a doorway), none in "open\""""
    moving_obstacles: tuple[int, int] = (3, 8)
    """range of the number of moving 0.5 m boxes (0-30, inclusive), drawn uniformly; at most one
    per ``AREA_PER_MOVING_OBSTACLE`` (2 m^2) of the smallest arena"""
    motion_mix: tuple[str, ...] = MOTIONS
    """motion models of the moving obstacles, one drawn per obstacle group uniformly (repeat a
    name to weigh it): "back_and_forth" (``BackAndForth`` along a 1-4 m segment),
    "route" (``Route``: one or two boxes on a rectangular loop), "random_in_rect"
    (``RandomInRect`` in a rectangle)"""
    relative_speed: tuple[float, float] = (0.3, 1.0)
    """range of the obstacles' speed in robot forward steps (0 < low <= high <= 3.33, i.e. at
    most 0.5 m per step)"""
    target_motion: tuple[str, ...] = ("static",)
    """"static" and/or "moving" (a ``BackAndForth`` or ``RandomInRect`` target at 0.3-0.6 robot
    steps), one drawn per world"""
    target_distance: tuple[float, float] = (3.0, 9.0)
    """range of the length (m) of the way from the start point to the target (its motion's
    centre) through the static layout, measured on the occupancy grid in steps along x and y
    (``validity.within_steps``); the low end at least 1 m and at most 0.7 of the smallest arena
    side, the high end at most 20 m (about 135 of an episode's 200 steps driving forward)"""
    camera: bool = False
    """a camera world: the target carries its red marker (``World.target_marker``) and is
    visible from the start (see ``validity.marker_visible``)"""
    pedestrians: tuple[int, int] = (0, 0)
    """range of the number of pedestrians (0-20, inclusive), drawn uniformly: 0.3 m cylinders
    walking in the world's free space at 0.75 m/s (``dynnav_tasks.crowd``, scenario
    "free_space"), invisible to the robot's presence; at most one per
    ``AREA_PER_MOVING_OBSTACLE`` of the smallest arena, as the moving boxes"""
    pedestrian_model: tuple[str, ...] = ("orca",)
    """the pedestrians' motion model, one drawn per world: "orca" and/or "social_force\""""

    def __post_init__(self):
        for name in ("layout", "motion_mix", "target_motion", "pedestrian_model"):  # a name, or a list of names
            value = getattr(self, name)
            if isinstance(value, (str, list)):
                object.__setattr__(self, name, (value,) if isinstance(value, str) else tuple(value))
        for name in ("arena_size", "layout_density", "moving_obstacles", "relative_speed", "target_distance",
                     "pedestrians"):
            value = getattr(self, name)  # a number means (number, number); a list a tuple
            if isinstance(value, numbers.Real) and not isinstance(value, bool):
                object.__setattr__(self, name, (value, value))
            elif isinstance(value, list):
                object.__setattr__(self, name, tuple(value))
        self._validate()

    def _validate(self) -> None:
        low, high = _real_range(self, "arena_size", *ARENA_SIDE_RANGE, "m")
        _names(self, "layout", LAYOUTS, "layout")
        _real_range(self, "layout_density", 0.0, MAX_LAYOUT_DENSITY, "")
        _, n_high = _int_range(self, "moving_obstacles", 0, MAX_MOVING_OBSTACLES)
        fit = int(low * low // AREA_PER_MOVING_OBSTACLE)
        if n_high > fit:
            raise GenerationError(
                f"WorldSpec.moving_obstacles: at most {fit} moving obstacles fit in the smallest arena of "
                f"arena_size ({low:g} m x {low:g} m, one per {AREA_PER_MOVING_OBSTACLE:g} m^2); got up to {n_high}. "
                "Lower moving_obstacles or raise arena_size.",
                "moving_obstacles",
            )
        _, p_high = _int_range(self, "pedestrians", 0, MAX_PEDESTRIANS)
        if p_high > fit:
            raise GenerationError(
                f"WorldSpec.pedestrians: at most {fit} pedestrians fit in the smallest arena of arena_size "
                f"({low:g} m x {low:g} m, one per {AREA_PER_MOVING_OBSTACLE:g} m^2); got up to {p_high}. "
                "Lower pedestrians or raise arena_size.",
                "pedestrians",
            )
        _names(self, "pedestrian_model", PEDESTRIAN_MODELS, "pedestrian model")
        _names(self, "motion_mix", MOTIONS, "motion model")
        s_low, _ = _real_range(self, "relative_speed", 0.0, MAX_RELATIVE_SPEED, "robot steps")
        if s_low <= 0:
            raise GenerationError(
                f"WorldSpec.relative_speed must be above 0 (a moving obstacle moves); got {self.relative_speed!r}",
                "relative_speed",
            )
        _names(self, "target_motion", TARGET_MOTIONS, "target motion")
        d_low, _ = _real_range(self, "target_distance", 1.0, MAX_TARGET_DISTANCE, "m")
        if d_low > 0.7 * low:
            raise GenerationError(
                f"WorldSpec.target_distance: its low end ({d_low:g} m) must be at most 0.7 of the smallest "
                f"arena side ({low:g} m), or no target fits; lower it or raise arena_size",
                "target_distance",
            )
        if not isinstance(self.camera, bool):
            raise GenerationError(f"WorldSpec.camera must be True or False; got {self.camera!r}", "camera")


def _real_range(spec: WorldSpec, name: str, low: float, high: float, unit: str) -> tuple[float, float]:
    """Check that field ``name`` is a (low, high) pair of finite numbers within [low, high]."""
    value = getattr(spec, name)
    unit = f" {unit}" if unit else ""
    if (
        not isinstance(value, tuple) or len(value) != 2
        or any(isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v) for v in value)
    ):
        raise GenerationError(
            f"WorldSpec.{name} must be a (low, high) pair of finite numbers; got {value!r}", name
        )
    a, b = float(value[0]), float(value[1])
    if not (low <= a <= b <= high):
        raise GenerationError(
            f"WorldSpec.{name} must satisfy {low:g} <= low <= high <= {high:.4g}{unit}; got {value!r}", name
        )
    return a, b


def _int_range(spec: WorldSpec, name: str, low: int, high: int) -> tuple[int, int]:
    """Check that field ``name`` is a (low, high) pair of integers within [low, high]."""
    value = getattr(spec, name)
    if (
        not isinstance(value, tuple) or len(value) != 2
        or any(isinstance(v, bool) or not isinstance(v, numbers.Integral) for v in value)
    ):
        raise GenerationError(f"WorldSpec.{name} must be a (low, high) pair of integers; got {value!r}", name)
    a, b = int(value[0]), int(value[1])
    if not (low <= a <= b <= high):
        raise GenerationError(f"WorldSpec.{name} must satisfy {low} <= low <= high <= {high}; got {value!r}", name)
    return a, b


def _names(spec: WorldSpec, name: str, valid: tuple[str, ...], what: str) -> None:
    """Check that field ``name`` is a non-empty tuple of names from ``valid``."""
    value = getattr(spec, name)
    if not isinstance(value, tuple) or not value:
        raise GenerationError(f"WorldSpec.{name} must be a name or a non-empty tuple of names; got {value!r}", name)
    for v in value:
        if v not in valid:
            raise GenerationError(
                f"WorldSpec.{name}: unknown {what} {v!r}. " + close_matches_message(v, valid, what), name
            )
