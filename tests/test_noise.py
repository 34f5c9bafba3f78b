"""Noise and per-episode randomization (``dynnav_tasks.noise``): off by default, seeded from
the reset's seed, apart from the world's own draws, and only in what the agent observes."""

import math

import numpy as np
import pytest

from dynnav_tasks.noise import NoiseConfig

TASK = "DynNav-MovingObstacles-v1"
SENSOR_NOISE = dict(laser_noise_std=0.05, laser_dropout=0.1, odometry_drift_std=0.02)
ALL_NOISE = dict(SENSOR_NOISE, action_noise=0.3, robot_speed_scale_min=0.7, robot_speed_scale_max=1.3,
                 obstacle_speed_scale_min=0.5, obstacle_speed_scale_max=1.5)
ACTIONS = np.random.default_rng(5).integers(0, 3, size=30)


def _run(env, seed, actions=ACTIONS):
    """Observations, true snapshots and rewards of one episode driven by ``actions``."""
    obs, _ = env.reset(seed=seed)
    observations, snapshots, rewards = [obs], [env.unwrapped.snapshot], []
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(int(a))
        observations.append(obs)
        snapshots.append(env.unwrapped.snapshot)
        rewards.append(reward)
        if terminated or truncated:
            break
    return np.array(observations), snapshots, rewards


def test_noise_is_off_by_default(make_env):
    env = make_env(TASK)
    env.reset(seed=0)
    base = env.unwrapped
    assert base.noise_config == NoiseConfig() and not base.noise_config.enabled
    assert base.episode_noise is None
    assert base.observed_snapshot is base.snapshot


def test_a_seed_replays_the_noise_and_another_seed_does_not(make_env):
    env = make_env(TASK, **ALL_NOISE)
    first, truth, _ = _run(env, seed=4)
    factors = (env.unwrapped.episode_noise.robot_speed_factor, env.unwrapped.episode_noise.obstacle_speed_factor)
    _run(env, seed=9)  # something else in between
    again, _, _ = _run(env, seed=4)
    assert np.array_equal(first, again)  # bit for bit
    assert factors == (env.unwrapped.episode_noise.robot_speed_factor, env.unwrapped.episode_noise.obstacle_speed_factor)
    other = make_env(TASK, **ALL_NOISE)  # a second task made alike replays it too
    assert np.array_equal(_run(other, seed=4)[0], first)
    seen, true, _ = _run(other, seed=5)
    assert not np.array_equal(seen[0, :16] - true[0].lasers, first[0, :16] - truth[0].lasers)  # other noise


def test_sensor_noise_leaves_the_world_and_the_truth_alone(make_env):
    """With laser noise, dropout and drift on, the true episode (start, obstacles, poses,
    rewards, outcome) is the noise-free one; only the observations differ."""
    clean_obs, clean, clean_rewards = _run(make_env(TASK), seed=2)
    noisy_obs, noisy, noisy_rewards = _run(make_env(TASK, **SENSOR_NOISE), seed=2)
    assert len(noisy) == len(clean)
    for a, b in zip(clean, noisy):
        assert a.pose == b.pose and a.contact == b.contact and a.d1 == b.d1
        assert np.array_equal(a.lasers, b.lasers)
        assert np.array_equal(a.moving_obstacle_xy, b.moving_obstacle_xy)
    assert noisy_rewards == clean_rewards
    assert not np.array_equal(noisy_obs[:, :16], clean_obs[:, :16])
    assert not np.array_equal(noisy_obs[1:, 16:18], clean_obs[1:, 16:18])
    assert np.array_equal(noisy_obs[:, 18:], clean_obs[:, 18:])  # target and obstacles: exact


def test_action_noise_and_robot_speeds_leave_the_obstacles_alone(make_env):
    """The obstacles' draws come from the world's generator, untouched by the noise's."""
    clean = _run(make_env(TASK), seed=6, actions=[1] * 20)[1]
    noisy = _run(make_env(TASK, action_noise=0.5, robot_speed_scale_min=0.5, robot_speed_scale_max=1.5,
                          laser_noise_std=0.1), seed=6, actions=[1] * 20)[1]
    n = min(len(clean), len(noisy))
    assert n > 5
    for a, b in zip(clean[:n], noisy[:n]):
        assert np.array_equal(a.moving_obstacle_xy, b.moving_obstacle_xy)
    assert clean[0].pose == noisy[0].pose  # the start too


def test_laser_readings_are_noisy_dropped_and_clipped(make_env):
    env = make_env(TASK, laser_noise_std=0.5, laser_range=3.0)
    env.reset(seed=0)
    base = env.unwrapped
    errors = []
    for _ in range(10):
        obs, *_ = env.step(1)
        true, seen = base.snapshot.lasers, obs[:16]
        assert seen.min() >= 0.0 and seen.max() <= 3.0
        inside = (true > 0.6) & (true < 2.4)  # far from both clips
        errors += (seen - true)[inside].tolist()
    assert len(errors) > 30
    assert 0.35 < np.std(errors) < 0.65
    env = make_env(TASK, laser_dropout=1.0)
    obs, _ = env.reset(seed=0)
    assert obs[:16].tolist() == [5.0] * 16  # every ray lost reads the range


def test_odometry_drift_is_a_random_walk_reset_every_episode(make_env):
    env = make_env(TASK, odometry_drift_std=0.05)
    obs, _ = env.reset(seed=1)
    base = env.unwrapped
    assert np.array_equal(obs[16:18], np.float32(base.snapshot.pose[:2]))  # no drift at the reset
    drifts = []
    for _ in range(8):
        obs, *_ = env.step(1)  # turning in place: only the drift moves the observed position
        x, y, _ = base.snapshot.pose
        dx, dy = base.episode_noise.drift
        np.testing.assert_allclose(obs[16:18], [x + dx, y + dy], atol=1e-6)
        drifts.append((dx, dy))
    assert len(set(drifts)) == 8  # it walked every step
    assert base.observed_snapshot.d1 != base.snapshot.d1  # derived from the observed position
    obs, _ = env.reset(seed=2)
    assert base.episode_noise.drift == (0.0, 0.0)


def test_the_procedural_state_is_read_from_the_observed_pose(make_env):
    env = make_env("DynNav-Procedural-v1", odometry_drift_std=0.05, laser_noise_std=0.02)
    env.reset(seed=0)
    for _ in range(4):
        obs, *_ = env.step(1)
    observed, true = env.unwrapped.observed_snapshot, env.unwrapped.snapshot
    assert obs[16] == pytest.approx(observed.d1, abs=1e-5) and obs[16] != pytest.approx(true.d1, abs=1e-5)
    assert np.array_equal(obs[:16], observed.lasers)


def test_action_noise_executes_random_actions(make_env):
    env = make_env(TASK, action_noise=1.0)
    env.reset(seed=0)
    executed = []
    for _ in range(15):
        _, _, terminated, _, _ = env.step(1)
        executed.append(env.unwrapped.episode_noise.executed_action)
        if terminated:
            break
    assert set(executed) == {0, 1, 2}
    env = make_env(TASK, laser_noise_std=0.01)  # action noise off: the asked action runs
    env.reset(seed=0)
    env.step(2)
    assert env.unwrapped.episode_noise.executed_action == 2


def test_speed_scales_are_drawn_per_episode(make_env):
    env = make_env(TASK, robot_speed_scale_min=0.5, robot_speed_scale_max=0.5)
    env.reset(seed=0)
    base = env.unwrapped
    base.place_robot(-0.7, -0.7, math.pi / 4)
    x0, y0, _ = base.snapshot.pose
    env.step(0)
    x1, y1, _ = base.snapshot.pose
    assert math.hypot(x1 - x0, y1 - y0) == pytest.approx(0.15 * 0.5, abs=2e-3)  # half the 0.15 m step

    clean = make_env(TASK)
    clean.reset(seed=3)
    fast = make_env(TASK, obstacle_speed_scale_min=2.0, obstacle_speed_scale_max=2.0)
    fast.reset(seed=3)
    assert fast.unwrapped.obstacle_motions[0].speed == 2.0 * clean.unwrapped.obstacle_motions[0].speed

    ranged = make_env(TASK, robot_speed_scale_min=0.8, robot_speed_scale_max=1.2,
                      obstacle_speed_scale_min=0.5, obstacle_speed_scale_max=1.5)
    factors = set()
    for seed in range(5):
        ranged.reset(seed=seed)
        noise = ranged.unwrapped.episode_noise
        assert 0.8 <= noise.robot_speed_factor <= 1.2 and 0.5 <= noise.obstacle_speed_factor <= 1.5
        factors.add((noise.robot_speed_factor, noise.obstacle_speed_factor))
    assert len(factors) == 5


def test_noise_options_fit_a_training_config(make_env):
    """Flat options of int/float values (a training config's ``task_kwargs``) or one dict."""
    from agents.training.envs import make_env as make_training_env

    env = make_training_env(TASK, task_kwargs={"laser_rays": 32, "laser_noise_std": 0.02, "action_noise": 0.1})
    try:
        assert env.unwrapped.noise_config == NoiseConfig(laser_noise_std=0.02, action_noise=0.1)
        assert env.observation_space.shape == (32 + 8,)
    finally:
        env.close()
    env = make_env(TASK, noise={"laser_dropout": 0.2})
    assert env.unwrapped.noise_config.laser_dropout == 0.2


@pytest.mark.parametrize("option, value", [
    ("laser_noise_std", -0.1), ("laser_noise_std", 5.0), ("laser_noise_std", "loud"), ("laser_dropout", 1.5),
    ("laser_dropout", -0.01), ("odometry_drift_std", float("nan")), ("odometry_drift_std", 3.0),
    ("action_noise", 2), ("action_noise", True), ("robot_speed_scale_min", 0.0), ("robot_speed_scale_max", 0.5),
    ("robot_speed_scale_max", 5.0), ("obstacle_speed_scale_min", -1.0), ("obstacle_speed_scale_max", 0.9),
    ("obstacle_speed_scale_max", None),
])
def test_bad_noise_options_are_errors_naming_the_option(make_env, option, value):
    with pytest.raises(ValueError, match=option):
        make_env(TASK, **{option: value})


def test_a_scaled_robot_step_must_stay_within_the_drive_limits(make_env):
    with pytest.raises(ValueError, match="robot_speed_scale_max"):
        make_env(TASK, forward_step=0.3, robot_speed_scale_max=2.0)  # 0.6 m > the 0.5 m limit
    with pytest.raises(ValueError, match="not both"):
        make_env(TASK, noise={"action_noise": 0.1}, laser_noise_std=0.1)
    with pytest.raises(ValueError, match="laser_noise"):
        make_env(TASK, noise={"laser_noise": 0.1})  # a misspelt option
