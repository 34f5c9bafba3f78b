"""gymnasium's own tools on the tasks: make_vec, AsyncVectorEnv with every start method,
check_env with ManiSkill's reward modes, and the batched ManiSkill API beside the plain one."""

import multiprocessing

import gymnasium as gym
import numpy as np
import pytest
import torch
from gymnasium.utils.env_checker import check_env
from mani_skill.utils.wrappers.gymnasium import CPUGymWrapper

import dynnav_tasks

TASK = "DynNav-MovingTarget-v1"  # state size 20


@pytest.mark.parametrize("mode", [None, "sync", "async"])
def test_make_vec_batches_plain_sub_environments(mode):
    """The default mode wraps its sub-environments itself; gymnasium's own modes are told to."""
    extra = {} if mode is None else dict(vectorization_mode=mode, wrappers=[dynnav_tasks.NumpyWrapper])
    env = gym.make_vec(TASK, num_envs=2, **extra)
    try:
        obs, info = env.reset(seed=0)
        assert obs.shape == (2, 20) and obs.dtype == np.float32
        assert env.single_observation_space.shape == (20,)
        obs, reward, terminated, truncated, info = env.step(np.array([0, 1]))
        assert obs.shape == (2, 20) and reward.shape == (2,) and terminated.shape == (2,)
        assert info["success"].shape == (2,)
        # the same seeds give the same episodes as single envs made by hand
        single = dynnav_tasks.NumpyWrapper(gym.make(TASK))
        first, _ = single.reset(seed=0)
        expected, *_ = single.step(0)
        single.close()
        np.testing.assert_array_equal(obs[0], expected)
    finally:
        env.close()


def test_make_vec_passes_task_arguments_and_recreates_from_its_spec():
    env = gym.make_vec(TASK, num_envs=3, reward_mode="sparse")
    try:
        assert env.num_envs == 3
        env.reset(seed=1)
        _, reward, *_ = env.step(np.array([1, 1, 1]))  # turning in place: neither end of the episode
        np.testing.assert_array_equal(reward, [-0.01] * 3)
        again = gym.make_vec(env.spec)
        assert again.num_envs == 3 and again.observation_space == env.observation_space
        again.close()
    finally:
        env.close()
    with pytest.raises(ValueError, match="num_envs must be a positive integer"):
        gym.make_vec(TASK, num_envs=0)


def _make_plain():
    return dynnav_tasks.NumpyWrapper(gym.make(TASK))


@pytest.mark.parametrize("context", ["fork", "forkserver", "spawn"])
def test_async_vector_env_with_every_start_method(context):
    """AsyncVectorEnv makes one env in this process first and closes it, then starts its
    workers: with fork they inherit this process, which must not hold a dying SAPIEN scene."""
    if context not in multiprocessing.get_all_start_methods():
        pytest.skip(f"{context} is not available here")
    env = gym.vector.AsyncVectorEnv([_make_plain, _make_plain], context=context)
    try:
        obs, _ = env.reset(seed=[3, 4])
        assert obs.shape == (2, 20)
        obs, reward, *_ = env.step(np.array([0, 2]))
        assert obs.shape == (2, 20) and np.isfinite(reward).all()
    finally:
        env.close()


def test_the_batched_maniskill_api_still_works():
    env = gym.make(TASK)
    try:
        obs, info = env.reset(seed=0)
        assert isinstance(obs, torch.Tensor) and obs.shape == (1, 20)
        obs, reward, terminated, truncated, info = env.step(torch.tensor([0]))
        assert obs.shape == (1, 20) and reward.shape == (1,) and terminated.dtype == torch.bool
        assert info["success"].shape == (1,) and int(info["elapsed_steps"][0]) == 1
        assert env.unwrapped.evaluate()["distance_to_target"].dtype == torch.float32
    finally:
        env.close()


@pytest.mark.parametrize("reward_mode", ["dense", "normalized_dense"])
def test_check_env_passes_with_maniskills_reward_modes(reward_mode):
    """ManiSkill's tools make tasks with reward_mode "dense" or "normalized_dense"."""
    env = dynnav_tasks.NumpyWrapper(gym.make(TASK, reward_mode=reward_mode))
    try:
        check_env(env, skip_render_check=True)
        assert env.unwrapped.reward_mode == reward_mode
    finally:
        env.close()


def test_numpy_wrapper_matches_cpu_gym_wrapper():
    """ManiSkill's own CPUGymWrapper still works on a task, with the same results."""
    a, b = dynnav_tasks.NumpyWrapper(gym.make(TASK)), CPUGymWrapper(gym.make(TASK))
    try:
        assert a.observation_space == b.observation_space and a.action_space == b.action_space
        np.testing.assert_array_equal(a.reset(seed=5)[0], b.reset(seed=5)[0])
        for action in [0, 0, 1, 0, 2, 0, 0]:
            ra, rb = a.step(action), b.step(action)
            np.testing.assert_array_equal(ra[0], rb[0])
            assert ra[1] == pytest.approx(float(rb[1]), abs=1e-6) and ra[2:4] == (bool(rb[2]), bool(rb[3]))
            for key in ("success", "collision", "timeout", "distance_to_target", "path_length"):
                assert ra[4][key] == pytest.approx(rb[4][key], abs=1e-6)
    finally:
        a.close()
        b.close()


def test_evaluate_changes_nothing(make_env):
    env = make_env(TASK)
    env.reset(seed=0)
    env.step(0)
    base = env.unwrapped
    before = base.snapshot
    first = base.evaluate()
    for _ in range(3):
        again = base.evaluate()
        assert base.snapshot is before
        assert all(torch.equal(first[k], again[k]) for k in first)
