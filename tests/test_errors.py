"""Bad names get a clear error listing the valid values and the close matches."""

import os
import subprocess
import sys

import gymnasium as gym
import pytest

import dynnav_tasks


def test_unknown_task_id_lists_tasks_and_close_match():
    with pytest.raises(ValueError) as err:
        dynnav_tasks.make("DynNav-MovingObstacle-v1")
    msg = str(err.value)
    assert "Unknown task id 'DynNav-MovingObstacle-v1'" in msg
    for task in dynnav_tasks.TASK_IDS:
        assert task in msg
    assert "Did you mean 'DynNav-MovingObstacles-v1'" in msg


def test_unknown_task_id_through_gymnasium_suggests_close_match():
    with pytest.raises(gym.error.NameNotFound, match="Did you mean: `DynNav-MovingObstacles`"):
        gym.make("DynNav-MovingObstacle-v1")


def test_unknown_reward_mode():
    with pytest.raises(ValueError) as err:
        gym.make("DynNav-MovingTarget-v1", reward_mode="potentail")
    msg = str(err.value)
    assert "Unknown reward_mode 'potentail'" in msg
    assert "distance_orientation_always, distance_orientation, distance, potential, potential_as_written, sparse" in msg
    assert "Did you mean 'potential'" in msg


def test_unknown_obs_mode():
    with pytest.raises(ValueError, match=r"Unknown obs_mode 'stat'\. Valid obs_modes: state, rgb, rgb\+state\. Did you mean 'state'"):
        gym.make("DynNav-MovingTarget-v1", obs_mode="stat")


def test_bad_action_is_named(make_env):
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"action must be an integer in \[0, 3\) \(forward, left, right\), got 3"):
        env.step(3)


def test_bad_step_length_is_named():
    with pytest.raises(ValueError, match="DriveConfig.forward_step must be > 0"):
        gym.make("DynNav-MovingTarget-v1", forward_step=0.0)


def test_missing_vulkan_driver_says_how_to_install():
    code = "import gymnasium as gym, dynnav_tasks; gym.make('DynNav-MovingTarget-v1')"
    env = dict(os.environ, VK_ICD_FILENAMES="/nonexistent/icd.json")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode != 0
    assert "VulkanUnavailableError" in out.stderr
    assert "apt-get install -y -t bookworm-backports mesa-vulkan-drivers libvulkan1" in out.stderr
