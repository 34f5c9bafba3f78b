"""The continuous drive (``control_mode="diff_drive_vel"``, ``drive.py``): its kinematics by
hand, its limits, clipping and refusals, seed replay, the noise options and gymnasium's checker
(no tunnelling at top speed: ``test_continuous_drive_collisions.py``)."""

import math
import warnings

import gymnasium as gym
import numpy as np
import pytest
import torch
from gymnasium.utils.env_checker import check_env
from mani_skill.utils.registration import register_env

import dynnav_tasks
from dynnav_tasks.drive import (
    CONTROL_MODES,
    MAX_LINEAR_SPEED,
    PIONEER_ANGULAR_SPEED,
    PIONEER_LINEAR_SPEED,
    VELOCITY_DRIVE,
    VelocityDriveConfig,
)
from dynnav_tasks.motion import Static
from dynnav_tasks.nav_env import NavEnv
from dynnav_tasks.world import Arena, StartArea, World

DT = 0.2  # s, one control step
SUB_STEPS = 4
V_MAX, W_MAX = PIONEER_LINEAR_SPEED, PIONEER_ANGULAR_SPEED
DV, DW = 1.0 * DT, math.radians(250.0) * DT  # the default accelerations over one step
BOX_V, BOX_W = float(np.float32(V_MAX)), float(np.float32(W_MAX))  # the float32 box's bounds


@register_env("DynNavTest-DriveOpen-v1", max_episode_steps=200)
class OpenFloorEnv(NavEnv):
    """A 20 m x 20 m empty arena, the target far in a corner: room to drive and turn."""

    world = World(targets=(Static((9.0, 9.0)),), arena=Arena((-10.0, 10.0), (-10.0, 10.0)),
                  start=StartArea((0.0, 0.0), (0.0, 0.0)))


def ramp(target: float, step: float, n: int, start: float = 0.0) -> list[float]:
    """The commands of ``n`` steps asking for ``target`` from ``start``, ``step`` at most each."""
    out, value = [], start
    for _ in range(n):
        value = min(max(target, value - step), value + step)
        out.append(value)
    return out


def drive(env, actions):
    """Step ``actions`` from the robot placed at the origin facing +x; the poses after each."""
    env.reset(seed=0)
    env.unwrapped.place_robot(0.0, 0.0, 0.0)
    poses = []
    for action in actions:
        env.step(np.asarray(action, dtype=np.float32))
        poses.append(env.unwrapped.snapshot.pose)
    return poses


def test_the_default_is_the_discrete_drive_and_the_modes_are_listed(make_env):
    env = make_env("DynNav-MovingTarget-v1")
    assert env.unwrapped.control_mode == "discrete_drive" and env.action_space == gym.spaces.Discrete(3)
    env = make_env("DynNav-MovingTarget-v1", control_mode=VELOCITY_DRIVE)
    assert env.unwrapped.control_mode == VELOCITY_DRIVE
    space = env.action_space
    assert isinstance(space, gym.spaces.Box) and space.shape == (2,) and space.dtype == np.float32
    np.testing.assert_array_equal(space.high, np.float32([V_MAX, W_MAX]))
    np.testing.assert_array_equal(space.low, -space.high)
    assert CONTROL_MODES == ("discrete_drive", "diff_drive_vel")


@pytest.mark.parametrize("mode", ["diff_drive", "pd_joint_vel", ""])
def test_a_bad_control_mode_is_an_error_listing_the_modes(mode):
    with pytest.raises(ValueError, match=r"Unknown control_mode .*Valid control_modes: discrete_drive, diff_drive_vel"):
        gym.make("DynNav-MovingTarget-v1", control_mode=mode or "?")


def test_straight_at_top_speed_drives_the_hand_computed_distance(make_env):
    """1.0 m/s^2 over 0.2 s steps: 0.2, 0.4, ... 1.2 m/s (6 steps), then 1.2 m/s; a step
    drives its command x 0.2 s."""
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE)
    k = 10
    poses = drive(env, [(V_MAX, 0.0)] * k)
    expected = np.cumsum(np.array(ramp(BOX_V, DV, k)) * DT)
    assert expected[5] == pytest.approx(0.84) and expected[-1] == pytest.approx(0.84 + 4 * 0.24)
    np.testing.assert_allclose([p[0] for p in poses], expected, atol=1e-3)
    np.testing.assert_allclose([(p[1], p[2]) for p in poses], 0.0, atol=1e-6)
    assert env.unwrapped.snapshot.path_length == pytest.approx(expected[-1], abs=1e-3)
    assert env.unwrapped.agent.controller.command == (BOX_V, 0.0)
    # braking: 0.2 m/s less every step, down to a standstill
    for v in ramp(0.0, DV, 7, start=BOX_V):
        x0 = env.unwrapped.snapshot.pose[0]
        env.step(np.zeros(2, dtype=np.float32))
        assert env.unwrapped.snapshot.pose[0] - x0 == pytest.approx(v * DT, abs=1e-4)
    assert env.unwrapped.agent.controller.command == (0.0, 0.0)


def test_turning_at_top_angular_speed_turns_the_hand_computed_angle(make_env):
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE)
    k = 8
    poses = drive(env, [(0.0, W_MAX)] * k)
    expected = np.cumsum(np.array(ramp(BOX_W, DW, k)) * DT)
    assert expected[5] == pytest.approx(DT * (15 * DW + BOX_W), rel=1e-9)  # 1.2 s to the top turn rate
    turned = np.unwrap([p[2] for p in poses])
    np.testing.assert_allclose(turned, expected, atol=1e-3)
    np.testing.assert_allclose([(p[0], p[1]) for p in poses], 0.0, atol=1e-4)  # in place
    poses = drive(env, [(0.0, -W_MAX)] * k)  # and clockwise
    np.testing.assert_allclose(np.unwrap([p[2] for p in poses]), -expected, atol=1e-3)


def test_an_arc_follows_the_heading_at_every_sub_step(make_env):
    """(v, w) held over a step's 4 sub-steps: each sub-step moves straight along the heading at
    its start, and turns by w / 20 s."""
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE)
    k, action = 9, (0.9, -2.0)
    poses = drive(env, [action] * k)
    x = y = yaw = 0.0
    vs, ws = ramp(0.9, DV, k), ramp(-2.0, DW, k)
    for (v, w), pose in zip(zip(vs, ws), poses):
        for _ in range(SUB_STEPS):
            x, y, yaw = x + v * math.cos(yaw) * DT / SUB_STEPS, y + v * math.sin(yaw) * DT / SUB_STEPS, yaw + w * DT / SUB_STEPS
        assert pose[:2] == pytest.approx((x, y), abs=2e-3)
        assert math.remainder(pose[2] - yaw, 2 * math.pi) == pytest.approx(0.0, abs=1e-3)


def test_out_of_box_actions_are_clipped_to_the_box(make_env):
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE)
    clipped = drive(env, [(50.0, -1e6)] * 8)
    assert env.unwrapped.agent.controller.command == (BOX_V, -BOX_W)
    at_bounds = drive(env, [(V_MAX, -W_MAX)] * 8)
    assert clipped == at_bounds
    backwards = drive(env, [(-9.0, 0.0)] * 8)
    assert backwards[-1][0] == pytest.approx(-drive(env, [(V_MAX, 0.0)] * 8)[-1][0], abs=1e-4)


@pytest.mark.parametrize("action", [(float("nan"), 0.0), (0.0, float("inf")), (-float("inf"), 0.0), np.float32([np.nan, np.nan])])
def test_non_finite_actions_are_refused(make_env, action):
    env = make_env("DynNav-MovingTarget-v1", control_mode=VELOCITY_DRIVE)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action must be finite"):
        env.step(np.asarray(action))


@pytest.mark.parametrize("action", [0, np.int64(1), [1.0], [1.0, 0.0, 0.0], "ab", None, [True, False], np.zeros((2, 2))])
def test_actions_that_are_not_two_numbers_are_refused(make_env, action):
    env = make_env("DynNav-MovingTarget-v1", control_mode=VELOCITY_DRIVE)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"control_mode 'diff_drive_vel' takes an action of two numbers"):
        env.step(action)


@pytest.mark.parametrize("form", [[0.5, 0.25], (0.5, 0.25), np.float64([[0.5, 0.25]]), np.array([1, 0]),
                                  torch.tensor([0.5, 0.25])])
def test_two_numbers_in_any_form_are_accepted(make_env, form):
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE)
    env.reset(seed=0)
    env.step(form)
    v, w = np.asarray(form, dtype=np.float64).reshape(-1).tolist()
    assert env.unwrapped.agent.controller.command == (min(v, DV), min(w, DW))


def test_the_batched_maniskill_api_takes_velocities():
    batched = gym.make("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE)  # ManiSkill's torch API
    try:
        batched.reset(seed=0)
        obs, reward, terminated, *_ = batched.step(torch.tensor([[0.5, 0.3]]))
        assert obs.shape[0] == 1 and reward.shape == (1,)
    finally:
        batched.close()


def test_a_seed_replays_the_continuous_drive_bit_for_bit(make_env):
    env = make_env("DynNav-MovingObstacles-v1", control_mode=VELOCITY_DRIVE)
    space = env.action_space

    def episode(seed):
        rng = np.random.default_rng(7)
        rows = [env.reset(seed=seed)[0]]
        for _ in range(40):
            obs, reward, terminated, truncated, info = env.step(rng.uniform(space.low, space.high).astype(np.float32))
            rows.append(np.concatenate([obs, [reward, terminated, truncated, info["path_length"]]]))
            if terminated or truncated:
                break
        return np.concatenate(rows)

    first = episode(3)
    assert np.array_equal(first, episode(3))
    assert not np.array_equal(first, episode(4))


def test_the_velocity_limits_are_options_and_bounded(make_env):
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE, max_linear_speed=0.5, max_linear_accel=10.0)
    np.testing.assert_array_equal(env.action_space.high, np.float32([0.5, W_MAX]))
    poses = drive(env, [(1.0, 0.0)] * 3)  # 10 m/s^2: top speed in the first step
    np.testing.assert_allclose([p[0] for p in poses], [0.1, 0.2, 0.3], atol=1e-3)
    assert MAX_LINEAR_SPEED == pytest.approx(2.5)
    for kwargs, message in [
        (dict(max_linear_speed=2.6), r"max_linear_speed must be <= 2.5 m/s at 20 Hz physics, got 2.6"),
        (dict(max_angular_speed=8.0), r"max_angular_speed must be <= 7.854 rad/s"),
        (dict(max_linear_accel=float("nan")), r"max_linear_accel must be a finite number > 0"),
        (dict(max_angular_accel=0.0), r"max_angular_accel must be a finite number > 0"),
    ]:
        with pytest.raises(ValueError, match=message):
            gym.make("DynNav-MovingTarget-v1", control_mode=VELOCITY_DRIVE, **kwargs)
    with pytest.raises(ValueError, match=r"make the task with control_mode='diff_drive_vel'"):
        gym.make("DynNav-MovingTarget-v1", max_linear_speed=1.0)


# ---------------------------------------------------------------------------- noise
def test_action_noise_is_gaussian_on_the_velocities_within_the_box(make_env):
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE, action_noise=0.1)
    noise = env.unwrapped.episode_noise

    def executed(seed):
        env.reset(seed=seed)
        out = []
        for _ in range(200):  # turning in place at the top turn rate; v is the noise alone
            *_, terminated, _, _ = env.step(np.float32([0.0, W_MAX]))
            assert not terminated
            out.append(noise.executed_action)
        return np.array(out)

    first = executed(1)
    assert np.array_equal(first, executed(1)) and not np.array_equal(first, executed(2))
    assert (np.abs(first) <= [BOX_V, BOX_W]).all()
    assert (first[:, 1] < BOX_W).mean() > 0.3  # about half the noisy turn rates fall under the top one
    assert (first[:, 1] == BOX_W).mean() > 0.3  # and the others are clipped to the box
    # v is unclipped around 0: its spread is 0.1 x the limit
    assert np.std(first[:, 0]) == pytest.approx(0.1 * V_MAX, rel=0.25)


def test_the_robot_speed_scale_multiplies_velocities_and_accelerations(make_env):
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE,
                   robot_speed_scale_min=1.5, robot_speed_scale_max=1.5)
    k = 8
    poses = drive(env, [(V_MAX, 0.0)] * k)
    expected = np.cumsum(np.array(ramp(1.5 * BOX_V, 1.5 * DV, k)) * DT)  # 0.3 m/s more a step, up to 1.8 m/s
    np.testing.assert_allclose([p[0] for p in poses], expected, atol=1e-3)
    np.testing.assert_array_equal(env.action_space.high, np.float32([V_MAX, W_MAX]))  # the box is the nominal one


def test_a_speed_scale_beyond_the_collision_check_is_refused():
    with pytest.raises(ValueError, match=r"robot_speed_scale_max 2.0 makes the robot too fast: .*max_angular_speed"):
        gym.make("DynNav-MovingTarget-v1", control_mode=VELOCITY_DRIVE, robot_speed_scale_max=2.0)


# ---------------------------------------------------------------------------- tools
NORMALIZED_BOX_ADVICE = "we recommend using a symmetric and normalized space"
"""check_env's advice for Box actions: the velocity drive's are in physical units by design
(``RescaleAction`` gives [-1, 1], see the next test)"""


def _checked(task_id: str, **kwargs):
    env = dynnav_tasks.NumpyWrapper(gym.make(task_id, **kwargs))
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            check_env(env, skip_render_check=True)
        assert [str(w.message) for w in caught if "WARN" in str(w.message) and "unwrapped" not in str(w.message)
                and NORMALIZED_BOX_ADVICE not in str(w.message)] == []
    finally:
        env.close()


@pytest.mark.parametrize("task_id", ["DynNav-MovingTarget-v1", "DynNav-Procedural-v1"])
@pytest.mark.parametrize("mode", CONTROL_MODES)
def test_check_env_passes_in_every_control_mode(task_id, mode):
    _checked(task_id, control_mode=mode)


def test_make_vec_batches_velocity_actions():
    envs = gym.make_vec("DynNav-MovingTarget-v1", num_envs=2, control_mode=VELOCITY_DRIVE)
    try:
        assert envs.single_action_space.shape == (2,) and envs.action_space.shape == (2, 2)
        envs.reset(seed=0)
        obs, reward, *_ = envs.step(np.float32([[1.2, 0.0], [0.0, -5.0]]))
        assert obs.shape == (2, 24) and reward.shape == (2,)  # 20 + heading + velocity
    finally:
        envs.close()


def test_rescale_action_gives_a_normalized_box(make_env):
    env = gym.wrappers.RescaleAction(make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE), -1.0, 1.0)
    env.reset(seed=0)
    env.step(np.float32([0.5, -0.5]))
    assert env.unwrapped.agent.controller.command == pytest.approx((DV, -DW))  # 0.6 m/s and -2.6 rad/s, ramped
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, skip_render_check=True, skip_close_check=True)
    assert [str(w.message) for w in caught if "WARN" in str(w.message) and "unwrapped" not in str(w.message)] == []


def test_the_planner_and_the_camera_pilot_refuse_the_continuous_drive():
    from dynnav_tasks.baselines.camera_pilot import run_pilot
    from dynnav_tasks.baselines.state_planner import run_planner

    with pytest.raises(ValueError, match=r"chooses among the three discrete actions.*not 'diff_drive_vel'"):
        run_planner("DynNav-MovingTarget-v1", [0], task_kwargs=dict(control_mode=VELOCITY_DRIVE))
    env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-MovingTarget-v1", control_mode=VELOCITY_DRIVE))
    try:
        with pytest.raises(ValueError, match=r"the camera pilot chooses among the three discrete actions"):
            run_pilot("DynNav-MovingTarget-v1", [0], env=env)
    finally:
        env.close()


def test_the_config_scales_and_clips():
    config = VelocityDriveConfig()
    assert config.scaled(1.5).speed_scale == 1.5 and config.speed_scale == 1.0
    assert config.clip(9.0, -9.0) == (BOX_V, -BOX_W)
    assert config.clip(0.3, 0.2) == (0.3, 0.2)


def test_the_continuous_state_ends_with_the_heading_and_the_driven_velocity(make_env):
    """With the velocity drive the study's state gains sin, cos of the yaw and then the (v, w)
    driven, the ramp of the acceleration limits: hand-computed from a start facing +x."""
    discrete = make_env("DynNavTest-DriveOpen-v1")
    env = make_env("DynNavTest-DriveOpen-v1", control_mode=VELOCITY_DRIVE)
    base = [name for name, _ in discrete.unwrapped.state_layout()]
    assert [name for name, _ in env.unwrapped.state_layout()] == base + ["robot_heading", "robot_velocity"]
    obs, _ = env.reset(seed=0)
    assert obs.shape == (discrete.observation_space.shape[0] + 4,)
    np.testing.assert_array_equal(obs[-2:], [0.0, 0.0])  # at rest after a reset
    env.unwrapped.place_robot(0.0, 0.0, 0.0)
    k, v, w = 4, 0.5, 2.0
    vs, ws = ramp(v, DV, k), ramp(w, DW, k)
    for i in range(k):
        obs, *_ = env.step(np.float32([v, w]))
        yaw = sum(ws[: i + 1]) * DT
        np.testing.assert_allclose(obs[-4:-2], [math.sin(yaw), math.cos(yaw)], atol=1e-4)
        np.testing.assert_allclose(obs[-2:], [vs[i], ws[i]], atol=1e-6)
        assert env.observation_space.contains(obs)
    assert vs == pytest.approx([0.2, 0.4, 0.5, 0.5]) and ws[-1] == pytest.approx(2.0)
