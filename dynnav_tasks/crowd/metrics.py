"""Social navigation metrics of one episode, accumulated step by step.

The definitions follow CrowdNav (Chen et al. 2019), SocNavGym (Kapoor et al. 2023) and the
guidelines of Francis et al. (2023, arXiv 2306.16740). Distances to a human are between the two
bodies' edges: the centres' distance less the robot's radius (its footprint's circle) and the
human's.

``min_human_distance`` (m)
    the smallest edge-to-edge distance to any human over the episode (CrowdNav's d_min;
    ``inf`` without humans).
``personal_space_compliance``
    the share of steps with no human within ``PERSONAL_SPACE`` (0.45 m, Hall's intimate zone;
    SocNavGym's threshold).
``discomfort_frequency``
    the share of steps with a human within ``DISCOMFORT`` (0.2 m) of the robot's edge
    (CrowdNav's "frequency of being in danger").
``time_to_goal`` (s)
    steps times the control step on success, else ``nan``.
``path_length`` (m), ``spl``
    the metres the robot's centre travelled; success weighted by (normalized inverse) path
    length, shortest / max(path, shortest) on success, else 0 (Anderson et al. 2018).
``path_irregularity`` (rad/m)
    the robot's total turning less the turn it needed at the start to face the target,
    per metre travelled (Guzzi et al. 2013, as Francis et al. define it; 0 if it did not move).
``jerk`` (m/s^3)
    the mean norm of the third finite difference of the robot's positions over the control
    step (``nan`` for episodes of fewer than three steps).

A step's distances are read after the step (the positions the step reached), as the outcome is.

Over many episodes (``aggregate``, what a test phase and a baseline's results report), as
CrowdNav's evaluation pools them: ``human_collision_rate`` is the share of episodes that ended
in a contact with a human; ``discomfort_frequency`` and ``personal_space_compliance`` pool the
steps of every episode (an episode of 80 steps weighs twice one of 40); ``min_human_distance``
is the mean of the episodes' minima; ``time_to_goal`` is the mean over successful episodes;
``path_length``, ``path_irregularity`` and ``jerk`` are means over the episodes that have them.
"""

from __future__ import annotations

import math

import numpy as np

PERSONAL_SPACE = 0.45
"""m between the robot's and a human's edges: closer violates personal space (SocNavGym)"""
DISCOMFORT = 0.2
"""m between the edges: closer is discomfort (CrowdNav)"""


EPISODE_METRICS = ("min_human_distance", "personal_space_compliance", "discomfort_frequency", "time_to_goal",
                   "path_length", "spl", "path_irregularity", "jerk")
"""the keys of one episode's metrics (``SocialMetrics.result``), in the final step's ``info``"""
AGGREGATE_METRICS = ("human_collision_rate", "min_human_distance", "personal_space_compliance",
                     "discomfort_frequency", "time_to_goal", "path_length", "path_irregularity", "jerk")
"""the keys of ``aggregate``'s result, in the order reports list them"""


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class SocialMetrics:
    """One episode's metrics: ``start`` at the reset, ``step`` after every step, ``result`` at the end."""

    def __init__(self, robot_radius: float, dt: float):
        self.robot_radius, self.dt = float(robot_radius), float(dt)
        self.start(0.0, 0.0, 0.0, (0.0, 0.0))

    def start(self, x: float, y: float, yaw: float, target) -> None:
        """A new episode with the robot at (x, y, yaw) and the target at ``target`` (x, y)."""
        self._positions = [(float(x), float(y))]
        self._yaw = float(yaw)
        self._needed_turn = abs(_wrap(math.atan2(target[1] - y, target[0] - x) - yaw))
        self._turned = 0.0
        self._steps = self._violations = self._discomfort = 0
        self._closest = math.inf

    def step(self, x: float, y: float, yaw: float, humans_xy=(), humans_radius=()) -> None:
        """The robot's pose after a step and the humans' centres (k, 2) and radii (k,) then."""
        self._positions.append((float(x), float(y)))
        self._turned += abs(_wrap(float(yaw) - self._yaw))
        self._yaw = float(yaw)
        self._steps += 1
        if len(humans_xy):
            h = np.asarray(humans_xy, float).reshape(-1, 2)
            gap = float((np.hypot(h[:, 0] - x, h[:, 1] - y) - np.asarray(humans_radius, float) - self.robot_radius).min())
            self._closest = min(self._closest, gap)
            self._violations += gap < PERSONAL_SPACE
            self._discomfort += gap < DISCOMFORT

    def result(self, success: bool, shortest: float) -> dict:
        """The episode's metrics (module docstring) given its outcome and the shortest way (m)."""
        p = np.asarray(self._positions)
        path = float(np.hypot(*np.diff(p, axis=0).T).sum()) if len(p) > 1 else 0.0
        steps = max(self._steps, 1)
        jerk = np.diff(p, n=3, axis=0) / self.dt ** 3 if len(p) >= 4 else np.zeros((0, 2))
        return dict(
            min_human_distance=self._closest,
            personal_space_compliance=1.0 - self._violations / steps,
            discomfort_frequency=self._discomfort / steps,
            time_to_goal=self._steps * self.dt if success else math.nan,
            path_length=path,
            spl=shortest / max(path, shortest, 1e-9) if success else 0.0,
            path_irregularity=max(self._turned - self._needed_turn, 0.0) / path if path > 0 else 0.0,
            jerk=float(np.hypot(*jerk.T).mean()) if len(jerk) else math.nan,
        )


def _mean(values) -> float | None:
    values = [float(v) for v in values if v is not None and math.isfinite(float(v))]
    return round(sum(values) / len(values), 4) if values else None


def aggregate(episodes: list[dict]) -> dict:
    """The social metrics of many episodes (module docstring), each episode a dict with its
    ``steps``, ``human_collision`` and its ``EPISODE_METRICS``; a metric no episode has is None."""
    if not episodes:
        raise ValueError("no episodes to aggregate")
    steps = [max(int(e["steps"]), 1) for e in episodes]
    total = sum(steps)

    def pooled(key: str) -> float:
        return round(sum(e[key] * n for e, n in zip(episodes, steps)) / total, 4)

    return dict(
        human_collision_rate=round(sum(bool(e["human_collision"]) for e in episodes) / len(episodes), 4),
        min_human_distance=_mean(e["min_human_distance"] for e in episodes),
        personal_space_compliance=pooled("personal_space_compliance"),
        discomfort_frequency=pooled("discomfort_frequency"),
        time_to_goal=_mean(e["time_to_goal"] for e in episodes),
        path_length=_mean(e["path_length"] for e in episodes),
        path_irregularity=_mean(e["path_irregularity"] for e in episodes),
        jerk=_mean(e["jerk"] for e in episodes),
    )


def episode_social(info: dict) -> dict | None:
    """An episode's social metrics and ``human_collision`` from its final step's ``info``
    (None in a task without pedestrians), as plain floats rounded for a results file
    (``min_human_distance`` is None when no human was there)."""
    if EPISODE_METRICS[0] not in info:
        return None
    out = dict(human_collision=bool(_item(info["human_collision"])))
    for key in EPISODE_METRICS:
        v = float(_item(info[key]))
        out[key] = round(v, 4) if math.isfinite(v) else None
    return out


def _item(value):
    return value.item() if hasattr(value, "item") else value
