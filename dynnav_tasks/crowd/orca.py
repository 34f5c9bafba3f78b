"""Optimal reciprocal collision avoidance (ORCA; van den Berg, Guy, Lin and Manocha, "Reciprocal
n-body collision avoidance", ISRR 2009 / Springer 2011), in plain Python and numpy.

Each agent takes, for every neighbour, the half-plane of velocities that avoids a collision with
it for ``time_horizon`` seconds if the neighbour does its share, and chooses the velocity nearest
its preferred one inside all the half-planes and its speed limit (a 2-D linear program, solved
incrementally as in the reference library RVO2). Where no velocity satisfies every half-plane,
the one that violates the worst of them least is taken (RVO2's ``linearProgram3``). An agent
already overlapping a neighbour takes the half-plane that separates them within one ``dt``.

``responsibility`` is the share of the avoidance an agent takes: 0.5 between two ORCA agents,
1 towards a neighbour that does not avoid (a robot it sees that does not run ORCA, a static
point). This is RVO2's ``Agent::computeNewVelocity`` without its static-obstacle lines: walls
and static boxes enter as resting neighbours of radius 0 at each box's point nearest the agent,
for the boxes within the distance the agent can cover in ``time_horizon`` (plus its radius).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

EPSILON = 1e-5
"""RVO2's RVO_EPSILON: determinants and lengths below it count as zero"""


@dataclass(frozen=True)
class Line:
    """A directed line: the half-plane to its left is permitted."""

    point: tuple[float, float]
    direction: tuple[float, float]


def _det(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def orca_line(position, velocity, radius: float, other_position, other_velocity, other_radius: float,
              time_horizon: float, dt: float, responsibility: float = 0.5) -> Line:
    """The ORCA half-plane of the agent at ``position`` with ``velocity`` and ``radius`` towards one
    neighbour (all in m and m/s), as RVO2 computes it."""
    rpx, rpy = other_position[0] - position[0], other_position[1] - position[1]
    rvx, rvy = velocity[0] - other_velocity[0], velocity[1] - other_velocity[1]
    dist_sq = rpx * rpx + rpy * rpy
    r = radius + other_radius
    r_sq = r * r
    if dist_sq > r_sq:  # no collision yet
        inv_t = 1.0 / time_horizon
        wx, wy = rvx - inv_t * rpx, rvy - inv_t * rpy  # from the cut-off circle's centre to the relative velocity
        w_sq = wx * wx + wy * wy
        dot1 = wx * rpx + wy * rpy
        if dot1 < 0.0 and dot1 * dot1 > r_sq * w_sq:  # nearest the cut-off circle
            w = math.sqrt(w_sq)
            ux, uy = wx / w, wy / w
            direction = (uy, -ux)
            scale = r * inv_t - w
            u = (scale * ux, scale * uy)
        else:  # nearest a leg of the cone
            leg = math.sqrt(dist_sq - r_sq)
            if _det(rpx, rpy, wx, wy) > 0.0:  # left leg
                direction = ((rpx * leg - rpy * r) / dist_sq, (rpx * r + rpy * leg) / dist_sq)
            else:  # right leg
                direction = (-(rpx * leg + rpy * r) / dist_sq, -(-rpx * r + rpy * leg) / dist_sq)
            dot2 = rvx * direction[0] + rvy * direction[1]
            u = (dot2 * direction[0] - rvx, dot2 * direction[1] - rvy)
    else:  # overlapping: separate within one step
        inv_dt = 1.0 / dt
        wx, wy = rvx - inv_dt * rpx, rvy - inv_dt * rpy
        w = math.hypot(wx, wy)
        if w < EPSILON:  # same place and velocity: any direction separates them
            wx, wy, w = 1.0, 0.0, 1.0
        ux, uy = wx / w, wy / w
        direction = (uy, -ux)
        scale = r * inv_dt - w
        u = (scale * ux, scale * uy)
    return Line((velocity[0] + responsibility * u[0], velocity[1] + responsibility * u[1]), direction)


def _program1(lines: list[Line], k: int, radius: float, opt, direction_opt: bool):
    """The best point on line ``k`` within the speed circle and lines 0..k-1, or None."""
    (px, py), (dx, dy) = lines[k].point, lines[k].direction
    dot = px * dx + py * dy
    disc = dot * dot + radius * radius - (px * px + py * py)
    if disc < 0.0:  # the line misses the speed circle
        return None
    root = math.sqrt(disc)
    t_left, t_right = -dot - root, -dot + root
    for i in range(k):
        (qx, qy), (ex, ey) = lines[i].point, lines[i].direction
        denominator = _det(dx, dy, ex, ey)
        numerator = _det(ex, ey, px - qx, py - qy)
        if abs(denominator) <= EPSILON:  # parallel lines
            if numerator < 0.0:
                return None
            continue
        t = numerator / denominator
        if denominator >= 0.0:
            t_right = min(t_right, t)
        else:
            t_left = max(t_left, t)
        if t_left > t_right:
            return None
    if direction_opt:
        t = t_right if opt[0] * dx + opt[1] * dy > 0.0 else t_left
    else:
        t = min(max(dx * (opt[0] - px) + dy * (opt[1] - py), t_left), t_right)
    return (px + t * dx, py + t * dy)


def _program2(lines: list[Line], radius: float, opt, direction_opt: bool):
    """(index of the first line that failed or len(lines), the velocity nearest ``opt`` so far)."""
    if direction_opt:
        result = (opt[0] * radius, opt[1] * radius)
    elif opt[0] * opt[0] + opt[1] * opt[1] > radius * radius:
        n = math.hypot(opt[0], opt[1])
        result = (opt[0] / n * radius, opt[1] / n * radius)
    else:
        result = (opt[0], opt[1])
    for i, line in enumerate(lines):
        if _det(line.direction[0], line.direction[1], line.point[0] - result[0], line.point[1] - result[1]) > 0.0:
            better = _program1(lines, i, radius, opt, direction_opt)
            if better is None:
                return i, result
            result = better
    return len(lines), result


def _program3(lines: list[Line], begin: int, radius: float, result):
    """The velocity that violates the worst line least, from line ``begin`` on."""
    distance = 0.0
    for i in range(begin, len(lines)):
        (px, py), (dx, dy) = lines[i].point, lines[i].direction
        if _det(dx, dy, px - result[0], py - result[1]) > distance:
            projected = []
            for j in range(i):
                (qx, qy), (ex, ey) = lines[j].point, lines[j].direction
                determinant = _det(dx, dy, ex, ey)
                if abs(determinant) <= EPSILON:
                    if dx * ex + dy * ey > 0.0:  # same direction
                        continue
                    point = (0.5 * (px + qx), 0.5 * (py + qy))
                else:
                    t = _det(ex, ey, px - qx, py - qy) / determinant
                    point = (px + t * dx, py + t * dy)
                nx, ny = ex - dx, ey - dy
                n = math.hypot(nx, ny)
                projected.append(Line(point, (nx / n, ny / n)))
            failed, candidate = _program2(projected, radius, (-dy, dx), True)
            if failed == len(projected):
                result = candidate
            distance = _det(dx, dy, px - result[0], py - result[1])
    return result


def solve(lines: list[Line], max_speed: float, preferred) -> tuple[float, float]:
    """The velocity nearest ``preferred`` within ``max_speed`` on the permitted side of every line
    (or violating the worst line least when they leave no room)."""
    failed, result = _program2(lines, max_speed, preferred, False)
    if failed < len(lines):
        result = _program3(lines, failed, max_speed, result)
    return result


def orca_velocities(positions: np.ndarray, velocities: np.ndarray, radii: np.ndarray, preferred: np.ndarray,
                    max_speeds: np.ndarray, dt: float, time_horizon: float = 5.0, neighbour_distance: float = 10.0,
                    max_neighbours: int = 10, others: tuple = (), boxes: np.ndarray | None = None) -> np.ndarray:
    """The new velocity (n, 2) of each of n ORCA agents (positions, velocities (n, 2); radii,
    max_speeds (n,); preferred velocities (n, 2)). Each avoids its ``max_neighbours`` nearest fellow
    agents within ``neighbour_distance`` (sharing the avoidance), every ``others`` entry,
    (position, velocity, radius, responsibility) tuples: neighbours that are not ORCA agents, and
    the ``boxes`` (k, 4) as (lo_x, lo_y, hi_x, hi_y) (module docstring)."""
    n = len(positions)
    out = np.zeros((n, 2))
    if boxes is not None and len(boxes):
        boxes = np.asarray(boxes, dtype=np.float64)
        nearest = np.stack([np.clip(positions[:, None, 0], boxes[None, :, 0], boxes[None, :, 2]),
                            np.clip(positions[:, None, 1], boxes[None, :, 1], boxes[None, :, 3])], axis=-1)  # (n, k, 2)
        reach = time_horizon * np.asarray(max_speeds, dtype=np.float64) + np.asarray(radii, dtype=np.float64)
        close = np.hypot(*(nearest - positions[:, None, :]).transpose(2, 0, 1)) < reach[:, None]
    for i in range(n):
        p, v = positions[i], velocities[i]
        d = np.hypot(*(positions - p).T)
        d[i] = np.inf
        near = [j for j in np.argsort(d, kind="stable")[:max_neighbours] if d[j] < neighbour_distance]
        lines = [orca_line(p, v, radii[i], positions[j], velocities[j], radii[j], time_horizon, dt) for j in near]
        lines += [orca_line(p, v, radii[i], op, ov, orad, time_horizon, dt, share) for op, ov, orad, share in others
                  if math.hypot(op[0] - p[0], op[1] - p[1]) < neighbour_distance]
        if boxes is not None and len(boxes):
            lines += [orca_line(p, v, radii[i], q, (0.0, 0.0), 0.0, time_horizon, dt, 1.0)
                      for q in nearest[i][close[i]].tolist()]
        out[i] = solve(lines, float(max_speeds[i]), (float(preferred[i][0]), float(preferred[i][1])))
    return out
