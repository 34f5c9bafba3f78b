"""The egocentric state: an observation that means the same in every world.

The study's state vectors hold absolute coordinates and one slot per moving obstacle of their
world, so their size and meaning change from world to world. The egocentric state is read in
the robot's own frame (x ahead, y to the left) and has one size for a given ``k``, whatever
the world, so a network trained in one world reads any other. Float32, in this order
(``egocentric_layout``):

====================  ======================================================================
part                  meaning
====================  ======================================================================
``lasers`` (n)        the laser ring's readings (m), as in every task: 16 rays, ray 0
                      straight ahead, unless the task's ``laser_rays`` and
                      ``laser_fov_deg`` say otherwise (``lasers.py``)
``target`` (3)        distance to the target's centre (m), sin and cos of its bearing (the
                      bearing is the ``StepSnapshot``'s: > 0 to the left; sin/cos has no
                      jump at +-pi)
``way`` (3)           only with the task's ``way=True``: the length of the way to the target
                      through the static layout (m) and the sin and cos of the bearing of
                      the point 0.5 m along it (``way_sense.py``: the map and a global
                      planner, no moving obstacle)
``odometry`` (3)      only with the task's ``odometry=True``: the robot's own move over the
                      last control step, as its wheel odometry measures it: the
                      displacement (m) ahead and to the left in its heading after the step,
                      and the turn (rad, counter-clockwise positive); 0 right after a reset
                      or ``place_robot``. With it an obstacle's own velocity in the robot's
                      frame is its relative velocity plus the displacement
``obstacle{i}`` (5)   for i < k, the i-th nearest moving obstacle (by squared centre
                      distance, ties in the world's order): x, y of its centre relative to the robot (m),
                      vx, vy of its velocity relative to the robot over the last step (m per
                      control step; 0 right after a reset or ``place_robot``: nothing moved
                      yet), all in the robot's frame, then 1.0 (present). A slot with no
                      obstacle left to fill it holds ``PADDING``: (FAR, 0, 0, 0, 0.0), an
                      obstacle-free slot as far away as nothing in any arena can be
``human{i}`` (5)      for i < ``human_k`` (0 unless the task says otherwise), the i-th nearest
                      pedestrian (``world.pedestrians``), as an obstacle slot but with its
                      radius (m) in place of "present": x, y, vx, vy, radius; an empty slot
                      holds ``PADDING`` (radius 0)
====================  ======================================================================

Relative velocity: the obstacle's displacement over the step minus the robot's, turned into
the robot's heading after the step. Positions are clipped to [-FAR, FAR] (no arena is wider
than 28.3 m across) and velocities to [-MAX_RELATIVE_STEP, MAX_RELATIVE_STEP], so the
observation always lies in ``egocentric_space``.
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np

from .snapshot import StepSnapshot

FAR = 30.0
"""metres: the largest relative coordinate and target distance; a padded slot's x"""
MAX_RELATIVE_STEP = 3.0
"""metres per control step: the largest relative velocity component"""
OBSTACLE_FIELDS = ("x", "y", "vx", "vy", "present")
HUMAN_FIELDS = ("x", "y", "vx", "vy", "radius")
MAX_HUMAN_RADIUS = 1.0
"""metres: the largest pedestrian radius a slot holds"""
PADDING = np.array([FAR, 0.0, 0.0, 0.0, 0.0], dtype=np.float32)
"""the fields of an empty obstacle slot"""


def egocentric_layout(num_lasers: int, k: int, way: bool = False, human_k: int = 0,
                      odometry: bool = False) -> list[tuple[str, int]]:
    """Names and sizes of the egocentric state's parts, in order (``way``, ``odometry``: with those parts)."""
    return ([("lasers", num_lasers), ("target", 3)] + ([("way", 3)] if way else [])
            + ([("odometry", 3)] if odometry else [])
            + [(f"obstacle{i}", len(OBSTACLE_FIELDS)) for i in range(k)]
            + [(f"human{i}", len(HUMAN_FIELDS)) for i in range(human_k)])


def egocentric_space(num_lasers: int, laser_range: float, k: int, way: bool = False,
                     human_k: int = 0, odometry: bool = False) -> gym.spaces.Box:
    """The egocentric state's observation space (bounds as the module docstring gives)."""
    slot_low = [-FAR, -FAR, -MAX_RELATIVE_STEP, -MAX_RELATIVE_STEP, 0.0]
    slot_high = [FAR, FAR, MAX_RELATIVE_STEP, MAX_RELATIVE_STEP, 1.0]
    human_high = slot_high[:4] + [MAX_HUMAN_RADIUS]
    heading_low, heading_high = [0.0, -1.0, -1.0], [FAR, 1.0, 1.0]  # a distance, then a sin and a cos
    odo_high = [MAX_RELATIVE_STEP, MAX_RELATIVE_STEP, math.pi] if odometry else []
    low = np.array([0.0] * num_lasers + heading_low * (2 if way else 1) + [-v for v in odo_high]
                   + slot_low * (k + human_k), dtype=np.float32)
    high = np.array([laser_range] * num_lasers + heading_high * (2 if way else 1) + odo_high + slot_high * k
                    + human_high * human_k, dtype=np.float32)
    return gym.spaces.Box(low, high, dtype=np.float32)


def egocentric_state(snapshot: StepSnapshot, before: StepSnapshot | None, k: int,
                     way: tuple[float, float, float] | None = None, human_k: int = 0,
                     odometry: bool = False) -> np.ndarray:
    """The egocentric state of ``snapshot`` (module docstring); ``before``: the snapshot
    before the step that led to it (``None`` after a reset or a placement: velocities 0);
    ``way``: the ``WaySense`` reading (length, sin, cos) for the ``way`` part, None without it;
    ``human_k``: pedestrian slots; ``odometry``: with the robot's own move over the step.
    Plain Python over the few obstacles: faster than numpy at these sizes."""
    x, y, yaw = snapshot.pose
    n = len(snapshot.lasers)
    out = np.empty(n + 3 + (3 if way is not None else 0) + (3 if odometry else 0) + len(PADDING) * (k + human_k),
                   dtype=np.float32)
    out[:n] = snapshot.lasers
    bearing = snapshot.bearing
    tail = [min(snapshot.d1, FAR), math.sin(bearing), math.cos(bearing)]
    if way is not None:
        tail += [min(way[0], FAR), way[1], way[2]]
    if odometry:
        tail += _odometry(snapshot, before)
    if k:
        tail += _nearest(snapshot.moving_obstacle_xy.tolist(), before.moving_obstacle_xy.tolist() if before else None,
                         None, before, k, x, y, yaw)
    if human_k:
        tail += _nearest(snapshot.human_xy.tolist(), before.human_xy.tolist() if before else None,
                         snapshot.human_radius.tolist(), before, human_k, x, y, yaw)
    out[n:] = tail
    return out


def _nearest(moving: list, previous: list | None, radius: list | None, before: StepSnapshot | None, k: int,
             x: float, y: float, yaw: float):
    """The ``k`` slots of the bodies at ``moving`` (``previous``: where they were a step before),
    flat, nearest first, padded: the last field 1.0 (present) or, given ``radius``, each one's radius."""
    rows = sorted((dx * dx + dy * dy, j, dx, dy) for j, (dx, dy) in enumerate((ox - x, oy - y) for ox, oy in moving))
    c, s = math.cos(yaw), math.sin(yaw)
    if before is not None:
        bx, by, _ = before.pose
        rx, ry = x - bx, y - by  # the robot's displacement over the step
    slots = []
    for _, j, dx, dy in rows[:k]:
        if before is not None:
            px, py = previous[j]
            vx, vy = moving[j][0] - px - rx, moving[j][1] - py - ry
            vx, vy = _clip(c * vx + s * vy, MAX_RELATIVE_STEP), _clip(-s * vx + c * vy, MAX_RELATIVE_STEP)
        else:
            vx = vy = 0.0
        slots += (_clip(c * dx + s * dy, FAR), _clip(-s * dx + c * dy, FAR), vx, vy,
                  1.0 if radius is None else min(radius[j], MAX_HUMAN_RADIUS))
    return slots + _PADDING_LIST * (k - len(rows[:k]))


_PADDING_LIST = PADDING.tolist()


def _odometry(snapshot: StepSnapshot, before: StepSnapshot | None) -> list[float]:
    """The robot's move from ``before`` to ``snapshot``: (ahead, left) in its heading after it, and the turn."""
    if before is None:
        return [0.0, 0.0, 0.0]
    x, y, yaw = snapshot.pose
    bx, by, byaw = before.pose
    dx, dy, c, s = x - bx, y - by, math.cos(yaw), math.sin(yaw)
    turn = math.atan2(math.sin(yaw - byaw), math.cos(yaw - byaw))
    return [_clip(c * dx + s * dy, MAX_RELATIVE_STEP), _clip(-s * dx + c * dy, MAX_RELATIVE_STEP), turn]


def _clip(v: float, bound: float) -> float:
    return bound if v > bound else (-bound if v < -bound else v)
