"""Each reward function against values worked out by hand (defaults: g=0.2, A=0.5,
threshold 0.8 m, orientation scale 1, gamma_p=0.9, A_p=1, B_p=-0.5)."""

import math

import numpy as np
import pytest

from dynnav_tasks.rewards import EXTRA_REWARD_MODES, REWARD_MODES, RewardParams, compute_reward
from dynnav_tasks.snapshot import take_snapshot

P = RewardParams()
E04 = 1.4918246976412703  # exp(0.2 * 2.0)


class Step:
    """A step from one snapshot to the next, for the rewards' (prev, cur) interface."""

    def __init__(self, prev, cur, reached=False, collided=False):
        self.prev, self.cur, self.reached, self.collided = prev, cur, reached, collided


def snap(d1, d2, bearing):
    """A snapshot with these distances and bearing: robot at the origin facing +x, the target
    d1 away at the bearing, one 0.5 m box straight behind with its near face d2 away."""
    target = (d1 * math.cos(bearing), d1 * math.sin(bearing))
    return take_snapshot(step=1, pose=(0.0, 0.0, 0.0), lasers=[5.0] * 16, target_xy=target, static_xy=[(-d2 - 0.25, 0.0)],
                         moving_xy=np.zeros((0, 2)), obstacle_half=[(0.25, 0.25)], contact=False)


def inputs(d1=2.0, d1_prev=2.15, d2=0.5, d2_prev=0.6, bearing=0.1, bearing_prev=0.4, reached=False, collided=False):
    return Step(snap(d1_prev, d2_prev, bearing_prev), snap(d1, d2, bearing), reached, collided)


def reward(mode, x, p=P):
    return compute_reward(mode, x.prev, x.cur, p, reached=x.reached, collided=x.collided)


NEAR = inputs()  # nearest obstacle 0.5 m away (<= 0.8): obstacle terms on
FAR = inputs(d2=2.0, d2_prev=2.0)  # obstacle terms off


@pytest.mark.parametrize(
    "mode, x, expected",
    [
        # 1 - e^0.4 - 0.5/0.5
        ("distance", NEAR, 1 - E04 - 1.0),
        ("distance", FAR, 1 - E04),
        # near an obstacle Eq. 4.5 drops the orientation term
        ("distance_orientation", NEAR, 1 - E04 - 1.0),
        # r_o = |0.4| - |0.1| = 0.3
        ("distance_orientation", FAR, 1 - E04 + 0.3),
        ("distance_orientation_always", NEAR, 1 - E04 + 0.3 - 1.0),
        ("distance_orientation_always", FAR, 1 - E04 + 0.3),
        # Phi' = 1/2 - 0.5/0.5 = -0.5 ; Phi = 1/2.15 - 0.5/0.6 ; F = 0.9 Phi' - Phi
        ("potential", NEAR, 0.9 * -0.5 - (1 / 2.15 - 0.5 / 0.6)),
        ("potential", FAR, 0.9 * 0.5 - 1 / 2.15),
        # Eq. 4.9 as written: the same near an obstacle, gamma (A/d1' - A/d1) elsewhere
        ("potential_as_written", NEAR, 0.9 * -0.5 - (1 / 2.15 - 0.5 / 0.6)),
        ("potential_as_written", FAR, 0.9 * (0.5 - 1 / 2.15)),
        ("sparse", NEAR, -0.01),
        # the 0.15 m gained on the target; obstacles and bearing play no part
        ("progress", NEAR, 0.15),
        ("progress", FAR, 0.15),
    ],
)
def test_step_rewards_match_hand_values(mode, x, expected):
    assert reward(mode, x) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("mode", REWARD_MODES + EXTRA_REWARD_MODES)
def test_terminal_rewards_replace_shaping(mode):
    reach, crash = (1.0, -1.0) if mode == "sparse" else (20.0, -20.0)
    assert reward(mode, inputs(reached=True), P) == reach
    assert reward(mode, inputs(collided=True), P) == crash
    # a collision on the target is still a collision
    assert reward(mode, inputs(reached=True, collided=True), P) == crash


def test_orientation_term_rewards_turning_towards_the_target():
    towards = reward("distance_orientation_always", inputs(d2=9, bearing=0.2, bearing_prev=-0.6))
    away = reward("distance_orientation_always", inputs(d2=9, bearing=-0.6, bearing_prev=0.2))
    assert towards == pytest.approx(1 - E04 + 0.4)
    assert away == pytest.approx(1 - E04 - 0.4)


def test_distance_penalty_grows_with_distance():
    values = [reward("distance", inputs(d1=d, d2=9)) for d in (0.5, 1, 2, 4, 8)]
    assert values == sorted(values, reverse=True)
    assert values[0] == pytest.approx(1 - math.exp(0.1))


def test_potential_penalises_standing_still():
    # gamma_p < 1: staying put loses (1 - 0.9) * Phi
    assert reward("potential", inputs(d1=2.0, d1_prev=2.0, d2=9, d2_prev=9)) == pytest.approx(-0.05)


def test_potential_as_written_pays_nothing_for_standing_still():
    still = inputs(d1=2.0, d1_prev=2.0, d2=9, d2_prev=9)
    assert reward("potential_as_written", still) == 0.0
    closer = reward("potential_as_written", inputs(d1=1.9, d1_prev=2.0, d2=9, d2_prev=9))
    assert closer == pytest.approx(0.9 * (1 / 1.9 - 1 / 2.0))


def test_at_gamma_1_the_two_potential_readings_differ_only_when_leaving_an_obstacle():
    p = RewardParams(potential_gamma=1.0, potential_target=3.0)
    for x in (NEAR, FAR, inputs(d1=1.0, d1_prev=1.2, d2=9, d2_prev=9)):
        assert reward("potential_as_written", x, p) == pytest.approx(reward("potential", x, p), abs=1e-12)
    # except on the step that leaves an obstacle's reach: the shaping returns B_p / d2(s)
    leaving = inputs(d2=2.0, d2_prev=0.6)
    assert reward("potential", leaving, p) == pytest.approx(3.0 / 2.0 - (3.0 / 2.15 - 0.5 / 0.6), abs=1e-12)
    assert reward("potential_as_written", leaving, p) == pytest.approx(3.0 / 2.0 - 3.0 / 2.15, abs=1e-12)


def test_params_change_the_constants():
    p = RewardParams(distance_gamma=0.1, obstacle_scale=1.0, obstacle_threshold=0.4)
    assert reward("distance", NEAR, p) == pytest.approx(1 - math.exp(0.2))  # 0.5 m is no longer near
    assert reward("distance", inputs(d2=0.25), p) == pytest.approx(1 - math.exp(0.2) - 4.0)


def test_unknown_reward_parameter_is_named():
    with pytest.raises(ValueError, match=r"'distance_gama'.*Did you mean 'distance_gamma'"):
        RewardParams.from_dict({"distance_gama": 0.3})


def test_snapshot_geometry_is_hand_computed():
    """Robot at (1, 1) facing north; target at (4, 5): d1 = 5, bearing = atan2(4, 3) - pi/2
    (to the right); boxes: (1, 3) with half 0.5 -> 1.5 m, (5, 1) half 0.25 -> 3.75 m."""
    s = take_snapshot(step=3, pose=(1.0, 1.0, math.pi / 2), lasers=np.arange(16), target_xy=(4.0, 5.0),
                      static_xy=[(1.0, 3.0)], moving_xy=[(5.0, 1.0)], obstacle_half=[(0.5, 0.5), (0.25, 0.25)],
                      contact=False)
    assert s.d1 == pytest.approx(5.0) and s.d2 == pytest.approx(1.5)
    assert s.bearing == pytest.approx(math.atan2(4, 3) - math.pi / 2) and s.bearing < 0
    np.testing.assert_array_equal(s.moving_obstacle_xy, [[5.0, 1.0]])
    np.testing.assert_allclose(s.state_vector(), [*range(16), 1, 1, 4, 5, 5, 1])
    with pytest.raises(ValueError):
        s.lasers[0] = 9.0  # read-only


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), "0.2", True])
def test_reward_parameters_must_be_finite_numbers(bad):
    with pytest.raises(ValueError, match=r"reward parameter 'distance_gamma' must be a finite number"):
        RewardParams.from_dict({"distance_gamma": bad})


def test_progress_sums_to_the_distance_gained_whatever_the_way():
    """Over a detour, a retreat and a wait, progress adds up to k times d1(start) - d1(end): ending
    an episode early never pays more than getting nearer."""
    p = RewardParams(progress_scale=2.5)
    way = [3.0, 2.8, 2.9, 2.9, 2.2, 1.0]
    total = sum(reward("progress", inputs(d1=b, d1_prev=a, d2=9, d2_prev=9), p) for a, b in zip(way, way[1:]))
    assert total == pytest.approx(2.5 * (3.0 - 1.0))
    assert reward("progress", inputs(d1=2.0, d1_prev=2.0), p) == 0.0
