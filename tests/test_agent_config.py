"""Training configuration: YAML + command line, and errors that name what was wrong."""

from pathlib import Path

import pytest

from agents.config import Config, load_yaml, parse_args
from agents.envs import make_env

CONFIGS = Path(__file__).resolve().parents[1] / "configs"


def write(tmp_path, text: str) -> str:
    path = tmp_path / "c.yaml"
    path.write_text(text)
    return str(path)


def test_thesis_configs_hold_the_thesis_settings():
    c52 = load_yaml(CONFIGS / "moving_target_5_2.yaml")
    assert (c52.task, c52.episodes, c52.learning_rate, c52.epsilon_decay_episodes, c52.reward_mode) == (
        "DynNav-MovingTarget-v1", 2000, 0.003, 1000, "distance")
    c53 = load_yaml(CONFIGS / "moving_obstacles_5_3.yaml")
    assert (c53.task, c53.episodes, c53.learning_rate, c53.epsilon_decay_episodes, c53.reward_mode) == (
        "DynNav-MovingObstacles-v1", 4000, 0.001, 2000, "distance")
    for c in (c52, c53):
        assert (c.gamma, c.batch_size, c.hidden_sizes, c.epsilon_start, c.epsilon_end) == (0.97, 128, (128, 128), 0.8, 0.05)
    for path in CONFIGS.rglob("*.yaml"):
        load_yaml(path).validate()


def test_command_line_overrides_yaml(tmp_path):
    path = write(tmp_path, "episodes: 7\nlearning_rate: 0.01\nhidden_sizes: [64, 32]\n")
    c = parse_args(["--config", path, "--learning-rate", "0.002", "--seed", "5"])
    assert (c.episodes, c.learning_rate, c.seed, c.hidden_sizes) == (7, 0.002, 5, (64, 32))
    assert parse_args([]) == Config()


def test_unknown_yaml_key_names_it_and_the_close_match(tmp_path):
    path = write(tmp_path, "episodes: 7\nlerning_rate: 0.01\n")
    with pytest.raises(ValueError, match=r"unknown field 'lerning_rate'.*'learning_rate'"):
        parse_args(["--config", path])


@pytest.mark.parametrize("text,field", [
    ("episodes: ten\n", "episodes"),
    ("gamma: fast\n", "gamma"),
    ("hidden_sizes: [128, x]\n", "hidden_sizes"),
    ("algorithm: sarsa\n", "algorithm"),
    ("progress: 3\n", "progress"),
])
def test_wrong_type_in_yaml_names_the_field(tmp_path, text, field):
    with pytest.raises(ValueError, match=f"field '{field}' expects"):
        load_yaml(write(tmp_path, text))


def test_impossible_values_and_bad_files_are_clear_errors(tmp_path):
    with pytest.raises(ValueError, match="gamma"):
        parse_args(["--gamma", "1.5"])
    with pytest.raises(ValueError, match="eval_epsilon"):
        parse_args(["--eval-epsilon", "1.5"])
    with pytest.raises(ValueError, match="ae_rare_colour_power"):
        parse_args(["--ae-rare-colour-power", "-0.5"])
    with pytest.raises(ValueError, match="batch_size"):
        parse_args(["--batch-size", "0"])
    with pytest.raises(ValueError, match="--checkpoint"):
        parse_args(["--eval"])
    with pytest.raises(ValueError, match="does not exist"):
        parse_args(["--config", str(tmp_path / "missing.yaml")])
    with pytest.raises(ValueError, match="not valid YAML"):
        load_yaml(write(tmp_path, "episodes: [1,\n"))
    with pytest.raises(ValueError, match="mapping"):
        load_yaml(write(tmp_path, "- 1\n- 2\n"))


def test_unknown_task_and_unsuitable_envs_are_clear_errors():
    with pytest.raises(ValueError, match=r"Unknown task id 'DynNav-MovingTargt-v1'.*'DynNav-MovingTarget-v1'"):
        make_env("DynNav-MovingTargt-v1")
    with pytest.raises(ValueError, match=r"'CartPole-v1'"):
        make_env("CartPol-v1")
    with pytest.raises(ValueError, match="Discrete"):
        make_env("Pendulum-v1")
    with pytest.raises(ValueError, match="apply to dynnav tasks only"):
        make_env("CartPole-v1", reward_mode="distance")


def test_epsilon_and_learning_rate_schedules():
    from agents.schedules import epsilon_at, learning_rate_at

    c = Config(random_episodes=10, epsilon_start=0.8, epsilon_end=0.05, epsilon_decay_episodes=100)
    assert [epsilon_at(c, e) for e in (0, 9)] == [1.0, 1.0]
    assert epsilon_at(c, 10) == pytest.approx(0.8)
    assert epsilon_at(c, 60) == pytest.approx(0.425)
    assert epsilon_at(c, 110) == epsilon_at(c, 5000) == pytest.approx(0.05)
    c = Config(epsilon_schedule="exponential", epsilon_start=0.8, epsilon_end=0.05, epsilon_decay_episodes=100)
    assert epsilon_at(c, 50) == pytest.approx((0.8 * 0.05) ** 0.5)
    assert learning_rate_at(Config(learning_rate=0.003), 1500) == 0.003  # constant
    lin = Config(lr_schedule="linear", learning_rate=0.003, learning_rate_end=0.0003, lr_decay_episodes=1000)
    assert learning_rate_at(lin, 500) == pytest.approx(0.00165)
    assert learning_rate_at(lin, 3000) == pytest.approx(0.0003)
    exp = Config(lr_schedule="exponential", learning_rate=0.003, learning_rate_end=0.0003, lr_decay_episodes=1000)
    assert learning_rate_at(exp, 500) == pytest.approx(0.003 / 10 ** 0.5)


def test_observation_scaling_uses_the_space_bounds():
    import gymnasium as gym
    import numpy as np

    from agents.envs import ObsScaler

    space = gym.spaces.Box(np.array([0.0, -2.0, -np.inf], np.float32), np.array([5.0, 4.5, np.inf], np.float32))
    scale = ObsScaler(space)
    np.testing.assert_allclose(scale(np.array([0.0, 4.5, 7.0], np.float32)), [-1.0, 1.0, 7.0])
    np.testing.assert_allclose(scale(np.array([2.5, 1.25, -3.0], np.float32)), [0.0, 0.0, -3.0])
    np.testing.assert_allclose(ObsScaler(space, enabled=False)(np.array([5.0, 4.5, 1.0])), [5.0, 4.5, 1.0])
