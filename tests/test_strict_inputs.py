"""Inputs are checked: actions, step lengths and reward parameters; and no step is long
enough to carry the robot through a wall or past the fastest obstacle unnoticed."""

import math

import numpy as np
import pytest
from mani_skill.utils.registration import register_env

from dynnav_tasks.motion import BackAndForth, Static
from dynnav_tasks.nav_env import NavEnv
from dynnav_tasks.world import Arena, Obstacles, StartArea, World

ROBOT_HALF = (0.225, 0.19)  # the footprint's half length and half width


@pytest.mark.parametrize("action", [1.5, True, np.bool_(False), "0", np.array([0, 1]), np.array([0.0]), None])
def test_actions_that_are_not_integers_are_refused(make_env, action):
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"action must be an integer in \[0, 3\) \(forward, left, right\)"):
        env.step(action)


@pytest.mark.parametrize("action", [0, np.int64(1), np.uint8(2), np.array(0), np.array([1]), np.array([[2]], dtype=np.int32)])
def test_integer_actions_in_any_numpy_form_are_accepted(make_env, action):
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    x0, y0, yaw0 = env.unwrapped.snapshot.pose
    env.step(action)
    x, y, yaw = env.unwrapped.snapshot.pose
    index = int(np.asarray(action).reshape(-1)[0])
    expected = {0: (0.15, 0.0), 1: (0.0, math.pi / 8), 2: (0.0, -math.pi / 8)}[index]
    assert math.hypot(x - x0, y - y0) == pytest.approx(expected[0], abs=1e-3)
    assert math.remainder(yaw - yaw0, 2 * math.pi) == pytest.approx(expected[1], abs=1e-3)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(forward_step=100.0), r"forward_step must be > 0.0 and <= 0.5 m, got 100.0"),
        (dict(forward_step=float("nan")), r"forward_step must be a finite number, got nan"),
        (dict(turn_step=math.pi), r"turn_step must be > 0.0 and <= 1.571 rad"),
        (dict(turn_forward_step=-0.1), r"turn_forward_step must be >= 0 and <= 0.5 m"),
        (dict(reward_params={"distance_gamma": float("nan")}), r"reward parameter 'distance_gamma' must be a finite number"),
    ],
)
def test_unbounded_settings_are_refused(kwargs, message):
    import gymnasium as gym

    with pytest.raises(ValueError, match=message):
        gym.make("DynNav-MovingTarget-v1", **kwargs)


def test_the_longest_forward_step_still_stops_at_the_wall(make_env):
    env = make_env("DynNav-MovingTarget-v1", forward_step=0.5)
    env.reset(seed=0)
    env.unwrapped.place_robot(3.9, 2.0, 0.0)  # nose at 4.125, east wall's inner face at 4.5
    for _ in range(3):
        *_, terminated, truncated, info = env.step(0)
        if terminated:
            break
    assert info["collision"]
    x = env.unwrapped.snapshot.pose[0]
    assert x + ROBOT_HALF[0] < 4.5 + 0.1  # never through the 0.1 m wall


@register_env("DynNavTest-HeadOn-v1", max_episode_steps=200)
class HeadOnEnv(NavEnv):
    """A corridor along x with one box sliding back and forth at the fastest obstacle speed."""

    world = World(
        targets=(Static((-1.5, 1.5)),),
        obstacles=(Obstacles(half_size=(0.25, 0.25), motion=BackAndForth(center=(2.5, 0.0), direction=(1, 0), amplitude=4.0, speed=0.5)),),
        arena=Arena(x_range=(-2.0, 7.0), y_range=(-2.0, 2.0)),
        start=StartArea(x_range=(-1.5, -1.0), y_range=(-1.5, -1.0)),
    )


def _overlap(snap):
    (rx, ry, _), (ox, oy) = snap.pose, snap.moving_obstacle_xy[0]
    return abs(rx - ox) < ROBOT_HALF[0] + 0.25 and abs(ry - oy) < ROBOT_HALF[1] + 0.25


def test_the_fastest_obstacle_head_on_is_never_missed(make_env):
    """Robot driving forward (0.15 m) into a box coming at 0.5 m per step: 0.65 m closer every
    step. Over gaps covering a whole step of phases, the collision is reported in the first
    step after which the two overlap (or earlier, on touching), never later."""
    env = make_env("DynNavTest-HeadOn-v1", reward_mode="sparse")
    base = env.unwrapped
    checked = 0
    for k, gap in enumerate(np.linspace(1.0, 1.65, 14)):
        env.reset(seed=k)
        x0 = base.snapshot.moving_obstacle_xy[0, 0]
        env.step(1)
        x1 = base.snapshot.moving_obstacle_xy[0, 0]
        direction = np.sign(x1 - x0)
        if abs(abs(x1 - x0) - 0.5) > 1e-9 or not -0.5 < x1 < 5.5:
            continue  # bounced at an end: try the next
        rx = x1 + direction * (0.25 + ROBOT_HALF[0] + gap)
        if not -1.7 < rx < 6.7 or not -1.5 < x1 + direction * 4 * 0.5 < 6.5:
            continue
        base.place_robot(rx, 0.0, math.pi if direction > 0 else 0.0)  # facing the box
        for _ in range(6):
            *_, terminated, truncated, info = env.step(0)
            snap = base.snapshot
            if _overlap(snap):
                assert terminated and info["collision"], (gap, snap)
            if terminated:
                break
        assert info["collision"], gap
        checked += 1
    assert checked >= 6
