"""Each reward function against values worked out by hand (defaults: g=0.2, A=0.5,
threshold 0.8 m, orientation scale 1, gamma_p=0.9, A_p=1, B_p=-0.5)."""

import math

import pytest

from dynnav_tasks.rewards import REWARD_MODES, RewardInputs, RewardParams, compute_reward

P = RewardParams()
E04 = 1.4918246976412703  # exp(0.2 * 2.0)


def inputs(**kw):
    base = dict(d1=2.0, d1_prev=2.15, d2=0.5, d2_prev=0.6, bearing=0.1, bearing_prev=0.4, reached=False, collided=False)
    base.update(kw)
    return RewardInputs(**base)


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
        ("sparse", NEAR, -0.01),
    ],
)
def test_step_rewards_match_hand_values(mode, x, expected):
    assert compute_reward(mode, x, P) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("mode", REWARD_MODES)
def test_terminal_rewards_replace_shaping(mode):
    reach, crash = (1.0, -1.0) if mode == "sparse" else (20.0, -20.0)
    assert compute_reward(mode, inputs(reached=True), P) == reach
    assert compute_reward(mode, inputs(collided=True), P) == crash
    # a collision on the target is still a collision
    assert compute_reward(mode, inputs(reached=True, collided=True), P) == crash


def test_orientation_term_rewards_turning_towards_the_target():
    towards = compute_reward("distance_orientation_always", inputs(d2=9, bearing=0.2, bearing_prev=-0.6), P)
    away = compute_reward("distance_orientation_always", inputs(d2=9, bearing=-0.6, bearing_prev=0.2), P)
    assert towards == pytest.approx(1 - E04 + 0.4)
    assert away == pytest.approx(1 - E04 - 0.4)


def test_distance_penalty_grows_with_distance():
    values = [compute_reward("distance", inputs(d1=d, d2=9), P) for d in (0.5, 1, 2, 4, 8)]
    assert values == sorted(values, reverse=True)
    assert values[0] == pytest.approx(1 - math.exp(0.1))


def test_potential_penalises_standing_still():
    # gamma_p < 1: staying put loses (1 - 0.9) * Phi
    assert compute_reward("potential", inputs(d1=2.0, d1_prev=2.0, d2=9, d2_prev=9), P) == pytest.approx(-0.05)


def test_params_change_the_constants():
    p = RewardParams(distance_gamma=0.1, obstacle_scale=1.0, obstacle_threshold=0.4)
    assert compute_reward("distance", NEAR, p) == pytest.approx(1 - math.exp(0.2))  # 0.5 m is no longer near
    assert compute_reward("distance", inputs(d2=0.25), p) == pytest.approx(1 - math.exp(0.2) - 4.0)


def test_unknown_reward_parameter_is_named():
    with pytest.raises(ValueError, match=r"'distance_gama'.*Did you mean 'distance_gamma'"):
        RewardParams.from_dict({"distance_gama": 0.3})
