"""The agent learns: a short training run on a dynnav task passes the test phase, and the
same code learns a gymnasium classic (CartPole) it knows nothing special about."""

from agents.config_io import make
from agents.dqn import train
from agents.evaluate import evaluate


def test_learns_moving_targets_world(tmp_path):
    """World 5.2 (three moving targets, static obstacles) in 600 episodes (about 40 s).

    Made easier than the thesis set-up in two ways: turns also move the robot 5 cm forward
    (a robot turning in place can dither left-right forever under a greedy policy, since the
    state has no heading), and a collision costs -50 instead of -20.
    """
    config = make(
        task="DynNav-MovingTarget-v1", reward_mode="distance_orientation_always",
        reward_params={"collision_reward": -50.0}, task_kwargs={"turn_forward_step": 0.05},
        algorithm="ddqn", episodes=600, learning_rate=0.001, lr_schedule="linear", learning_rate_end=0.0001,
        lr_decay_episodes=600, epsilon_decay_episodes=300, target_update_interval=200,
        checkpoint_every=600, runs_dir=str(tmp_path), progress=False, eval_after_training=False, seed=1,
    ).validate()
    run = train(config)
    summary = evaluate(run, episodes=100, picture=False, verbose=False)
    assert summary["success_rate"] >= 0.9, summary
    assert summary["spl"] > 0.5, summary


def test_learns_cartpole(tmp_path):
    config = make(
        task="CartPole-v1", algorithm="ddqn", episodes=300, gamma=0.99, learning_rate=0.0005, epsilon_start=1.0,
        epsilon_decay_episodes=150, target_update_interval=200,
        checkpoint_every=300, runs_dir=str(tmp_path), progress=False, eval_after_training=False, seed=1,
    ).validate()
    run = train(config)
    summary = evaluate(run, episodes=20, verbose=False)
    assert summary["avg_return"] >= 195, summary  # CartPole's "solved" mark; a random policy averages about 22
    assert summary["collision_rate"] == 0 and "spl" not in summary
