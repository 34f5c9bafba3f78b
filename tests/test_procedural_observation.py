"""The egocentric state of DynNav-Procedural-v1 (target and nearest obstacles in the robot's
frame, padded to a fixed size), its space under gymnasium's checker, and the camera in a
generated world."""

import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import dynnav_tasks
from dynnav_tasks import egocentric
from dynnav_tasks.motion import BackAndForth, RandomInRect, Static
from dynnav_tasks.snapshot import take_snapshot
from dynnav_tasks.world import Arena, Obstacles, StartArea, World

TASK = "DynNav-Procedural-v1"
TURN_LEFT = 1


def world_with(moving, target=(5.0, 6.0), marker=False) -> World:
    return World(
        targets=(Static(target),),
        obstacles=tuple(Obstacles(half_size=(0.25, 0.25), motion=m) for m in moving),
        arena=Arena(x_range=(0.0, 9.0), y_range=(0.0, 9.0)),
        start=StartArea(x_range=(0.9, 1.1), y_range=(0.9, 1.1)),
        target_marker=marker,
    )


def standing(x, y) -> RandomInRect:
    """A moving box that starts at (x, y) (and barely moves)."""
    return RandomInRect(x_range=(x - 0.01, x + 0.01), y_range=(y - 0.01, y + 0.01), speed_range=(0.001, 0.002),
                        start=(x, y))


@pytest.fixture(scope="module")
def env():
    e = dynnav_tasks.NumpyWrapper(gym.make(TASK, difficulty="medium", obstacle_k=4))
    yield e
    e.close()


def test_the_state_has_one_size_and_layout_in_every_world(env):
    u = env.unwrapped
    assert u.state_layout() == [("lasers", 16), ("target", 3)] + [(f"obstacle{i}", 5) for i in range(4)]
    assert env.observation_space.shape == (39,)
    for seed in range(8):
        obs, _ = env.reset(seed=seed)
        assert obs.shape == (39,) and obs.dtype == np.float32 and env.observation_space.contains(obs)
    k0 = dynnav_tasks.NumpyWrapper(gym.make(TASK, obstacle_k=0))
    try:
        obs, _ = k0.reset(seed=0)
        assert obs.shape == (19,) and k0.observation_space.shape == (19,)
    finally:
        k0.close()


def test_target_distance_and_bearing_in_the_robots_frame(env):
    env.reset(seed=0, options={"world": world_with((), target=(5.0, 6.0))})
    state = env.unwrapped.place_robot(2.0, 2.0, math.pi / 2)  # facing +y; the target 3 m east, 4 m north
    distance, sin_b, cos_b = state[16:19]
    assert distance == pytest.approx(5.0)
    assert (sin_b, cos_b) == (pytest.approx(-0.6), pytest.approx(0.8))  # ahead and to the right
    state = env.unwrapped.place_robot(5.0, 3.0, math.pi)  # facing -x; the target 3 m to its right
    assert state[16:19] == pytest.approx([3.0, -1.0, 0.0], abs=1e-6)
    np.testing.assert_array_equal(state[19:], np.tile(egocentric.PADDING, 4))  # no moving obstacle


def test_the_nearest_obstacles_come_sorted_in_the_robots_frame_and_padded(env):
    moving = (standing(4.0, 2.0), standing(2.0, 3.0), standing(2.0, 0.5))  # 2 m, 1 m and 1.5 m away
    env.reset(seed=0, options={"world": world_with(moving)})
    state = env.unwrapped.place_robot(2.0, 2.0, math.pi / 2)  # facing +y: ahead is +y, left is -x
    slots = state[19:].reshape(4, 5)
    np.testing.assert_allclose(slots[:3], [[1.0, 0.0, 0, 0, 1], [-1.5, 0.0, 0, 0, 1], [0.0, -2.0, 0, 0, 1]], atol=1e-6)
    np.testing.assert_array_equal(slots[3], egocentric.PADDING)
    assert egocentric.PADDING[0] == egocentric.FAR and egocentric.PADDING[4] == 0.0


def test_only_the_k_nearest_obstacles_enter_with_their_relative_velocities():
    def snap(robot, moving):
        return take_snapshot(step=0, pose=robot, lasers=np.full(16, 5.0), target_xy=(9.0, 0.0), static_xy=(),
                             moving_xy=moving, obstacle_half=[(0.25, 0.25)] * len(moving), contact=False)

    moving = [(5.0, 0.0), (0.0, 1.0), (3.0, 3.0), (-2.0, 0.0), (0.5, 0.0)]  # 5, 1, 4.24, 2 and 0.5 m away
    before = snap((0.0, 0.0, 0.0), moving)
    after = snap((0.1, 0.0, 0.0), [(x, y + 0.2) for x, y in moving])  # the robot 0.1 m ahead, all boxes 0.2 m north
    state = egocentric.egocentric_state(after, before, 2)
    assert state.shape == (16 + 3 + 10,)
    # nearest: (0.5, 0.2) then (0, 1.2), relative to the robot at (0.1, 0); velocity (0.2 north - 0.1 ahead)
    np.testing.assert_allclose(state[19:].reshape(2, 5), [[0.4, 0.2, -0.1, 0.2, 1], [-0.1, 1.2, -0.1, 0.2, 1]], atol=1e-6)
    np.testing.assert_allclose(egocentric.egocentric_state(after, None, 2)[21:23], [0.0, 0.0])  # no step: no velocity


def test_obstacle_velocity_is_relative_and_in_the_robots_frame(env):
    sweeping = BackAndForth(center=(5.0, 5.0), direction=(1.0, 0.0), amplitude=2.0, speed=0.1)  # along world x
    env.reset(seed=2, options={"world": world_with((sweeping,))})
    env.unwrapped.place_robot(2.0, 2.0, math.pi / 2)
    before = env.unwrapped.snapshot
    state, *_ = env.step(TURN_LEFT)  # turning in place
    after = env.unwrapped.snapshot
    moved = after.moving_obstacle_xy[0, 0] - before.moving_obstacle_xy[0, 0]  # +-0.1 m (or less at an end)
    robot = np.subtract(after.pose[:2], before.pose[:2])
    yaw = after.pose[2]
    vx, vy = moved - robot[0], -robot[1]
    expected = (math.cos(yaw) * vx + math.sin(yaw) * vy, -math.sin(yaw) * vx + math.cos(yaw) * vy)
    assert abs(moved) > 0.05 and abs(robot).max() < 0.02
    assert state[21:23] == pytest.approx(expected, abs=1e-5)
    # the robot faces about +y (a bit more to the left): the world's +x is its right, -y
    assert abs(state[22]) == pytest.approx(abs(moved), abs=0.02) and np.sign(state[22]) == -np.sign(moved)


def test_check_env_passes():
    env = dynnav_tasks.NumpyWrapper(gym.make(TASK, difficulty="hard", split="ood"))
    try:
        check_env(env, skip_render_check=True)
    finally:
        env.close()


def test_the_camera_sees_the_target_marker_and_the_top_down_view_follows_the_world():
    env = dynnav_tasks.NumpyWrapper(gym.make(TASK, obs_mode="rgb+state", obstacle_k=2))
    try:
        obs, _ = env.reset(seed=4)
        assert env.unwrapped.world.target_marker  # the camera variant of the spec
        assert obs["state"].shape == (29,) and obs["rgb"].dtype == np.uint8
        world = world_with((), target=(6.0, 2.0), marker=True)
        env.reset(seed=0, options={"world": world})
        obs = env.unwrapped.place_robot(3.0, 2.0, 0.0)  # the marker 3 m straight ahead
        frame = env.unwrapped.camera_image()
        red = (frame[..., 0] > 150) & (frame[..., 1] < 80) & (frame[..., 2] < 80)
        assert red[:, frame.shape[1] // 2 - 2:frame.shape[1] // 2 + 2].any()
        env.unwrapped.place_robot(3.0, 2.0, math.pi)  # facing away: no red
        frame = env.unwrapped.camera_image()
        assert not ((frame[..., 0] > 150) & (frame[..., 1] < 80) & (frame[..., 2] < 80)).any()
        top = env.unwrapped.render_top_down()
        col, row = (int(round(v)) for v in env.unwrapped.top_down_pixel(6.0, 2.0))
        r, g, b = top[row, col].astype(int)
        assert r > 150 and g < 80 and b < 80  # the target's disc where the mapping puts it
        col, row = (int(round(v)) for v in env.unwrapped.top_down_pixel(4.5, 4.5))
        assert top[row, col].min() > 180  # the floor at the arena's centre
    finally:
        env.close()
