"""``StepSnapshot``: everything a dynnav task knows about the world after one step.

A task takes exactly one snapshot after every ``reset()`` and every ``step()`` (and after
``place_robot``), with ``snapshot_of`` (``sensing.py`` gathers its inputs); ``take_snapshot``
does the same from plain values. Nothing else computes these quantities. Success and
failure (``NavEnv.evaluate``), the reward (``rewards.compute_reward(mode, previous, current,
...)``), the state vector, recordings and pictures all read the snapshot, which is public
as ``env.unwrapped.snapshot`` and immutable: its arrays are read-only. A task with sensor or
odometry noise (``noise.py``) observes ``perceived_snapshot`` of it instead
(``env.unwrapped.observed_snapshot``); everything else reads the true one.

Geometry (metres, radians, world frame, z up):

=================  ==========================================================================
field              meaning
=================  ==========================================================================
``step``           control steps since the last reset (0 right after it)
``pose``           the robot's (x, y, yaw), yaw counter-clockwise from +x
``lasers``         the laser readings, float32 (16 unless the task's ``laser_rays`` says
                   otherwise; see ``lasers.py``)
``target_xy``      centre of the episode's chosen target
``obstacle_xy``    (n, 2) centres of every obstacle box: static ones first, then moving ones
``obstacle_half``  (n, 2) half sizes of those boxes (walls are not obstacles)
``moving_count``   how many of the boxes (the last ones) move
``d1``             distance from the robot's centre to the target's centre
``d2``             distance from the robot's centre to the nearest obstacle box or
                   pedestrian's edge (0 inside one; ``inf`` in a world without either)
``bearing``        the target's direction seen from the robot, relative to its heading,
                   in [-pi, pi); > 0 when the target is to the left
``contact``        the robot touched a wall or an obstacle during the step: a PhysX contact
                   at one of its sub-steps, or its footprint overlapping one at the end
                   (always False after a reset or ``place_robot``: nothing was simulated)
``path_length``    metres the robot's centre has travelled since the reset
``human_xy``       (k, 2) centres of the pedestrians (``world.pedestrians``; (0, 2) without)
``human_radius``   (k,) their radii
``human_contact``  the contact (``contact``) was with a pedestrian: a human collision
=================  ==========================================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .motion import wrap_angle


def box_distance(point: np.ndarray, centers: np.ndarray, half_sizes: np.ndarray) -> np.ndarray:
    """Distances from a 2D point to axis-aligned rectangles (0 inside)."""
    d = np.maximum(np.abs(point[None, :] - centers) - half_sizes, 0.0)
    return np.sqrt((d * d).sum(axis=1))


def nearest_box_distance(x: float, y: float, boxes) -> float:
    """The smallest of ``box_distance`` from (x, y) to the ``boxes`` (cx, cy, hx, hy), the same
    value to the last bit, in plain Python; ``inf`` when there are none."""
    nearest = math.inf
    for cx, cy, hx, hy in boxes:
        dx, dy = abs(x - cx) - hx, abs(y - cy) - hy
        dx, dy = (0.0 if dx <= 0.0 else dx), (0.0 if dy <= 0.0 else dy)
        d = math.sqrt(dx * dx + dy * dy)
        if d < nearest:
            nearest = d
    return nearest


def footprint_overlaps(pose, half, boxes) -> bool:
    """Does a rectangle of half sizes ``half`` at ``pose`` (x, y, yaw) overlap any of the
    axis-aligned ``boxes`` (cx, cy, hx, hy)? A separating-axis test on the two shapes' axes;
    plain Python, as there are only a few boxes and most are rejected by the first test."""
    x, y, yaw = pose
    a, b = half
    cos, sin = math.cos(yaw), math.sin(yaw)
    c, s = abs(cos), abs(sin)
    ex, ey = a * c + b * s, a * s + b * c  # the rectangle's half extents along x and y
    for cx, cy, hx, hy in boxes:
        dx, dy = x - cx, y - cy
        if (
            abs(dx) < hx + ex
            and abs(dy) < hy + ey
            and abs(dx * cos + dy * sin) < a + hx * c + hy * s
            and abs(dy * cos - dx * sin) < b + hx * s + hy * c
        ):
            return True
    return False


def footprint_touches_circles(pose, half, circles) -> bool:
    """Does a rectangle of half sizes ``half`` at ``pose`` (x, y, yaw) overlap any of the
    ``circles`` (cx, cy, r)? The circle's centre in the rectangle's frame, clamped to it, is the
    rectangle's nearest point to it."""
    x, y, yaw = pose
    a, b = half
    cos, sin = math.cos(yaw), math.sin(yaw)
    for cx, cy, r in circles:
        dx, dy = cx - x, cy - y
        u, v = dx * cos + dy * sin, dy * cos - dx * sin
        nu, nv = min(max(u, -a), a), min(max(v, -b), b)
        if (u - nu) ** 2 + (v - nv) ** 2 < r * r:
            return True
    return False


def nearest_circle_distance(x: float, y: float, circles) -> float:
    """The smallest distance from (x, y) to the edge of any of the ``circles`` (cx, cy, r), 0
    inside one; ``inf`` when there are none."""
    nearest = math.inf
    for cx, cy, r in circles:
        d = max(math.hypot(x - cx, y - cy) - r, 0.0)
        if d < nearest:
            nearest = d
    return nearest


NO_HUMANS_XY = np.zeros((0, 2))
NO_HUMANS_XY.setflags(write=False)
NO_HUMANS_RADIUS = np.zeros(0)
NO_HUMANS_RADIUS.setflags(write=False)


def _frozen(values, dtype, shape=None) -> np.ndarray:
    array = np.array(values, dtype=dtype)  # a copy: later changes to the source do not leak in
    if shape is not None:
        array = array.reshape(shape)
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class StepSnapshot:
    """The world after one step, as the task saw it (see the module docstring)."""

    step: int
    pose: tuple[float, float, float]
    lasers: np.ndarray
    target_xy: np.ndarray
    obstacle_xy: np.ndarray
    obstacle_half: np.ndarray
    moving_count: int
    d1: float
    d2: float
    bearing: float
    contact: bool
    path_length: float
    human_xy: np.ndarray = field(default_factory=lambda: NO_HUMANS_XY)
    human_radius: np.ndarray = field(default_factory=lambda: NO_HUMANS_RADIUS)
    human_contact: bool = False

    @property
    def robot_xy(self) -> np.ndarray:
        """(x, y) of the robot's centre."""
        return np.array(self.pose[:2])

    @property
    def moving_obstacle_xy(self) -> np.ndarray:
        """(m, 2) centres of the moving obstacles, in state-vector order."""
        return self.obstacle_xy[len(self.obstacle_xy) - self.moving_count:]

    def state_vector(self) -> np.ndarray:
        """lasers | robot x, y | target x, y | moving obstacles' x, y (float32)."""
        return np.concatenate(
            [self.lasers, self.pose[:2], self.target_xy, self.moving_obstacle_xy.reshape(-1)], dtype=np.float32
        )


def take_snapshot(
    *,
    step: int,
    pose,
    lasers,
    target_xy,
    static_xy,
    moving_xy,
    obstacle_half,
    contact: bool,
    previous: StepSnapshot | None = None,
) -> StepSnapshot:
    """A ``StepSnapshot`` from plain values (sequences or arrays, copied): ``snapshot_of``
    after freezing copies of the arrays.

    ``previous``: the snapshot of the step before, whose path length this one extends by
    the distance between the two poses (``None`` after a reset: the path starts at 0).
    """
    moving = np.reshape(moving_xy, (-1, 2))
    obstacles = _frozen(np.concatenate([np.reshape(static_xy, (-1, 2)), moving]), np.float64, (-1, 2))
    half = _frozen(obstacle_half, np.float64, (-1, 2))
    if len(half) != len(obstacles):
        raise ValueError(f"{len(obstacles)} obstacle centres but {len(half)} half sizes")
    tx, ty = (float(v) for v in target_xy)
    x, y, yaw = (float(v) for v in pose)
    return snapshot_of(
        step=int(step),
        pose=(x, y, yaw),
        lasers=_frozen(lasers, np.float32),
        target_xy=_frozen((tx, ty), np.float64),
        obstacle_xy=obstacles,
        obstacle_half=half,
        moving_count=len(moving),
        boxes=[(*c, *h) for c, h in zip(obstacles.tolist(), half.tolist())],
        contact=contact,
        previous=previous,
    )


def snapshot_of(
    *,
    step: int,
    pose,
    lasers: np.ndarray,
    target_xy: np.ndarray,
    obstacle_xy: np.ndarray,
    obstacle_half: np.ndarray,
    moving_count: int,
    boxes,
    contact: bool,
    previous: StepSnapshot | None,
    placed: bool = False,
    humans: tuple[np.ndarray, np.ndarray] | None = None,
    human_contact: bool = False,
) -> StepSnapshot:
    """The one function that makes a ``StepSnapshot``: derives d1, d2, the bearing and the
    path length. ``step`` is an int and ``pose`` a tuple of Python floats; the arrays are
    kept as given: read-only arrays nothing else writes to (``take_snapshot`` makes them
    from plain values); ``boxes`` lists ``obstacle_xy`` and ``obstacle_half`` as
    (cx, cy, hx, hy) rows of Python floats.

    ``placed``: the robot was put where it is (``NavEnv.place_robot``), not driven there, so
    the path length stays ``previous``'s instead of growing by the distance between them.
    ``humans``: (centres (k, 2), radii (k,)) of the pedestrians, read-only arrays (None: none);
    ``human_contact``: ``contact`` was with one of them."""
    x, y, yaw = pose
    tx, ty = target_xy.tolist()
    path = 0.0
    if previous is not None:
        px, py, _ = previous.pose
        path = previous.path_length if placed else previous.path_length + math.hypot(x - px, y - py)
    snapshot = object.__new__(StepSnapshot)  # the frozen dataclass's fields, set without its slower __init__
    snapshot.__dict__.update(
        step=step,
        pose=pose,
        lasers=lasers,
        target_xy=target_xy,
        obstacle_xy=obstacle_xy,
        obstacle_half=obstacle_half,
        moving_count=moving_count,
        d1=math.hypot(tx - x, ty - y),
        d2=nearest_box_distance(x, y, boxes),
        bearing=wrap_angle(math.atan2(ty - y, tx - x) - yaw),
        contact=bool(contact),
        path_length=path,
        human_xy=NO_HUMANS_XY,
        human_radius=NO_HUMANS_RADIUS,
        human_contact=bool(human_contact),
    )
    if humans is not None and len(humans[0]):
        xy, radius = humans
        circles = [(cx, cy, r) for (cx, cy), r in zip(xy.tolist(), radius.tolist())]
        snapshot.__dict__.update(human_xy=xy, human_radius=radius,
                                 d2=min(snapshot.d2, nearest_circle_distance(x, y, circles)))
    return snapshot


def perceived_snapshot(snapshot: StepSnapshot, lasers: np.ndarray, xy) -> StepSnapshot:
    """``snapshot`` as a robot with noisy sensors perceives it (``noise.py``): ``lasers`` (a
    read-only float32 array) for its readings and ``xy`` for its position, its heading kept.
    The target's distance ``d1`` and ``bearing`` are recomputed from ``xy``; ``d2``,
    ``contact`` and ``path_length`` stay the true ones (the outcome's and the reward's, which
    no observation reads)."""
    x, y = (float(v) for v in xy)
    yaw = snapshot.pose[2]
    tx, ty = snapshot.target_xy.tolist()
    perceived = object.__new__(StepSnapshot)
    perceived.__dict__.update(
        snapshot.__dict__,
        pose=(x, y, yaw),
        lasers=lasers,
        d1=math.hypot(tx - x, ty - y),
        bearing=wrap_angle(math.atan2(ty - y, tx - x) - yaw),
    )
    return perceived
