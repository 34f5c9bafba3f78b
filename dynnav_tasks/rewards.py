"""The reward functions of the study and ManiSkill's reward modes, selected with ``reward_mode``.

Every function reads the snapshots before and after the step (``snapshot.StepSnapshot``:
only their ``d1``, ``d2`` and ``bearing``) and the task's ``RewardParams``; whether the step
reached the target or collided comes from ``NavEnv.evaluate``. Each function is defined here
and nowhere else.

Symbols: d1 = distance from the robot's centre to the target's centre; d2 = distance from
the robot's centre to the nearest obstacle box (walls are not obstacles; infinite when the
world has none); "near" means d2 <= ``obstacle_threshold``.

=================================  ===========================================================
reward_mode                        reward of a step that neither reaches nor collides
=================================  ===========================================================
``sparse`` (Eq. 3.1)               ``sparse_step`` (-0.01); reach +1, collision -1
``distance`` (Eq. 4.2/4.3)         1 - exp(g d1') [- A / d2' when near]
``distance_orientation`` (4.5)     1 - exp(g d1') - A / d2' when near, else 1 - exp(g d1') + r_o
``distance_orientation_always``    1 - exp(g d1') + r_o [- A / d2' when near]   (default)
(Eq. 4.6)
``potential`` (Eq. 4.8/4.9)        gamma_p * Phi(s') - Phi(s), Phi = A_p / d1 [+ B_p / d2 near]
``potential_as_written`` (4.9)     near: as ``potential``; else gamma_p * (A_p / d1' - A_p / d1)
=================================  ===========================================================

Beyond the study's, dynnav's own (``EXTRA_REWARD_MODES``):

=================================  ===========================================================
``progress``                       k (d1 - d1'): the metres the step brought the robot nearer
                                   the target, times ``progress_scale`` k
=================================  ===========================================================

``progress`` is potential-based shaping with Phi = -k d1 and no discount inside it (Ng et al.
1999), the progress term of NavRep's and Arena-Rosnav's rewards: over an episode its steps sum to
k times the distance gained, whatever the way, so ending an episode early never pays more than
reaching the target, and standing still costs nothing but the discount. The study's
rewards charge every step (1 - exp(g d1) < 0), which makes an early crash the better deal for a
learner that discounts little (``examples/sb3_continuous_drive.py``: PPO at gamma 0.99 learned
to crash under them); it is the reward of the Stable-Baselines3 recipe (docs/sb3.md).

All but ``sparse`` give +20 on reaching the target and -20 on a collision, alone (no
shaping term is added on those steps). ``'`` marks the state after the step.

Readings chosen where the thesis is ambiguous (each is tested in tests/test_rewards.py):

* Eq. 4.1 writes ``1 - exp(-g d)`` (a reward between 0 and 1 that grows with distance) and
  Eq. 4.2 ``1 - exp(+g d)``; only the second is a penalty that grows with distance, so it is
  the one used, with g = 0.2 as the thesis settled on.
* Eq. 4.4 defines r_o as the change of ``arctan((y - y_t) / (x - x_t))`` between steps: the
  azimuth of the robot around the target, which does not change when the robot drives
  straight at the target and so cannot reward "taking the action with direction toward the
  target" as the text intends. We use the reading that does: the azimuth of the target *seen
  from the robot*, relative to its heading, alpha = wrap(atan2(y_t - y, x_t - x) - yaw), and
  r_o = (|alpha| - |alpha'|) * ``orientation_scale``: positive when a step turns the robot
  towards the target, negative when it turns away.
* Eq. 4.9's far-from-obstacles branch reads ``gamma (A/d1' - A/d1)``, gamma multiplying both
  terms: not a potential difference, and it gives nothing for standing still, contradicting
  the text ("the agent will get penalty even though it stays in the same position") and
  Eq. 4.8. Both readings are offered: ``potential`` is potential-based shaping as Eq. 4.8 and
  the text describe, F = gamma_p * Phi(s') - Phi(s), with the obstacle term B_p / d2 in Phi
  only when near an obstacle; ``potential_as_written`` is Eq. 4.9 letter for letter (its near
  branch is the same as ``potential``'s). At gamma_p = 1 the two differ only on a step that
  leaves an obstacle's reach: the shaping then pays back the B_p / d2 it charged before the
  step, Eq. 4.9 as written does not.
* A_p: the study says only that the potential "can be adjusted according to the learning
  efficiency"; it is ``potential_target`` (default 1.0), set per experiment in its config.

ManiSkill's reward modes (``MANISKILL_REWARD_MODES``), so that ManiSkill's tools run on the tasks:

======================  ==================================================================
reward_mode             reward
======================  ==================================================================
``dense``               the task's default reward, ``distance_orientation_always`` (Eq. 4.6),
                        with the task's ``RewardParams``: the same value, step for step
``normalized_dense``    that reward divided by ``dense_bound``, so every reward is in [-1, 1]
                        (+1 on reaching the target and -1 on a collision with the defaults)
``sparse``              the study's own sparse reward (Eq. 3.1, above); ManiSkill's default
                        sparse reward, ``success - fail``, is the same but for the -0.01 of
                        every other step: ``reward_params={"sparse_step": 0.0}`` gives it
                        exactly (a task's ``fail`` is its collision)
``none``                0 on every step
======================  ==================================================================

``dense_bound``, the largest |reward| ``dense`` can give: a step that reaches the target
gives ``reach_reward`` and one that collides ``collision_reward``; any other step gives the
sum of three terms, each bounded on its own:

* |1 - exp(g d1')| <= |1 - exp(g D)|, D the world's ``World.span()``: the robot's centre and
  the target both stay in the arena, and 1 - exp(g d) is monotonic in d and 0 at d = 0;
* |r_o| = | |alpha| - |alpha'| | * |orientation_scale| <= pi * |orientation_scale|, as
  alpha is in [-pi, pi);
* |A / d2'| <= |A| / r, r the radius of the largest circle in the robot's footprint (0.19 m):
  a step that does not collide leaves the footprint clear of every box, so its centre is at
  least r from each (and the term is 0 when ``obstacle_threshold`` < r).

dense_bound = max(|reach_reward|, |collision_reward|, the sum of the three). With the
default parameters in the 6.5 m x 6.5 m arena the sum is 5.29 + 3.14 + 2.63 = 11.06, so the
+-20 of reaching and colliding dominate and the bound is 20 (tests/test_reward_modes.py
drives episodes that reach the target and collide, and checks the bound and the division).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, fields
from typing import Protocol

REWARD_MODES = (
    "distance_orientation_always",
    "distance_orientation",
    "distance",
    "potential",
    "potential_as_written",
    "sparse",
)
DEFAULT_REWARD_MODE = "distance_orientation_always"
"""The study's reward of a task made without a ``reward_mode``, and ManiSkill's ``dense``"""
EXTRA_REWARD_MODES = ("progress",)
"""dynnav's rewards beyond the study's (see above)"""
MANISKILL_REWARD_MODES = ("dense", "normalized_dense", "none")
"""ManiSkill's names for the default reward, it normalised, and no reward (see above)"""
SUPPORTED_REWARD_MODES = REWARD_MODES + EXTRA_REWARD_MODES + MANISKILL_REWARD_MODES


@dataclass(frozen=True)
class RewardParams:
    """Constants of the reward functions (defaults from the thesis where it gives them)."""

    reach_reward: float = 20.0
    """reward for reaching the target (all modes but sparse)"""
    collision_reward: float = -20.0
    """reward for a collision (all modes but sparse)"""
    distance_gamma: float = 0.2
    """g in 1 - exp(g d1) (thesis Fig. 6.7 picked 0.2)"""
    obstacle_scale: float = 0.5
    """A in -A / d2 (Eq. 4.5/4.6 use 0.5)"""
    obstacle_threshold: float = 0.8
    """d2 (m) at or below which the obstacle terms apply"""
    orientation_scale: float = 1.0
    """factor on r_o"""
    potential_gamma: float = 0.9
    """gamma_p of the potential shaping (Table 6.1: 0.9 was best)"""
    potential_target: float = 1.0
    """A_p > 0 in Phi = A_p / d1 + B_p / d2"""
    potential_obstacle: float = -0.5
    """B_p < 0 in Phi = A_p / d1 + B_p / d2"""
    progress_scale: float = 1.0
    """k in ``progress``'s k (d1 - d1'): reward per metre gained on the target"""
    sparse_reach: float = 1.0
    """sparse mode: reward for reaching the target"""
    sparse_collision: float = -1.0
    """sparse mode: reward for a collision"""
    sparse_step: float = -0.01
    """sparse mode: reward of every other step"""

    @classmethod
    def from_dict(cls, values: dict | None) -> "RewardParams":
        """The parameters from a dict of overrides; an unknown name is refused with the close matches."""
        values = dict(values or {})
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            from .errors import close_matches_message

            raise ValueError(
                "unknown reward parameter(s) " + ", ".join(repr(u) for u in unknown) + "; "
                + close_matches_message(unknown[0], sorted(known), "reward parameter")
            )
        return cls(**values)

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"reward parameter {f.name!r} must be a finite number, got {value!r}")
            object.__setattr__(self, f.name, float(value))


class Geometry(Protocol):
    """What a reward reads of a step's snapshot (``StepSnapshot`` has all three)."""

    d1: float
    d2: float
    bearing: float
    """alpha in radians, the target's azimuth seen from the robot relative to its heading"""


def _distance_term(cur: Geometry, p: RewardParams) -> float:
    return 1.0 - math.exp(p.distance_gamma * cur.d1)


def _near(d2: float, p: RewardParams) -> bool:
    return d2 <= p.obstacle_threshold


def _obstacle_term(cur: Geometry, p: RewardParams) -> float:
    return -p.obstacle_scale / cur.d2 if _near(cur.d2, p) else 0.0


def orientation_term(prev: Geometry, cur: Geometry, p: RewardParams) -> float:
    """r_o: how much the step reduced the angle between heading and target direction."""
    return (abs(prev.bearing) - abs(cur.bearing)) * p.orientation_scale


def potential(d1: float, d2: float, p: RewardParams) -> float:
    """Phi(s) = A_p / d1 (+ B_p / d2 when near an obstacle)."""
    phi = p.potential_target / d1
    if _near(d2, p):
        phi += p.potential_obstacle / d2
    return phi


def distance(prev: Geometry, cur: Geometry, p: RewardParams) -> float:
    """Eq. 4.2/4.3: 1 - exp(g d1') [- A / d2' when near]."""
    return _distance_term(cur, p) + _obstacle_term(cur, p)


def distance_orientation(prev: Geometry, cur: Geometry, p: RewardParams) -> float:
    """Eq. 4.5: the obstacle term when near, else the orientation term r_o."""
    if _near(cur.d2, p):
        return _distance_term(cur, p) + _obstacle_term(cur, p)
    return _distance_term(cur, p) + orientation_term(prev, cur, p)


def distance_orientation_always(prev: Geometry, cur: Geometry, p: RewardParams) -> float:
    """Eq. 4.6 (the default, and ManiSkill's ``dense``): 1 - exp(g d1') + r_o [- A / d2' when near]."""
    return _distance_term(cur, p) + orientation_term(prev, cur, p) + _obstacle_term(cur, p)


def potential_shaping(prev: Geometry, cur: Geometry, p: RewardParams) -> float:
    """Eq. 4.8: gamma_p * Phi(s') - Phi(s)."""
    return p.potential_gamma * potential(cur.d1, cur.d2, p) - potential(prev.d1, prev.d2, p)


def potential_as_written(prev: Geometry, cur: Geometry, p: RewardParams) -> float:
    """Eq. 4.9 letter for letter (see the module docstring)."""
    if _near(cur.d2, p):
        return potential_shaping(prev, cur, p)
    return p.potential_gamma * (p.potential_target / cur.d1 - p.potential_target / prev.d1)


def progress(prev: Geometry, cur: Geometry, p: RewardParams) -> float:
    """dynnav's ``progress``: k (d1 - d1'), the potential -k d1's difference (see the module docstring)."""
    return p.progress_scale * (prev.d1 - cur.d1)


_SHAPED = {
    "distance": distance,
    "distance_orientation": distance_orientation,
    "distance_orientation_always": distance_orientation_always,
    "potential": potential_shaping,
    "potential_as_written": potential_as_written,
    "progress": progress,
}
_SHAPED["dense"] = _SHAPED[DEFAULT_REWARD_MODE]


def dense_bound(p: RewardParams, span: float, clearance: float) -> float:
    """The largest |reward| of ``dense`` (see the module docstring): ``span`` bounds the
    robot's distance to the target (m), ``clearance`` the distance from its centre to any
    obstacle box on a step without collision (m, > 0)."""
    if not (span >= 0 and clearance > 0):
        raise ValueError(f"dense_bound needs span >= 0 and clearance > 0, got {span!r} and {clearance!r}")
    shaping = abs(1.0 - math.exp(p.distance_gamma * span)) + math.pi * abs(p.orientation_scale)
    if p.obstacle_threshold >= clearance:
        shaping += abs(p.obstacle_scale) / clearance
    return max(abs(p.reach_reward), abs(p.collision_reward), shaping)


def compute_reward(
    mode: str, prev: Geometry, cur: Geometry, p: RewardParams, *, reached: bool, collided: bool,
    bound: float | None = None,
) -> float:
    """The reward of the step from snapshot ``prev`` to snapshot ``cur`` under ``mode``.

    ``reached`` and ``collided`` are the step's outcome as ``NavEnv.evaluate`` decided it;
    ``bound``: ``dense_bound`` of the task, which ``normalized_dense`` divides by.
    """
    if mode == "none":
        return 0.0
    if mode == "normalized_dense":
        if bound is None:
            raise ValueError("reward_mode 'normalized_dense' needs the task's bound: pass bound=dense_bound(...)")
        dense = compute_reward("dense", prev, cur, p, reached=reached, collided=collided)
        return dense / bound if bound > 0 else 0.0  # a bound of 0: every dense reward is 0
    if mode == "sparse":
        return p.sparse_collision if collided else p.sparse_reach if reached else p.sparse_step
    if collided:
        return p.collision_reward
    if reached:
        return p.reach_reward
    return _SHAPED[mode](prev, cur, p)
