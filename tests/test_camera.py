"""The front camera: what it sees, the observation modes, frame stacking, the 640 px option.

Camera tests share one pytest process: on lavapipe the first frame in a process is slow."""

import math

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from dynnav_tasks.wrappers import GrayFrameStack, to_gray


def red_pixels(img):
    r, g, b = (img[..., k].astype(int) for k in range(3))
    return (r > 150) & (g < 90) & (b < 90)


@pytest.fixture
def camera_env(make_env):
    def _make(task_id="DynNav-VisualStaticTarget-v1", **kw):
        kw.setdefault("obs_mode", "rgb")
        return make_env(task_id, **kw)

    return _make


def test_rgb_observations(camera_env):
    env = camera_env()
    obs, _ = env.reset(seed=0)
    assert obs.shape == (32, 32, 3) and obs.dtype == np.uint8
    assert env.observation_space.contains(obs)
    obs, *_ = env.step(0)
    assert obs.shape == (32, 32, 3)


@pytest.mark.parametrize("obs_mode", ["rgb", "rgb+state"])
def test_check_env_with_camera(camera_env, obs_mode):
    check_env(camera_env(obs_mode=obs_mode), skip_render_check=True, skip_close_check=True)


def test_image_and_state_together(camera_env):
    env = camera_env("DynNav-VisualTargets-v1", obs_mode="rgb+state")
    obs, _ = env.reset(seed=0)
    assert set(obs) == {"rgb", "state"}
    assert obs["rgb"].shape == (32, 32, 3) and obs["state"].shape == (26,)
    np.testing.assert_array_equal(obs["state"], env.unwrapped.state_vector())


def test_the_red_target_is_seen_from_1m_when_faced(camera_env):
    env = camera_env()
    env.reset(seed=0)
    base = env.unwrapped
    base.place_robot(3.0, 2.0, math.pi / 2)  # 1 m south of the target (3, 3), facing it
    facing = base.camera_image()
    red = red_pixels(facing)
    assert red.sum() >= 20
    cols = np.nonzero(red)[1]
    assert abs(cols.mean() - 15.5) < 2  # straight ahead: in the middle of the image
    base.place_robot(3.0, 2.0, -math.pi / 2)  # facing away
    assert red_pixels(base.camera_image()).sum() == 0


def test_the_image_changes_when_the_robot_turns(camera_env):
    env = camera_env()
    obs, _ = env.reset(seed=0)
    base = env.unwrapped
    base.place_robot(0.0, -1.5, 0.0)
    before = base.camera_image()
    obs, *_ = env.step(1)  # turn left 22.5 deg
    assert np.abs(obs.astype(int) - before.astype(int)).mean() > 5
    # and the picture is the camera's view of the new pose
    np.testing.assert_array_equal(obs, base.camera_image())


def test_only_the_chosen_target_is_rendered(camera_env):
    env = camera_env("DynNav-VisualTargets-v1")
    targets = [t.at for t in env.unwrapped.world.targets]
    seen = set()
    for seed in range(12):
        env.reset(seed=seed)
        base = env.unwrapped
        chosen = tuple(float(v) for v in base.state_vector()[18:20])
        for tx, ty in targets:
            base.place_robot(tx, ty - 1.0, math.pi / 2)  # 1 m south of this target, facing it
            # a marked target 1 m away fills 400 pixels; the chosen one farther off, 70 at most
            visible = red_pixels(base.camera_image()).sum() >= 200
            assert visible == np.allclose((tx, ty), chosen), (seed, (tx, ty), chosen)
        seen.add(chosen)
    assert len(seen) == 3  # every target was the chosen one at least once


def test_gray_frame_stack_order_and_reset(camera_env):
    env = GrayFrameStack(camera_env(), num_frames=4)
    assert env.observation_space.shape == (32, 32, 4)
    obs, _ = env.reset(seed=0)
    base = env.unwrapped
    first = to_gray(base.camera_image())
    for k in range(4):  # reset fills the stack with copies of the first frame
        np.testing.assert_array_equal(obs[..., k], first)
    frames = [first]
    for _ in range(5):
        obs, *_ = env.step(1)  # turning changes every frame
        frames.append(to_gray(base.camera_image()))
        expected = ([first] * 4 + frames[1:])[-4:]
        for k in range(4):  # oldest (channel 0) to newest (channel 3)
            np.testing.assert_array_equal(obs[..., k], expected[k])
    assert not np.array_equal(obs[..., 0], obs[..., 3])


def test_gray_frame_stack_keeps_the_state(camera_env):
    env = GrayFrameStack(camera_env(obs_mode="rgb+state"), num_frames=2)
    obs, _ = env.reset(seed=0)
    assert obs["gray"].shape == (32, 32, 2) and obs["state"].shape == (24,)
    assert env.observation_space.contains(obs)


def test_gray_frame_stack_needs_images(make_env):
    with pytest.raises(ValueError, match="obs_mode='rgb'"):
        GrayFrameStack(make_env("DynNav-VisualStaticTarget-v1"))


def test_render_640_and_shrink_like_the_thesis(camera_env):
    small = camera_env()
    large = camera_env(camera_render_size=640)
    images = []
    for env in (small, large):
        env.reset(seed=0)
        env.unwrapped.place_robot(3.0, 2.0, math.pi / 2)
        images.append(env.unwrapped.camera_image())
    assert images[1].shape == (32, 32, 3)
    assert red_pixels(images[1]).sum() >= 20
    # the same view: averaging 20x20 blocks differs from sampling only at edges
    assert np.abs(images[0].astype(int) - images[1].astype(int)).mean() < 12


def test_bad_camera_sizes_are_named(make_env):
    with pytest.raises(ValueError, match="camera_render_size \\(100\\) must be a multiple of camera_size \\(32\\)"):
        make_env("DynNav-VisualStaticTarget-v1", obs_mode="rgb", camera_render_size=100)


@pytest.mark.parametrize("kwargs, message", [
    (dict(camera_size=0), "camera_size must be an integer from 8 to 512"),
    (dict(camera_size=100000), "camera_size must be an integer from 8 to 512"),
    (dict(camera_size=32.0), "camera_size must be an integer"),
    (dict(camera_render_size=64000), "camera_render_size must be an integer from camera_size \\(32\\) to 2048"),
])
def test_camera_sizes_are_bounded(make_env, kwargs, message):
    with pytest.raises(ValueError, match=message):
        make_env("DynNav-VisualStaticTarget-v1", obs_mode="rgb", **kwargs)
