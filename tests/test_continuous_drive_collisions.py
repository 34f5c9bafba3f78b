"""The continuous drive (``control_mode="diff_drive_vel"``) never tunnels: head-on at top
speed into the thinnest wall and into the fastest box, each drive ends in a collision and the
robot never gets through (``drive.py``'s argument)."""

import math

import numpy as np
import pytest
from mani_skill.utils.registration import register_env

from dynnav_tasks.drive import MAX_LINEAR_SPEED, PIONEER_LINEAR_SPEED, VELOCITY_DRIVE
from dynnav_tasks.motion import Static
from dynnav_tasks.nav_env import NavEnv
from dynnav_tasks.world import Arena, Obstacles, StartArea, World
from test_strict_inputs import HeadOnEnv  # noqa: F401 (registers HEAD_ON)

HEAD_ON = "DynNavTest-HeadOn-v1"
"""a corridor along x with one box sliding back and forth at the fastest obstacle speed"""

ROBOT_HALF = (0.225, 0.19)  # the footprint's half length and half width
DT = 0.2  # s, one control step
V_MAX = PIONEER_LINEAR_SPEED
WALL_X, WALL_HALF = 6.0, 0.05  # the thin wall: 0.1 m thick, the thinnest thing in a world


@register_env("DynNavTest-DriveThinWall-v1", max_episode_steps=200)
class ThinWallEnv(NavEnv):
    """A corridor along x closed by a 0.1 m wall across it at x = 6."""

    world = World(
        targets=(Static((-1.5, 1.5)),),
        obstacles=(Obstacles(half_size=(WALL_HALF, 1.95), motion=Static((WALL_X, 0.0))),),
        arena=Arena(x_range=(-2.0, 12.0), y_range=(-2.0, 2.0)),
        start=StartArea(x_range=(-1.5, -1.5), y_range=(0.0, 0.0)),
    )


def _overlaps_wall(pose) -> bool:
    return pose[0] + ROBOT_HALF[0] > WALL_X - WALL_HALF  # heading +x, the wall across the corridor


@pytest.mark.parametrize("top_speed, accel", [(V_MAX, None), (MAX_LINEAR_SPEED, 1000.0)])
def test_top_speed_into_the_thinnest_wall_is_a_collision_never_past_it(make_env, top_speed, accel):
    """Head-on into a 0.1 m wall at the default top speed (ramping up from 7 m away) and at
    the fastest limit allowed (2.5 m/s from the first step), from starts a whole step apart:
    the step after which the robot overlaps the wall (or an earlier one) is a collision, and
    the robot never gets through."""
    options = dict(max_linear_speed=top_speed) | ({} if accel is None else dict(max_linear_accel=accel))
    env = make_env("DynNavTest-DriveThinWall-v1", control_mode=VELOCITY_DRIVE, **options)
    base = env.unwrapped
    for offset in np.linspace(0.0, top_speed * DT, 7):
        env.reset(seed=0)
        base.place_robot(-1.5 + offset, 0.0, 0.0)
        for _ in range(60):
            *_, terminated, truncated, info = env.step(np.float32([top_speed, 0.0]))
            pose = base.snapshot.pose
            assert pose[0] - ROBOT_HALF[0] < WALL_X + WALL_HALF  # never through
            assert pose[0] < WALL_X
            if _overlaps_wall(pose):
                assert terminated and info["collision"], (offset, pose)
            if terminated:
                break
        assert info["collision"], offset
        assert base.agent.controller.command[0] == pytest.approx(top_speed, rel=1e-6)  # hit at top speed


def _overlap(snap) -> bool:
    (rx, ry, _), (ox, oy) = snap.pose, snap.moving_obstacle_xy[0]
    return abs(rx - ox) < ROBOT_HALF[0] + 0.25 and abs(ry - oy) < ROBOT_HALF[1] + 0.25


@pytest.mark.parametrize("top_speed", [V_MAX, MAX_LINEAR_SPEED])
def test_top_speed_into_the_fastest_box_head_on_is_never_missed(make_env, top_speed):
    """The robot at top speed (reached in the first step) against a box coming at 0.5 m per
    step, over gaps covering a whole step of their closing: the collision comes in the first
    step after which the two overlap (or earlier), and the robot never passes the box."""
    env = make_env(HEAD_ON, control_mode=VELOCITY_DRIVE, reward_mode="sparse",
                   max_linear_speed=top_speed, max_linear_accel=1000.0)
    base = env.unwrapped
    closing = top_speed * DT + 0.5
    checked = 0
    for k, gap in enumerate(np.linspace(1.0, 1.0 + closing, 12)):
        env.reset(seed=k)
        x0 = base.snapshot.moving_obstacle_xy[0, 0]
        env.step(np.zeros(2, dtype=np.float32))
        x1 = base.snapshot.moving_obstacle_xy[0, 0]
        direction = np.sign(x1 - x0)
        if abs(abs(x1 - x0) - 0.5) > 1e-9 or not -0.5 < x1 < 5.5:
            continue  # bounced at an end: try the next
        rx = x1 + direction * (0.25 + ROBOT_HALF[0] + gap)
        if not -1.7 < rx < 6.7 or not -1.5 < x1 + direction * 4 * 0.5 < 6.5:
            continue
        base.place_robot(rx, 0.0, math.pi if direction > 0 else 0.0)  # facing the box
        side = np.sign(rx - x1)
        for _ in range(6):
            *_, terminated, truncated, info = env.step(np.float32([top_speed, 0.0]))
            snap = base.snapshot
            assert np.sign(snap.pose[0] - snap.moving_obstacle_xy[0, 0]) == side, (gap, snap.pose)
            if _overlap(snap):
                assert terminated and info["collision"], (gap, snap)
            if terminated:
                break
        assert info["collision"], gap
        checked += 1
    assert checked >= 5
