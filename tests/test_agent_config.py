"""Training configuration: YAML + command line, and errors that name what was wrong."""

import pytest

from agents.training.config import Config, ScheduleConfig
from agents.training.config_io import load_yaml, make, parse_args, to_yaml_dict
from agents.training.envs import make_env


def write(tmp_path, text: str) -> str:
    path = tmp_path / "c.yaml"
    path.write_text(text)
    return str(path)


def test_command_line_overrides_yaml(tmp_path):
    path = write(tmp_path, "episodes: 7\nlearning_rate: 0.01\nhidden_sizes: [64, 32]\n")
    c = parse_args(["--config", path, "--learning-rate", "0.002", "--seed", "5"])
    assert (c.episodes, c.schedule.learning_rate, c.seed, c.dqn.hidden_sizes) == (7, 0.002, 5, (64, 32))
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
    from agents.core.schedules import epsilon_at, learning_rate_at

    c = ScheduleConfig(random_episodes=10, epsilon_start=0.8, epsilon_end=0.05, epsilon_decay_episodes=100)
    assert [epsilon_at(c, e) for e in (0, 9)] == [1.0, 1.0]
    assert epsilon_at(c, 10) == pytest.approx(0.8)
    assert epsilon_at(c, 60) == pytest.approx(0.425)
    assert epsilon_at(c, 110) == epsilon_at(c, 5000) == pytest.approx(0.05)
    c = ScheduleConfig(epsilon_schedule="exponential", epsilon_start=0.8, epsilon_end=0.05, epsilon_decay_episodes=100)
    assert epsilon_at(c, 50) == pytest.approx((0.8 * 0.05) ** 0.5)
    assert learning_rate_at(ScheduleConfig(learning_rate=0.003), 1500) == 0.003  # constant
    lin = ScheduleConfig(lr_schedule="linear", learning_rate=0.003, learning_rate_end=0.0003, lr_decay_episodes=1000)
    assert learning_rate_at(lin, 500) == pytest.approx(0.00165)
    assert learning_rate_at(lin, 3000) == pytest.approx(0.0003)
    exp = ScheduleConfig(lr_schedule="exponential", learning_rate=0.003, learning_rate_end=0.0003, lr_decay_episodes=1000)
    assert learning_rate_at(exp, 500) == pytest.approx(0.003 / 10 ** 0.5)


def test_observation_scaling_uses_the_space_bounds():
    import gymnasium as gym
    import numpy as np

    from agents.core.obs_scaling import ObsScaler

    space = gym.spaces.Box(np.array([0.0, -2.0, -np.inf], np.float32), np.array([5.0, 4.5, np.inf], np.float32))
    scale = ObsScaler(space)
    np.testing.assert_allclose(scale(np.array([0.0, 4.5, 7.0], np.float32)), [-1.0, 1.0, 7.0])
    np.testing.assert_allclose(scale(np.array([2.5, 1.25, -3.0], np.float32)), [0.0, 0.0, -3.0])
    np.testing.assert_allclose(ObsScaler(space, enabled=False)(np.array([5.0, 4.5, 1.0])), [5.0, 4.5, 1.0])


def test_grouped_and_flat_yaml_give_the_same_config(tmp_path):
    grouped = write(tmp_path, "name: x\nepisodes: 7\ndqn: {batch_size: 32, hidden_sizes: [64]}\nschedule: {learning_rate: 0.01}\n")
    flat = tmp_path / "flat.yaml"
    flat.write_text("name: x\nepisodes: 7\nbatch_size: 32\nhidden_sizes: [64]\nlearning_rate: 0.01\n")
    assert load_yaml(grouped) == load_yaml(flat) == make(name="x", episodes=7, batch_size=32, hidden_sizes=(64,),
                                                         learning_rate=0.01)
    saved = tmp_path / "saved.yaml"
    saved.write_text(__import__("yaml").safe_dump(to_yaml_dict(load_yaml(flat))))
    assert load_yaml(saved) == load_yaml(flat)  # a run's config.yaml reads back the same
    with pytest.raises(ValueError, match=r"unknown field 'dqn.learning_rate'. It belongs in the 'schedule' group"):
        load_yaml(write(tmp_path, "dqn: {learning_rate: 0.01}\n"))


def test_help_lists_documented_flags_by_group(capsys):
    with pytest.raises(SystemExit):
        parse_args(["--help"])
    out = capsys.readouterr().out
    for flag in ("--learning-rate", "--camera-input", "--q-network", "--device", "--eval-episodes", "--task-kwargs"):
        assert flag in out, flag
    assert "where the Q-network and its update run" in out


def test_a_config_file_of_binary_junk_names_the_file(tmp_path):
    junk = tmp_path / "junk.yaml"
    junk.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(ValueError, match=f"config file '{junk}' is not a text"):
        parse_args(["--config", str(junk)])


def test_batch_larger_than_the_memory_is_an_error_before_any_run():
    with pytest.raises(ValueError, match=r"batch_size \(64\) is larger than buffer_size \(32\)"):
        parse_args(["--batch-size", "64", "--buffer-size", "32"])


def test_eval_refuses_training_settings_it_would_ignore():
    with pytest.raises(ValueError, match="--task cannot change them"):
        parse_args(["--eval", "--checkpoint", "runs/x", "--task", "CartPole-v1"])
    with pytest.raises(ValueError, match="--learning-rate, --normalize-obs cannot change them"):
        parse_args(["--eval", "--checkpoint", "runs/x", "--learning-rate", "0.1", "--no-normalize-obs"])
    c = parse_args(["--eval", "--checkpoint", "runs/x", "--eval-episodes", "3", "--no-eval-picture"])
    assert (c.test.eval_episodes, c.test.eval_picture) == (3, False)


def test_key_value_flags_lay_over_the_yaml_keys(tmp_path):
    path = write(tmp_path, "env:\n  reward_params: {distance_gamma: 0.1}\n  task_kwargs: {turn_forward_step: 0.05}\n")
    c = parse_args(["--config", str(path), "--reward-params", "collision_reward", "-100"])
    assert c.env.reward_params == {"distance_gamma": 0.1, "collision_reward": -100.0}
    assert c.env.task_kwargs == {"turn_forward_step": 0.05}
    c = parse_args(["--config", str(path), "--reward-params", "distance_gamma", "0.2", "--task-kwargs", "camera_size", "16"])
    assert c.env.reward_params == {"distance_gamma": 0.2}
    assert c.env.task_kwargs == {"turn_forward_step": 0.05, "camera_size": 16}
    assert parse_args(["--config", str(path)]).env.reward_params == {"distance_gamma": 0.1}


def test_integer_task_options_stay_integers(tmp_path):
    c = parse_args(["--task-kwargs", "camera_size", "32", "turn_forward_step", "0.05"])
    assert c.env.task_kwargs == {"camera_size": 32, "turn_forward_step": 0.05}
    assert type(c.env.task_kwargs["camera_size"]) is int
    env = make_env("DynNav-VisualStaticTarget-v1", task_kwargs={"camera_size": 16}, camera_frames=1)
    try:
        assert env.observation_space["rgb"].shape == (16, 16, 3)
    finally:
        env.close()


def test_state_frames_stack_the_last_states_oldest_first():
    import numpy as np

    env = make_env("DynNav-MovingObstacles-v1", state_frames=2)
    try:
        assert env.observation_space.shape == (48,)
        first, _ = env.reset(seed=3)
        assert np.array_equal(first[:24], first[24:])  # a reset repeats the first state
        second, *_ = env.step(0)
        assert np.array_equal(second[:24], first[24:])  # the older state first
        moved = second[44:48] - second[20:24]  # the two obstacles' motion over the step
        speed = np.linalg.norm(moved.reshape(2, 2), axis=1)
        assert np.all(speed > 0)  # the stack shows that they move
    finally:
        env.close()
    with pytest.raises(ValueError, match="state_frames stacks state vectors for runs without a camera"):
        parse_args(["--state-frames", "2", "--camera-frames", "1"])
    with pytest.raises(ValueError, match="state_frames must be at least 1"):
        parse_args(["--state-frames", "0"])
