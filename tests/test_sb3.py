"""Stable-Baselines3 on the continuous drive, with no glue beyond ``NumpyWrapper``: SB3's own
env checker passes, SAC and PPO train for a few hundred steps and act inside the box, a saved
model acts the same after loading, and the docs' example script tests a model by outcome."""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch

import dynnav_tasks

sb3 = pytest.importorskip("stable_baselines3", reason="the bench extra (pip install -e '.[bench]')")

torch.set_num_threads(1)  # as the example does: one torch thread per process
ROOT = Path(__file__).resolve().parents[1]
TASK = "DynNav-MovingTarget-v1"


def load_example():
    spec = importlib.util.spec_from_file_location("sb3_continuous_drive", ROOT / "examples/sb3_continuous_drive.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def example():
    return load_example()


@pytest.mark.parametrize("control_mode", ["discrete_drive", "diff_drive_vel"])
def test_sb3_env_checker_passes(control_mode):
    """SB3's checker raises on any break of the API it relies on. It only advises (a warning)
    a normalized action box, which the continuous drive's physical units are not."""
    from stable_baselines3.common.env_checker import check_env

    env = dynnav_tasks.NumpyWrapper(gym.make(TASK, control_mode=control_mode))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, warn=True)
    env.close()
    advice = [str(w.message) for w in caught if "symmetric and normalized" in str(w.message)]
    assert bool(advice) == (control_mode == "diff_drive_vel")


@pytest.mark.parametrize("algo, overrides", [
    ("sac", dict(learning_starts=50, batch_size=32, buffer_size=1000)),
    ("ppo", dict(n_steps=64, batch_size=32, n_epochs=2)),
])
def test_short_training_acts_in_the_box_and_reloads(example, algo, overrides, tmp_path):
    env = example.make_env(TASK)
    assert isinstance(env.action_space, gym.spaces.Box) and env.action_space.shape == (2,)
    model = example.make_model(algo, env, seed=1, **overrides)
    before = {k: v.clone() for k, v in model.policy.state_dict().items()}
    model.learn(total_timesteps=128)
    assert model.num_timesteps == 128
    changed = [k for k, v in model.policy.state_dict().items() if not np.array_equal(v.numpy(), before[k].numpy())]
    assert changed, "training did not change the policy's weights"

    obs, _ = env.reset(seed=3)
    actions = [model.predict(obs, deterministic=True)[0]]
    for _ in range(5):
        obs, *_ = env.step(actions[-1])
        actions.append(model.predict(obs, deterministic=True)[0])
    low, high = env.action_space.low, env.action_space.high
    assert all(a.shape == (2,) and np.all(a >= low) and np.all(a <= high) for a in actions)

    model.save(tmp_path / algo)
    loaded = type(model).load(tmp_path / algo, device="cpu")
    obs, _ = env.reset(seed=3)
    np.testing.assert_array_equal(loaded.predict(obs, deterministic=True)[0], actions[0])
    env.close()


def test_example_test_counts_every_episode_by_its_outcome(example):
    """The example's test phase: every episode ends in exactly one outcome. A policy that
    always drives full speed ahead never times out in world 5.2 (a wall or a target comes first)."""

    class FullAhead:
        def predict(self, obs, deterministic=True):
            return np.float32([1.2, 0.0]), None

    env = example.make_env(TASK)
    outcomes = example.test(FullAhead(), env, episodes=4)
    env.close()
    assert sum(outcomes.values()) == 4
    assert set(outcomes) <= {"success", "collision"}


def test_example_refuses_an_unknown_algorithm(example):
    env = example.make_env(TASK)
    with pytest.raises(ValueError, match="unknown algorithm 'td3'; choose one of sac, ppo"):
        example.make_model("td3", env, seed=1)
    env.close()


def test_ppo_collects_from_several_copies_of_the_task(example):
    envs = example.make_training_env(TASK, envs=2)
    assert envs.num_envs == 2 and envs.action_space.shape == (2,)
    model = example.make_model("ppo", envs, seed=1, n_steps=32, batch_size=32, n_epochs=1)
    model.learn(total_timesteps=64)
    assert model.num_timesteps == 64
    envs.close()
