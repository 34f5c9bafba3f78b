"""Motions of a generated world's moving obstacles and moving target, with the existing models.

Sizes (m) before any shrinking, all axis-aligned:

* ``BackAndForth`` obstacle: along x or y, amplitude 0.5-2.0 (a 1-4 m segment), one speed
  drawn from the spec's ``relative_speed``.
* ``Route`` obstacle: a rectangular loop of sides 1.0-3.0, clockwise or counter-clockwise,
  carrying one or two boxes (two when the count left allows it, half of the time); the
  ``Route`` draws its speed per episode from the spec's range.
* ``RandomInRect`` obstacle: a rectangle of sides 0.6-2.5; a step length per step from the
  spec's range.
* a moving target: a ``BackAndForth`` of amplitude 0.4-1.0 or a ``RandomInRect`` of sides
  0.6-1.5, at 0.3-0.6 robot steps (0.045-0.09 m per step), as the camera world 5.5c's.

An obstacle is placed by drawing its size and the centre of its extent (uniform where the
extent fits inside the walls) up to ``PLACEMENT_TRIES`` times, shrinking the sizes a little at
each try, until the extent passes the checks of ``validity`` (clear of blocks and walls, away
from the start area and the target).
"""

from __future__ import annotations

import numpy as np

from ..motion import BackAndForth, Motion, RandomInRect, Route
from .spec import BLOCK_HALF, ROBOT_STEP
from .validity import EXCLUSION, OBSTACLE_MARGIN, BlockIndex, rects_apart

SEGMENT_AMPLITUDE = (0.5, 2.0)
LOOP_SIDE = (1.0, 3.0)
AREA_SIDE = (0.6, 2.5)
TARGET_AMPLITUDE = (0.4, 1.0)
TARGET_AREA_SIDE = (0.6, 1.5)
TARGET_RELATIVE_SPEED = (0.3, 0.6)
PLACEMENT_TRIES = 40
_SHRINK = 0.6  # the last try's sizes are this fraction of the first's range

Rect = tuple[tuple[float, float], tuple[float, float]]


def _uniform(rng: np.random.Generator, low: float, high: float) -> float:
    return low + (high - low) * float(rng.random())


def _r(value: float) -> float:
    """Round to the millimetre, so a world's numbers print and compare exactly."""
    return round(float(value), 3)


def _extent_half(model: str, scale: float, rng: np.random.Generator) -> tuple[float, float]:
    """Half sizes (x, y) of the extent of a ``model`` motion, scaled by ``scale`` <= 1."""
    if model == "back_and_forth":
        a = _r(_uniform(rng, SEGMENT_AMPLITUDE[0], SEGMENT_AMPLITUDE[0] + (SEGMENT_AMPLITUDE[1] - SEGMENT_AMPLITUDE[0]) * scale))
        return (a, 0.0) if rng.integers(2) else (0.0, a)
    low, high = LOOP_SIDE if model == "route" else AREA_SIDE
    top = low + (high - low) * scale
    return _r(_uniform(rng, low, top) / 2), _r(_uniform(rng, low, top) / 2)


def _motion(model: str, center, half, count: int, speed: tuple[float, float], rng) -> Motion:
    """The motion spec of ``model`` whose extent is ``center`` +- ``half``."""
    (cx, cy), (hx, hy) = center, half
    if model == "back_and_forth":
        direction = (1.0, 0.0) if hx > 0 else (0.0, 1.0)
        return BackAndForth(center=(cx, cy), direction=direction, amplitude=max(hx, hy),
                            speed=_r(_uniform(rng, *speed)))
    x_range, y_range = (_r(cx - hx), _r(cx + hx)), (_r(cy - hy), _r(cy + hy))
    if model == "route":
        corners = ((x_range[0], y_range[0]), (x_range[1], y_range[0]), (x_range[1], y_range[1]), (x_range[0], y_range[1]))
        if rng.integers(2):
            corners = corners[::-1]
        return Route(waypoints=corners, speed_range=speed, count=count)
    return RandomInRect(x_range=x_range, y_range=y_range, speed_range=speed)


def place_obstacle(
    model: str, count: int, relative_speed: tuple[float, float], index: BlockIndex,
    keep_away: tuple[Rect, ...], rng: np.random.Generator,
) -> Motion | None:
    """A ``model`` motion of ``count`` boxes whose extent fits (see the module docstring), or
    None if ``PLACEMENT_TRIES`` draws all failed."""
    speed = (_r(relative_speed[0] * ROBOT_STEP), _r(relative_speed[1] * ROBOT_STEP))
    margin = BLOCK_HALF + OBSTACLE_MARGIN
    size_x, size_y = index.size
    for t in range(PLACEMENT_TRIES):
        hx, hy = _extent_half(model, 1.0 - _SHRINK * t / PLACEMENT_TRIES, rng)
        u, v = float(rng.random()), float(rng.random())
        span_x, span_y = size_x - 2 * (margin + hx), size_y - 2 * (margin + hy)
        if span_x <= 0 or span_y <= 0:
            continue
        cx, cy = _r(margin + hx + u * span_x), _r(margin + hy + v * span_y)
        low, high = (cx - hx, cy - hy), (cx + hx, cy + hy)
        if not index.clear(low, high, margin):
            continue
        if all(rects_apart(low, high, a, b, EXCLUSION) for a, b in keep_away):
            return _motion(model, (cx, cy), (hx, hy), count, speed, rng)
    return None


def target_motion(center: tuple[float, float], rng: np.random.Generator) -> Motion:
    """A moving target around ``center``: a ``BackAndForth`` or a ``RandomInRect`` (sizes and
    speeds in the module docstring)."""
    speed = (_r(TARGET_RELATIVE_SPEED[0] * ROBOT_STEP), _r(TARGET_RELATIVE_SPEED[1] * ROBOT_STEP))
    if rng.integers(2):
        a = _r(_uniform(rng, *TARGET_AMPLITUDE))
        half = (a, 0.0) if rng.integers(2) else (0.0, a)
        return _motion("back_and_forth", center, half, 1, speed, rng)
    half = (_r(_uniform(rng, *TARGET_AREA_SIDE) / 2), _r(_uniform(rng, *TARGET_AREA_SIDE) / 2))
    return _motion("random_in_rect", center, half, 1, speed, rng)


def extent_of(motion: Motion) -> Rect:
    """The rectangle (low, high) a motion's centre stays in, as Python floats."""
    low, high = motion.extent()
    return (float(low[0]), float(low[1])), (float(high[0]), float(high[1]))
