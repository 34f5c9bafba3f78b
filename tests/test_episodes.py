"""Episodes end as a user relies on: collisions, reaching the target, and exact replays."""

import math

import numpy as np
import pytest


def test_driving_into_a_wall_ends_with_collision(make_env):
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    env.unwrapped.place_robot(4.0, 2.0, 0.0)  # nose at x=4.225, east wall at 4.5
    obs, reward, terminated, truncated, info = env.step(0)  # nose at 4.375: 12.5 cm to go
    assert not terminated and not info["collision"]
    obs, reward, terminated, truncated, info = env.step(0)  # would reach 4.525
    assert terminated and not truncated
    assert info["collision"] and info["fail"] and not info["success"]
    assert reward == -20.0


def test_a_moving_obstacle_running_into_the_robot_is_a_collision(make_env):
    """The robot turns in place on the obstacles' loop until one of them arrives."""
    env = make_env("DynNav-MovingObstacles-v1", reward_mode="sparse")
    for seed in range(20):
        obs, _ = env.reset(seed=seed)
        obstacles = obs[20:24].reshape(2, 2)
        if np.linalg.norm(obstacles - [2.0, 1.3], axis=1).min() > 1.0:
            break
    env.unwrapped.place_robot(2.0, 1.3, 0.0)  # on the loop's east side
    for step in range(200):
        obs, reward, terminated, truncated, info = env.step(1)
        if terminated or truncated:
            break
    assert step > 0, "the obstacle must come to the robot, not start on it"
    assert terminated and info["collision"] and not info["success"]
    assert reward == -1.0  # sparse mode's collision reward
    obstacles = obs[20:24].reshape(2, 2)
    assert np.abs(obstacles - [2.0, 1.3]).max(axis=1).min() < 0.25 + 0.225 + 0.5  # one obstacle is at the robot


def test_reaching_the_target_ends_with_success(make_env):
    env = make_env("DynNav-MovingObstacles-v1")
    obs, _ = env.reset(seed=4)
    tx, ty = obs[18:20]
    env.unwrapped.place_robot(tx, ty + 0.5, -math.pi / 2)  # 0.5 m north of the target, facing it
    obs, reward, terminated, truncated, info = env.step(0)  # 0.35 m: not yet within 0.3
    assert not terminated and info["distance_to_target"] == pytest.approx(0.35, abs=1e-3)
    obs, reward, terminated, truncated, info = env.step(0)  # 0.20 m
    assert terminated and info["success"] and not info["collision"]
    assert reward == 20.0
    assert info["path_length"] == pytest.approx(0.30, abs=1e-3)


def test_reward_mode_reaches_the_step_reward(make_env):
    env = make_env("DynNav-MovingTarget-v1", reward_mode="distance")
    env.reset(seed=2)
    env.unwrapped.place_robot(-1.0, -1.0, 0.0)  # > 0.8 m from every obstacle: no obstacle term
    _, reward, _, _, info = env.step(0)
    assert reward == pytest.approx(1 - math.exp(0.2 * float(info["distance_to_target"])), abs=1e-5)


def _rollout(env, seed, actions):
    obs, info = env.reset(seed=seed)
    trace = [obs.copy()]
    for a in actions:
        obs, reward, terminated, truncated, info = env.step(int(a))
        trace += [obs.copy(), np.float64(reward), bool(terminated), bool(truncated), float(info["path_length"])]
        if terminated or truncated:
            break
    return trace


def _same(a, b):
    return len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b))


@pytest.mark.parametrize("task", ["DynNav-MovingTarget-v1", "DynNav-MovingObstacles-v1"])
def test_same_seed_replays_bit_for_bit(make_env, task):
    actions = np.random.default_rng(0).integers(0, 3, size=200)
    first, second = make_env(task), make_env(task)
    for seed in (11, 12):
        a = _rollout(first, seed, actions)
        first.reset(seed=99)  # something else in between
        _rollout(first, 99, actions[::-1])
        b = _rollout(first, seed, actions)  # same env, again
        c = _rollout(second, seed, actions)  # a fresh env
        assert len(a) > 4
        assert _same(a, b) and _same(a, c)
    assert not _same(_rollout(first, 11, actions), _rollout(first, 12, actions))
