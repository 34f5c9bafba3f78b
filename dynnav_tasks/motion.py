"""Motion patterns for moving targets and obstacles.

A world declares *what* moves and *how* with these small frozen specs; the environment turns
each spec into a ``Mover`` when it loads and advances every mover once per control step. A
spec may move several bodies together (``count``): a ``Route`` spaces its obstacles evenly
along one loop and gives them one speed, so they never run into each other.

All randomness (start phase, direction, speed) is drawn from the episode's random generator,
so the same reset seed replays the same motion. Speeds are in metres per control step (the
thesis's "m/dt").
"""

from __future__ import annotations

import math
from bisect import bisect_right
from dataclasses import dataclass
from functools import cached_property
from typing import Sequence, Union

import numpy as np

Point = tuple[float, float]


class Mover:
    """Episode state of one motion spec; positions are arrays of shape (count, 2).

    Public, read-only for everyone but the mover itself: ``spec`` (the motion spec it runs),
    ``count`` (bodies it moves) and ``speed`` (metres per control step this episode; ``None``
    when the motion draws a new step length every step, as ``RandomInRect`` does).
    """

    spec: Motion
    count = 1
    speed: float | None = None

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        """Start a new episode; return the positions."""
        raise NotImplementedError

    def advance(self, rng: np.random.Generator) -> np.ndarray:
        """Move one control step; return the new positions."""
        return np.array(self.advance_points(rng))

    def advance_points(self, rng: np.random.Generator) -> list[Point]:
        """``advance``, returning the positions as (x, y) tuples of Python floats."""
        raise NotImplementedError

    def scale_speed(self, factor: float) -> None:
        """Move ``factor`` times as fast until the next ``reset`` (per-episode randomization,
        ``noise.py``); draws nothing, so the motion's random draws stay as they were."""
        raise NotImplementedError


@dataclass(frozen=True)
class Static:
    """Does not move."""

    at: Point
    count = 1

    def mover(self) -> Mover:
        return _StaticMover(self, np.array([self.at], dtype=np.float64))

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        p = np.array(self.at, dtype=np.float64)
        return p, p


class _StaticMover(Mover):
    speed = 0.0

    def __init__(self, spec: Static, at: np.ndarray):
        self.spec = spec
        self.at = at
        self._points = [tuple(p) for p in at.tolist()]

    def reset(self, rng):
        return self.at

    def advance(self, rng):
        return self.at

    def advance_points(self, rng):
        return list(self._points)

    def scale_speed(self, factor):
        pass  # nothing to scale


@dataclass(frozen=True)
class BackAndForth:
    """Moves along the segment ``center +- amplitude * direction`` at a constant speed.

    Each episode starts at a uniformly random point of the segment, heading either way.
    """

    center: Point
    direction: Point
    amplitude: float
    speed: float
    count = 1

    def mover(self) -> Mover:
        return _BackAndForthMover(self)

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        c, d = np.array(self.center, dtype=np.float64), _unit(self.direction)
        a, b = c - self.amplitude * d, c + self.amplitude * d
        return np.minimum(a, b), np.maximum(a, b)


class _BackAndForthMover(Mover):
    def __init__(self, spec: BackAndForth):
        self.spec = spec
        self.center = np.array(spec.center, dtype=np.float64)
        self.direction = _unit(spec.direction)
        self._c, self._d = self.center.tolist(), self.direction.tolist()
        self.amplitude = float(spec.amplitude)
        self.speed = float(spec.speed)
        self.offset = 0.0
        self.sign = 1.0

    def _point(self) -> Point:
        (cx, cy), (dx, dy), t = self._c, self._d, self.offset
        return cx + t * dx, cy + t * dy

    def reset(self, rng):
        self.speed = float(self.spec.speed)  # (a scaled speed lasts one episode)
        self.offset = rng.uniform(-self.amplitude, self.amplitude)
        self.sign = 1.0 if rng.integers(2) else -1.0
        return np.array([self._point()])

    def advance_points(self, rng):
        a, s = self.amplitude, self.offset + self.sign * self.speed
        while s > a or s < -a:  # reflect at the ends (more than once if fast and short)
            s, self.sign = (2 * a - s, -1.0) if s > a else (-2 * a - s, 1.0)
        self.offset = s
        return [self._point()]

    def scale_speed(self, factor):
        self.speed *= factor


@dataclass(frozen=True)
class Route:
    """``count`` bodies moving along a closed polyline, in the order of its waypoints.

    Each episode draws one speed uniformly from ``speed_range`` (shared by the bodies) and a
    uniformly random shift along the loop; the bodies stay evenly spaced.
    """

    waypoints: tuple[Point, ...]
    speed_range: tuple[float, float]
    count: int = 1

    @cached_property
    def _geometry(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Closed loop points, segment lengths and cumulative lengths (computed once)."""
        pts = np.array(list(self.waypoints) + [self.waypoints[0]], dtype=np.float64)
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        if np.any(seg == 0):
            raise ValueError(f"a Route's consecutive waypoints must differ: {self.waypoints}")
        return pts, seg, np.cumsum(seg)

    @cached_property
    def _segments(self) -> tuple[list, list, float]:
        """The geometry as Python floats: cumulative lengths, per segment (start arc length,
        length, x, y, dx, dy), and the loop length."""
        pts, seg, cum = self._geometry
        p, c = pts.tolist(), cum.tolist()
        rows = [
            (float(cum[i] - seg[i]), float(seg[i]), *p[i], p[i + 1][0] - p[i][0], p[i + 1][1] - p[i][1])
            for i in range(len(seg))
        ]
        return c, rows, c[-1]

    def length(self) -> float:
        return float(self._geometry[2][-1])

    def point_at(self, s: float) -> tuple[float, float]:
        """``position_at`` as a tuple of Python floats."""
        cum, rows, length = self._segments
        s = s % length
        start, seg, x, y, dx, dy = rows[min(bisect_right(cum, s), len(rows) - 1)]
        t = (s - start) / seg
        return x + dx * t, y + dy * t

    def position_at(self, s: float) -> np.ndarray:
        """Point at arc length ``s`` (taken modulo the loop length) from the first waypoint."""
        return np.array(self.point_at(s))

    def nearest_arc_length(self, point) -> float:
        """Arc length (from the first waypoint) of the loop's point nearest to ``point``."""
        pts, seg, cum = self._geometry
        p = np.asarray(point, dtype=np.float64)
        a, b = pts[:-1], pts[1:]
        t = np.clip(np.einsum("ij,ij->i", p - a, b - a) / seg**2, 0, 1)
        d = np.linalg.norm(a + (b - a) * t[:, None] - p, axis=1)
        i = int(np.argmin(d))
        return float(cum[i] - seg[i] + t[i] * seg[i])

    def signed_area(self) -> float:
        """Shoelace area of the loop: negative when it runs clockwise seen from above (z up)."""
        p = np.array(self.waypoints, dtype=np.float64)
        x, y = p[:, 0], p[:, 1]
        return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        p = np.array(self.waypoints, dtype=np.float64)
        return p.min(axis=0), p.max(axis=0)

    def mover(self) -> Mover:
        return _RouteMover(self)


class _RouteMover(Mover):
    def __init__(self, spec: Route):
        self.spec = spec
        self.count = spec.count
        self.length = spec.length()
        self.spacing = self.length / spec.count
        self.speed = 0.0
        self.s = 0.0

    def _points(self) -> list[Point]:
        point_at, s, spacing = self.spec.point_at, self.s, self.spacing
        if self.count == 1:
            return [point_at(s)]
        return [point_at(s + i * spacing) for i in range(self.count)]

    def reset(self, rng):
        lo, hi = self.spec.speed_range
        self.speed = rng.uniform(lo, hi)
        self.s = rng.uniform(0.0, self.length)
        return np.array(self._points())

    def advance_points(self, rng):
        self.s = (self.s + self.speed) % self.length
        return self._points()

    def scale_speed(self, factor):
        self.speed *= factor


@dataclass(frozen=True)
class RandomInRect:
    """Wanders inside a rectangle (the thesis's random motion in a motion area).

    Every step the heading turns by an angle uniform in ``+-max_turn`` and the body moves a
    distance uniform in ``speed_range``; it bounces off the rectangle's edges, so its centre
    never leaves ``x_range`` x ``y_range``. An episode starts at ``start`` (default: uniform
    in the rectangle) with a uniform heading.
    """

    x_range: tuple[float, float]
    y_range: tuple[float, float]
    speed_range: tuple[float, float] = (0.05, 0.5)
    max_turn: float = math.pi / 4
    start: Point | None = None
    count = 1

    def __post_init__(self):
        if not (self.x_range[0] < self.x_range[1] and self.y_range[0] < self.y_range[1]):
            raise ValueError(f"RandomInRect needs low < high in both ranges, got {self.x_range}, {self.y_range}")

    def mover(self) -> Mover:
        return _RandomInRectMover(self)

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        return np.array([self.x_range[0], self.y_range[0]]), np.array([self.x_range[1], self.y_range[1]])


class _RandomInRectMover(Mover):
    def __init__(self, spec: RandomInRect):
        self.spec = spec
        self.low, self.high = spec.extent()
        self._bounds = list(zip(self.low.tolist(), self.high.tolist()))
        self._turn = _UniformRange(-float(spec.max_turn), float(spec.max_turn))
        self._speed = _UniformRange(*(float(v) for v in spec.speed_range))
        self._xy = [0.0, 0.0]
        self.heading = 0.0
        self._factor = 1.0  # the episode's speed factor (scale_speed)

    @property
    def p(self) -> np.ndarray:
        """The current position."""
        return np.array(self._xy)

    def reset(self, rng):
        if self.spec.start is None:
            # one draw per coordinate, x first: rng.uniform(low, high) with the arrays draws the same
            self._xy = [rng.uniform(lo, hi) for lo, hi in self._bounds]
        else:
            self._xy = [float(v) for v in self.spec.start]
        self.heading = rng.uniform(-math.pi, math.pi)
        self._factor = 1.0
        return np.array([self._xy])

    def scale_speed(self, factor):
        self._factor = float(factor)

    def advance_points(self, rng):
        turn, speed = self._turn, self._speed
        heading = self.heading + (turn.low + turn.span * rng.random())  # turn.draw(rng), inlined
        step = speed.low + speed.span * rng.random()  # speed.draw(rng)
        if self._factor != 1.0:
            step *= self._factor
        dx, dy = math.cos(heading), math.sin(heading)
        x, y = self._xy
        x, y = x + step * dx, y + step * dy
        (x_lo, x_hi), (y_lo, y_hi) = self._bounds
        while x < x_lo or x > x_hi:  # bounce: mirror the position and the heading's component
            x, dx = (2 * x_lo - x if x < x_lo else 2 * x_hi - x), -dx
        while y < y_lo or y > y_hi:
            y, dy = (2 * y_lo - y if y < y_lo else 2 * y_hi - y), -dy
        self.heading = math.atan2(dy, dx)
        self._xy = [x, y]
        return [(x, y)]


class _UniformRange:
    """``draw(rng)`` is ``rng.uniform(low, high)``: the same value and the same draw.

    numpy's ``Generator.uniform`` computes ``low + (high - low) * u`` from one standard
    uniform draw ``u``, which ``rng.random()`` returns for a third of the call's cost
    (``tests/test_step_speedups.py`` checks the two agree).
    """

    __slots__ = ("low", "span")

    def __init__(self, low: float, high: float):
        self.low, self.span = low, high - low

    def draw(self, rng: np.random.Generator) -> float:
        return self.low + self.span * rng.random()


Motion = Union[Static, BackAndForth, Route, RandomInRect]
"""Any motion spec of this module."""


@dataclass(frozen=True)
class EpisodeMotion:
    """What one group of moving bodies does this episode (``NavEnv.obstacle_motions``)."""

    motion: Motion
    """the group's motion spec, as its world declares it"""
    count: int
    """bodies in the group"""
    speed: float | None
    """metres per control step this episode; None when drawn anew every step (``RandomInRect``)"""

    @classmethod
    def of(cls, mover: Mover) -> "EpisodeMotion":
        """A frozen copy of what ``mover`` runs this episode."""
        return cls(mover.spec, mover.count, mover.speed)


def _unit(v: Sequence[float]) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    n = float(np.linalg.norm(v))
    if n == 0:
        raise ValueError("a motion direction must be non-zero")
    return v / n


def wrap_angle(a):
    """Wrap an angle (or array of angles) to [-pi, pi)."""
    return (a + math.pi) % (2 * math.pi) - math.pi
