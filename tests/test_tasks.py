"""Every registered task makes, resets, steps, ends episodes and passes gymnasium's checker."""

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import dynnav_tasks

STATE_SIZES = {
    "DynNav-OneObstacle-v1": 22,
    "DynNav-MovingTarget-v1": 20,
    "DynNav-MovingObstacles-v1": 24,
    "DynNav-MotionAreas-v1": 24,
    "DynNav-MotionAreasRoute-v1": 26,
    "DynNav-OverlappingAreas-v1": 24,
    "DynNav-VisualStaticTarget-v1": 24,
    "DynNav-VisualTargets-v1": 26,
    "DynNav-VisualMovingTargets-v1": 24,
}


def test_every_task_is_listed_with_its_state_size():
    assert set(STATE_SIZES) == set(dynnav_tasks.TASK_IDS)


def _checked(task_id, **skip):
    env = dynnav_tasks.NumpyWrapper(gym.make(task_id))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, **skip)
    assert [str(w.message) for w in caught if "WARN" in str(w.message) and "unwrapped" not in str(w.message)] == []
    env.close()
    env.close()  # closing twice is allowed


def test_check_env_with_default_arguments():
    """gymnasium's checker as a user calls it: it also re-creates the env from ``env.spec``
    (wrapper included) in render mode "rgb_array" and to check closing."""
    _checked("DynNav-MovingObstacles-v1")


def test_check_env(task_id):
    """Every task; the close check re-creates the env from its spec (the render check, which
    does the same, costs a rendered frame per task and is run once above)."""
    _checked(task_id, skip_render_check=True)


def test_make_reset_step(make_env, task_id):
    env = make_env(task_id)
    obs, info = env.reset(seed=0)
    size = STATE_SIZES[task_id]
    assert env.observation_space.shape == (size,) and obs.shape == (size,) and obs.dtype == np.float32
    assert env.action_space.n == 3
    assert sum(n for _, n in env.unwrapped.state_layout()) == size
    rng = np.random.default_rng(0)
    outcomes = {"success": 0, "collision": 0, "timeout": 0}
    for _ in range(600):
        obs, reward, terminated, truncated, info = env.step(int(rng.integers(3)))
        assert env.observation_space.contains(obs)
        assert np.isfinite(reward)
        for key in ("success", "collision", "timeout", "distance_to_target", "path_length"):
            assert key in info
        if terminated or truncated:
            assert terminated == bool(info["success"] or info["collision"])
            assert truncated == bool(info["timeout"])
            outcomes[dynnav_tasks.outcome_of(info, terminated)] += 1
            env.reset()
    assert sum(outcomes.values()) > 0


def test_state_vector_layout(make_env, task_id):
    env = make_env(task_id)
    obs, _ = env.reset(seed=3)
    base = env.unwrapped
    snap = base.snapshot
    np.testing.assert_array_equal(obs[:16], snap.lasers)
    np.testing.assert_allclose(obs[16:18], base.agent.pose2d()[:2], rtol=0, atol=1e-6)
    np.testing.assert_allclose(obs[18:20], snap.target_xy, rtol=0, atol=1e-6)
    np.testing.assert_allclose(obs[20:], snap.moving_obstacle_xy.reshape(-1), rtol=0, atol=1e-6)
    assert len(obs[20:]) == 2 * base.world.moving_obstacle_count == 2 * snap.moving_count


def test_timeout_truncates_after_200_steps(make_env):
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=1)
    for step in range(1, 201):
        obs, reward, terminated, truncated, info = env.step(1)  # spin in place at the start
        assert not terminated
        assert truncated == (step == 200)
        assert bool(info["timeout"]) == (step == 200)
    assert info["path_length"] < 1e-3  # turning in place goes nowhere (< 1 mm in 200 steps)


def test_step_after_the_end_asks_for_reset(make_env):
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    env.unwrapped.place_robot(4.0, 2.0, 0.0)
    while True:
        *_, terminated, truncated, info = env.step(0)
        if terminated:
            break
    with pytest.raises(RuntimeError, match="call reset"):
        env.step(0)


def test_forward_step_length_is_configurable(make_env):
    env = make_env("DynNav-MovingTarget-v1", forward_step=0.1, turn_step=np.pi / 2)
    env.reset(seed=0)
    base = env.unwrapped
    base.place_robot(0.0, -1.5, 0.0)
    env.step(0)
    np.testing.assert_allclose(base.agent.pose2d(), [0.1, -1.5, 0.0], atol=1e-4)
    env.step(1)  # quarter turn left, in place
    np.testing.assert_allclose(base.agent.pose2d(), [0.1, -1.5, np.pi / 2], atol=1e-4)
    env.step(0)
    np.testing.assert_allclose(base.agent.pose2d(), [0.1, -1.4, np.pi / 2], atol=1e-4)
