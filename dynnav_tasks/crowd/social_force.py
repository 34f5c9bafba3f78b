"""The social force model of pedestrian motion (Helbing and Molnár, "Social force model for
pedestrian dynamics", Phys. Rev. E 51, 4282, 1995), in numpy.

A pedestrian i at x_i with velocity v_i, heading for its goal in direction e_i at its preferred
speed v0_i, accelerates by

    a_i = (v0_i e_i - v_i) / tau                                  (the goal: relaxation in tau)
        + sum_j w_ij (V0 / sigma) exp(-b_ij / sigma) n_ij          (every other body j)
        + sum_B (U0 / R) exp(-b_iB / R) n_iB                       (every static box and wall B)

with n_ij the unit vector from j to i, b_ij = |x_i - x_j| - r_i - r_j the gap between the two
bodies' edges and n_iB, b_iB the same towards the nearest point of B. The weight w_ij is 1 for a
body within ``sight_angle`` of e_i and ``out_of_sight_weight`` (c) behind it. The new velocity
is v_i + a_i dt, its speed capped at ``max_speed_factor`` v0_i.

The paper's repulsion is a potential of an ellipse stretched by the other's step; this is its
circular form (the ellipse's step taken to zero), with the bodies' radii subtracted so that a
bigger body is felt sooner, as in the circular specification most crowd simulators use.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SocialForceParams:
    """The model's constants; defaults are Helbing and Molnár's (1995), Sec. II."""

    relaxation_time: float = 0.5
    """tau (s): how fast a pedestrian returns to its preferred velocity"""
    strength: float = 2.1
    """V0 (m^2/s^2): the repulsive potential of another body at zero gap"""
    range: float = 0.3
    """sigma (m): the distance over which that repulsion falls by e"""
    wall_strength: float = 10.0
    """U0 (m^2/s^2): the repulsive potential of a wall or static box at zero gap"""
    wall_range: float = 0.2
    """R (m): the distance over which a wall's repulsion falls by e"""
    sight_angle: float = 100.0
    """phi (degrees): half of the field of view (2 phi = 200 degrees) in which bodies count fully"""
    out_of_sight_weight: float = 0.5
    """c: the weight of a body outside the field of view"""
    max_speed_factor: float = 1.3
    """v_max / v0: the speed a push can reach"""


def goal_directions(positions: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """Unit vectors (n, 2) from each position to its goal (zero at the goal)."""
    delta = goals - positions
    norm = np.hypot(delta[:, 0], delta[:, 1])[:, None]
    return np.divide(delta, norm, out=np.zeros_like(delta), where=norm > 1e-9)


def accelerations(positions: np.ndarray, velocities: np.ndarray, radii: np.ndarray, goals: np.ndarray,
                  preferred_speeds: np.ndarray, params: SocialForceParams = SocialForceParams(),
                  bodies: tuple[np.ndarray, np.ndarray] | None = None,
                  boxes: np.ndarray | None = None) -> np.ndarray:
    """a_i (n, 2) of each of n pedestrians (module docstring). ``bodies``: (positions (m, 2),
    radii (m,)) of other bodies they avoid but that are not pedestrians (a robot they see);
    ``boxes``: (k, 4) static boxes and walls as (lo_x, lo_y, hi_x, hi_y)."""
    e = goal_directions(positions, goals)
    a = (preferred_speeds[:, None] * e - velocities) / params.relaxation_time
    others_p, others_r = positions, radii
    if bodies is not None and len(bodies[0]):
        others_p = np.concatenate([positions, np.asarray(bodies[0], float).reshape(-1, 2)])
        others_r = np.concatenate([radii, np.asarray(bodies[1], float).reshape(-1)])
    n = len(positions)
    if len(others_p) > 1:
        delta = positions[:, None, :] - others_p[None, :, :]  # (n, n + m, 2): from j to i
        distance = np.hypot(delta[..., 0], delta[..., 1])
        gap = distance - radii[:, None] - others_r[None, :]
        unit = np.divide(delta, distance[..., None], out=np.zeros_like(delta), where=distance[..., None] > 1e-9)
        magnitude = params.strength / params.range * np.exp(-gap / params.range)
        magnitude[np.arange(n), np.arange(n)] = 0.0  # no force on oneself
        ahead = np.einsum("nd,nmd->nm", e, -unit) >= math.cos(math.radians(params.sight_angle))
        weight = np.where(ahead | (np.hypot(e[:, 0], e[:, 1]) == 0.0)[:, None], 1.0, params.out_of_sight_weight)
        a += np.einsum("nm,nmd->nd", weight * magnitude, unit)
    if boxes is not None and len(boxes):
        boxes = np.asarray(boxes, float)
        nearest = np.stack([np.clip(positions[:, None, 0], boxes[None, :, 0], boxes[None, :, 2]),
                            np.clip(positions[:, None, 1], boxes[None, :, 1], boxes[None, :, 3])], axis=-1)
        delta = positions[:, None, :] - nearest
        distance = np.hypot(delta[..., 0], delta[..., 1])
        unit = np.divide(delta, distance[..., None], out=np.zeros_like(delta), where=distance[..., None] > 1e-9)
        gap = distance - radii[:, None]
        a += np.einsum("nk,nkd->nd", params.wall_strength / params.wall_range * np.exp(-gap / params.wall_range), unit)
    return a


def step_velocities(velocities: np.ndarray, accelerations_: np.ndarray, preferred_speeds: np.ndarray, dt: float,
                    params: SocialForceParams = SocialForceParams()) -> np.ndarray:
    """v + a dt, each speed capped at ``max_speed_factor`` times its preferred speed."""
    v = velocities + accelerations_ * dt
    speed = np.hypot(v[:, 0], v[:, 1])
    cap = params.max_speed_factor * preferred_speeds
    scale = np.where(speed > cap, cap / np.maximum(speed, 1e-12), 1.0)
    return v * scale[:, None]
