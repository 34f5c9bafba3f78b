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


def orca_lines(position, velocity, radius, others_position: np.ndarray, others_velocity: np.ndarray,
               others_radius, time_horizon: float, dt: float, responsibility) -> tuple[np.ndarray, np.ndarray]:
    """The ORCA half-planes of m (agent, neighbour) pairs, as RVO2's ``computeNewVelocity`` makes
    them, in one numpy pass: (points (m, 2), directions (m, 2)). The agents' positions, velocities
    and radii and the neighbours' are (m, 2) / (m,) arrays or one value for all pairs;
    responsibility likewise. Apart: the velocity obstacle's cone cut off at ``time_horizon``,
    projected on its cut-off circle or on a leg; overlapping: the circle of one step ``dt``."""
    rp = np.asarray(others_position, dtype=np.float64) - np.asarray(position, dtype=np.float64)
    m = len(rp)
    rv = np.asarray(velocity, dtype=np.float64) - np.asarray(others_velocity, dtype=np.float64)
    dist_sq = (rp * rp).sum(1)
    r = np.broadcast_to(np.asarray(radius, dtype=np.float64) + np.asarray(others_radius, dtype=np.float64), (m,))
    r_sq = r * r
    apart = dist_sq > r_sq
    inv_t = np.where(apart, 1.0 / time_horizon, 1.0 / dt)  # overlapping: separate within one step
    w = rv - inv_t[:, None] * rp
    w_sq = (w * w).sum(1)
    dot1 = (w * rp).sum(1)
    cut = ~apart | ((dot1 < 0.0) & (dot1 * dot1 > r_sq * w_sq))  # nearest the cut-off circle
    w_len = np.sqrt(w_sq)
    degenerate = w_len < EPSILON
    unit = np.where(degenerate[:, None], [1.0, 0.0], w / np.where(degenerate, 1.0, w_len)[:, None])
    w_len = np.where(degenerate, 1.0, w_len)
    cut_dir = np.stack([unit[:, 1], -unit[:, 0]], axis=1)
    cut_u = ((r * inv_t - w_len)[:, None]) * unit
    leg = np.sqrt(np.maximum(dist_sq - r_sq, 0.0))
    left = rp[:, 0] * w[:, 1] - rp[:, 1] * w[:, 0] > 0.0
    safe = np.where(apart, dist_sq, 1.0)
    left_dir = np.stack([rp[:, 0] * leg - rp[:, 1] * r, rp[:, 0] * r + rp[:, 1] * leg], axis=1) / safe[:, None]
    right_dir = -np.stack([rp[:, 0] * leg + rp[:, 1] * r, -rp[:, 0] * r + rp[:, 1] * leg], axis=1) / safe[:, None]
    leg_dir = np.where(left[:, None], left_dir, right_dir)
    leg_u = (rv * leg_dir).sum(1)[:, None] * leg_dir - rv
    direction = np.where(cut[:, None], cut_dir, leg_dir)
    u = np.where(cut[:, None], cut_u, leg_u)
    share = np.broadcast_to(np.asarray(responsibility, dtype=np.float64), (m,))
    return np.asarray(velocity, dtype=np.float64) + share[:, None] * u, direction


def orca_line(position, velocity, radius: float, other_position, other_velocity, other_radius: float,
              time_horizon: float, dt: float, responsibility: float = 0.5) -> Line:
    """The ORCA half-plane of the agent at ``position`` with ``velocity`` and ``radius`` towards one
    neighbour (all in m and m/s), as RVO2 computes it (``orca_lines`` for one pair)."""
    point, direction = orca_lines(position, velocity, radius, np.asarray([other_position], dtype=np.float64),
                                  np.asarray([other_velocity], dtype=np.float64), other_radius, time_horizon, dt,
                                  responsibility)
    return Line(tuple(point[0].tolist()), tuple(direction[0].tolist()))


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
    positions, velocities = np.asarray(positions, dtype=np.float64), np.asarray(velocities, dtype=np.float64)
    radii, max_speeds = np.asarray(radii, dtype=np.float64), np.asarray(max_speeds, dtype=np.float64)
    # every (agent, neighbour) pair's half-plane in one numpy pass, then each agent's linear program
    agent, other, share, o_pos, o_vel, o_rad = [], [], [], [], [], []
    if n > 1:
        d = np.hypot(*(positions[:, None, :] - positions[None, :, :]).transpose(2, 0, 1))
        np.fill_diagonal(d, np.inf)
        order = np.argsort(d, axis=1, kind="stable")[:, :max_neighbours]
        keep = np.take_along_axis(d, order, axis=1) < neighbour_distance
        rows, cols = np.nonzero(keep)
        agent.append(rows)
        other.append(order[rows, cols])
        share.append(np.full(len(rows), 0.5))
    pairs_agent = np.concatenate(agent) if agent else np.zeros(0, int)
    pairs_other = np.concatenate(other) if other else np.zeros(0, int)
    points = [positions[pairs_other]]
    vels, rads, shares = [velocities[pairs_other]], [radii[pairs_other]], [np.concatenate(share) if share else np.zeros(0)]
    for op, ov, orad, responsibility in others:  # neighbours that are not ORCA agents
        close = np.flatnonzero(np.hypot(*(positions - np.asarray(op, dtype=np.float64)).T) < neighbour_distance)
        pairs_agent = np.concatenate([pairs_agent, close])
        points.append(np.tile(np.asarray(op, dtype=np.float64), (len(close), 1)))
        vels.append(np.tile(np.asarray(ov, dtype=np.float64), (len(close), 1)))
        rads.append(np.full(len(close), float(orad)))
        shares.append(np.full(len(close), float(responsibility)))
    if boxes is not None and len(boxes):
        boxes = np.asarray(boxes, dtype=np.float64)
        nearest = np.stack([np.clip(positions[:, None, 0], boxes[None, :, 0], boxes[None, :, 2]),
                            np.clip(positions[:, None, 1], boxes[None, :, 1], boxes[None, :, 3])], axis=-1)  # (n, k, 2)
        reach = time_horizon * max_speeds + radii
        rows, cols = np.nonzero(np.hypot(*(nearest - positions[:, None, :]).transpose(2, 0, 1)) < reach[:, None])
        pairs_agent = np.concatenate([pairs_agent, rows])
        points.append(nearest[rows, cols])
        vels.append(np.zeros((len(rows), 2)))
        rads.append(np.zeros(len(rows)))
        shares.append(np.ones(len(rows)))
    point, direction = orca_lines(positions[pairs_agent], velocities[pairs_agent], radii[pairs_agent],
                                  np.concatenate(points), np.concatenate(vels), np.concatenate(rads), time_horizon, dt,
                                  np.concatenate(shares))
    lines: list[list[Line]] = [[] for _ in range(n)]
    for i, p, q in zip(pairs_agent.tolist(), point.tolist(), direction.tolist()):
        lines[i].append(Line(tuple(p), tuple(q)))
    out = np.zeros((n, 2))
    for i in range(n):
        out[i] = solve(lines[i], float(max_speeds[i]), (float(preferred[i][0]), float(preferred[i][1])))
    return out
