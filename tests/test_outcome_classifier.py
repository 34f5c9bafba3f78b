"""``dynnav_tasks.outcome_of`` names how an episode ended from what ``evaluate()`` reported, in
every form a step's info comes in; the speed each moving obstacle drew is public."""

import dataclasses
import math

import gymnasium as gym
import numpy as np
import pytest
import torch

import dynnav_tasks
from dynnav_tasks import outcome_of
from dynnav_tasks.motion import Route


def _drive(env, actions):
    """Step ``actions`` until the episode ends; the last (info, terminated, truncated)."""
    for action in actions:
        _, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            return info, terminated, truncated
    raise AssertionError("the episode did not end")


def test_each_way_a_task_ends_is_named(make_env):
    env = make_env("DynNav-MovingObstacles-v1")
    obs, _ = env.reset(seed=4)
    tx, ty = obs[18:20]
    env.unwrapped.place_robot(tx, ty + 0.5, -math.pi / 2)  # 0.5 m north of the target, facing it
    info, terminated, _ = _drive(env, [0, 0])
    assert outcome_of(info, terminated) == "success" and info["success"]

    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    env.unwrapped.place_robot(4.0, 2.0, 0.0)  # facing the east wall, 27.5 cm away
    info, terminated, _ = _drive(env, [0, 0])
    assert outcome_of(info, terminated) == "collision" and info["collision"]

    env = make_env("DynNav-OneObstacle-v1")
    env.reset(seed=5)
    info, terminated, truncated = _drive(env, [1] * 200)  # turning in place until the step limit
    assert truncated and not terminated
    assert outcome_of(info, terminated) == "timeout" and info["timeout"]


def test_maniskills_batched_info_is_read_too():
    env = gym.make("DynNav-MovingTarget-v1")
    try:
        env.reset(seed=0)
        env.unwrapped.place_robot(4.0, 2.0, 0.0)
        info, terminated, _ = _drive(env, [torch.tensor([0])] * 2)
        assert isinstance(info["collision"], torch.Tensor) and isinstance(terminated, torch.Tensor)
        assert outcome_of(info, terminated) == "collision"
        assert outcome_of(env.unwrapped.evaluate()) == "collision"
    finally:
        env.close()


def test_other_environments_end_as_terminated_or_timeout():
    env = gym.make("CartPole-v1")
    env.reset(seed=0)
    info, terminated, truncated = _drive(env, [0] * 500)  # pushing one way topples the pole
    env.close()
    assert terminated and outcome_of(info, terminated) == "terminated"
    assert outcome_of({}, terminated=False) == "timeout"
    assert outcome_of({"success": np.bool_(True), "collision": np.array([True])}) == "success"


def test_a_vector_environments_info_is_refused():
    with pytest.raises(ValueError, match="one environment's info"):
        outcome_of({"success": np.array([False, True])})


def test_the_speed_each_moving_obstacle_drew_is_public(make_env):
    env = make_env("DynNav-MovingObstacles-v1")
    speeds = set()
    for seed in range(4):
        obs, _ = env.reset(seed=seed)
        (motion,) = env.unwrapped.obstacle_motions
        assert isinstance(motion.motion, Route) and motion.count == 2
        assert 0.05 <= motion.speed <= 0.5
        speeds.add(motion.speed)
        before = obs[20:22]
        obs, *_ = env.step(1)  # turn in place: the obstacles move on
        travelled = (motion.motion.nearest_arc_length(obs[20:22]) - motion.motion.nearest_arc_length(before))
        assert travelled % motion.motion.length() == pytest.approx(motion.speed, abs=1e-5)
        with pytest.raises(dataclasses.FrozenInstanceError):
            motion.speed = 0.0
    assert len(speeds) == 4  # drawn anew each episode
    wander = make_env("DynNav-MotionAreas-v1")
    wander.reset(seed=0)
    assert all(m.speed is None for m in wander.unwrapped.obstacle_motions)  # a new step length every step
