"""Test-phase statistics: outcomes, the Wilson interval of the success rate, the summary.

* success rate: with a 95% Wilson score interval (sound for rates near 0 or 1, unlike the
  normal approximation).
* SPL (success weighted by path length, Anderson et al. 2018): mean over episodes of
  S_i * l_i / max(p_i, l_i), S_i = 1 on success, p_i the path the robot drove
  (``info["path_length"]``) and l_i the shortest path, taken as the straight-line distance from
  the robot's start to the target's position at the start minus the reach radius (0.3 m).
  Obstacles and the target's motion are ignored, so l_i is a lower bound.
"""

from __future__ import annotations

import math

import numpy as np

from dynnav_tasks.crowd.metrics import aggregate as aggregate_social
from dynnav_tasks.outcomes import OUTCOMES


def wilson_interval(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95% for z = 1.96)."""
    if n <= 0:
        return (math.nan, math.nan)
    p = successes / n
    denom = 1 + z * z / n
    center = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return (max(0.0, center - half), min(1.0, center + half))


def straight_shortest(start, target, reach: float) -> float:
    """The shortest path SPL takes (module docstring): the straight line from ``start`` to ``target``
    (x, y) less the reach radius."""
    return max(float(np.linalg.norm(np.subtract(target, start))) - reach, 0.0)


def spl(success: bool, shortest: float, driven: float) -> float:
    """One episode's SPL term: ``shortest / max(driven, shortest)`` on success, else 0."""
    return round(shortest / max(driven, shortest, 1e-9), 4) if success else 0.0


def summarize(records: list[dict], epsilon: float = 0.0) -> dict:
    """The test phase's summary of its episode records (each with ``outcome``, ``steps``, ``ret``
    and, for dynnav tasks, ``spl``): the rate of each outcome, the success rate's Wilson interval,
    the average steps of successes, the average return, the SPL and, in a task with pedestrians,
    ``social``: their social metrics over the episodes (``dynnav_tasks.crowd.metrics.aggregate``)."""
    n = len(records)
    count = {k: sum(r["outcome"] == k for r in records) for k in OUTCOMES}
    lo, hi = wilson_interval(count["success"], n)
    steps = [r["steps"] for r in records if r["outcome"] == "success"]
    summary = dict(
        episodes=n,
        epsilon=epsilon,
        success_rate=count["success"] / n,
        success_ci95=[round(lo, 4), round(hi, 4)],
        collision_rate=count["collision"] / n,
        timeout_rate=count["timeout"] / n,
        terminated_rate=count["terminated"] / n,
        avg_steps_success=round(float(np.mean(steps)), 2) if steps else None,
        avg_return=round(float(np.mean([r["ret"] for r in records])), 4),
    )
    if records and "spl" in records[0]:
        summary["spl"] = round(float(np.mean([r["spl"] for r in records])), 4)
    if records and "discomfort_frequency" in records[0]:  # a task with pedestrians
        summary["social"] = aggregate_social(records)
    return summary
