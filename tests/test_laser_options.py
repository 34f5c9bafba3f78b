"""The laser options (``laser_rays``, ``laser_fov_deg``, ``laser_range``): readings against
distances worked out by hand, the state vector's size, and clear errors for bad values."""

import math

import numpy as np
import pytest

from dynnav_tasks.lasers import LaserConfig
from test_lasers import _ray_box  # entry distance of a ray into a box, by hand

R2 = math.sqrt(2)
FAN = dict(laser_rays=7, laser_fov_deg=270, laser_range=8.0)
"""rays every 45 degrees from -135 (right, behind) to +135 (left, behind)"""


def test_a_fan_of_rays_reads_the_hand_computed_distances(make_env):
    """World 5.2: walls' inner faces at x = -2, 4.5 and y = -2, 4.5; 0.5 m boxes centred at
    (-0.8, 1.2), (1.1, 1.1), (1.2, -0.8). The robot at (-1, -1.6) facing east (+x)."""
    env = make_env("DynNav-MovingTarget-v1", **FAN)
    env.reset(seed=0)
    base = env.unwrapped
    np.testing.assert_allclose(base.laser_angles, np.radians([-135, -90, -45, 0, 45, 90, 135]), atol=1e-12)
    assert base.laser_range == 8.0
    expected = [
        0.4 * R2,  # -135 deg: the south wall (y = -2), 0.4 m below, at 45 deg
        0.4,  # -90 deg: the south wall
        0.4 * R2,  # -45 deg: the south wall
        5.5,  # ahead: the east wall 5.5 m away (beyond the study's 5 m)
        5.5 * R2,  # 45 deg: the east wall at y = 3.9, 7.78 m away (within 8 m)
        2.55,  # 90 deg: the bottom (y = 0.95) of the box at (-0.8, 1.2)
        1.0 * R2,  # 135 deg: the west wall (x = -2) at y = -0.6
    ]
    obs = base.place_robot(-1.0, -1.6, 0.0)
    np.testing.assert_allclose(obs[:7], expected, atol=1e-3)

    # facing north, the fan turns with the robot: now from -45 to 225 deg in the world
    obs = base.place_robot(-1.0, -1.6, math.pi / 2)
    np.testing.assert_allclose(obs[:7], [0.4 * R2, 5.5, 5.5 * R2, 2.55, R2, 1.0, 0.4 * R2], atol=1e-3)


def test_a_shorter_range_caps_the_same_rays(make_env):
    env = make_env("DynNav-MovingTarget-v1", laser_rays=7, laser_fov_deg=270, laser_range=2.0)
    env.reset(seed=0)
    obs = env.unwrapped.place_robot(-1.0, -1.6, 0.0)
    np.testing.assert_allclose(obs[:7], [0.4 * R2, 0.4, 0.4 * R2, 2.0, 2.0, 2.0, R2], atol=1e-3)
    assert env.observation_space.high[:7].tolist() == [2.0] * 7


def test_360_rays_match_the_geometry(make_env):
    """A full ring of 360 rays, one per degree, ray 0 ahead, counter-clockwise, 8 m range,
    against an independent ray-rectangle intersection of world 5.3's walls and boxes."""
    env = make_env("DynNav-MovingObstacles-v1", laser_rays=360, laser_range=8.0)
    env.reset(seed=3)
    base = env.unwrapped
    x, y, yaw = -0.5, 1.0, 0.3
    got = base.place_robot(x, y, yaw)[:360]
    snap = base.snapshot
    boxes = list(base.world.arena.walls().values()) + list(zip(snap.obstacle_xy, snap.obstacle_half))
    for k in range(360):
        a = yaw + math.radians(k)
        d = (math.cos(a), math.sin(a))
        expected = min(min(_ray_box((x, y), d, c, h) for c, h in boxes), 8.0)
        assert got[k] == pytest.approx(expected, abs=2e-3), k
    assert got.max() > 5.0  # the longer range is in use


@pytest.mark.parametrize("task_id, fixed", [("DynNav-MovingObstacles-v1", 8), ("DynNav-Procedural-v1", 3 + 5 * 4)])
@pytest.mark.parametrize("rays", [16, 90, 360])
def test_the_state_follows_the_ray_count(make_env, task_id, fixed, rays):
    """The observation space, ``state_layout()`` and the state itself have one reading per
    ray (the study's state in 5.3; the egocentric state in the procedural task)."""
    env = make_env(task_id, laser_rays=rays, laser_fov_deg=180, laser_range=6.0)
    obs, _ = env.reset(seed=1)
    layout = env.unwrapped.state_layout()
    assert layout[0] == ("lasers", rays)
    assert sum(n for _, n in layout) == rays + fixed
    assert obs.shape == env.observation_space.shape == (rays + fixed,)
    assert env.observation_space.high[:rays].tolist() == [6.0] * rays
    obs, *_ = env.step(1)
    assert env.observation_space.contains(obs)
    assert len(env.unwrapped.laser_angles) == rays


def test_the_default_ring_is_the_studys():
    config = LaserConfig.of()
    assert config == LaserConfig(rays=16, fov_deg=360.0, max_range=5.0)
    assert np.array_equal(config.angles(), 2 * math.pi * np.arange(16) / 16)
    assert LaserConfig.of(1, 90, 5).angles().tolist() == [0.0]  # a single ray looks ahead


@pytest.mark.parametrize("option, value", [
    ("laser_rays", 0), ("laser_rays", -4), ("laser_rays", 100_000), ("laser_rays", 16.0), ("laser_rays", "16"),
    ("laser_rays", True), ("laser_fov_deg", 0), ("laser_fov_deg", -90), ("laser_fov_deg", 361),
    ("laser_fov_deg", float("nan")), ("laser_fov_deg", "wide"), ("laser_range", 0), ("laser_range", -1.0),
    ("laser_range", float("inf")), ("laser_range", 1e6), ("laser_range", "far"), ("laser_range", None),
])
def test_bad_laser_options_are_errors_naming_the_option(make_env, option, value):
    with pytest.raises(ValueError, match=option):
        make_env("DynNav-OneObstacle-v1", **{option: value})


def test_the_state_planner_reads_a_state_of_any_ray_count():
    """The full-state planner finds the robot, the target and the obstacles after the lasers,
    however many there are: the same episode with 16 or 90 rays."""
    from dynnav_tasks.baselines.state_planner import run_planner

    default = run_planner("DynNav-MotionAreas-v1", [2]).episodes[0]
    wide = run_planner("DynNav-MotionAreas-v1", [2], task_kwargs={"laser_rays": 90}).episodes[0]
    assert (wide.outcome, wide.steps) == (default.outcome, default.steps) == ("success", 39)
