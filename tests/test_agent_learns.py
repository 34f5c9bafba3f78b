"""The agent learns: a short training run on a dynnav task passes the test phase, and the
same code learns a gymnasium classic (CartPole) it knows nothing special about."""

from agents.training.config_io import make
from agents.dqn import train
from agents.training.test_phase import evaluate


def test_learns_moving_targets_world(tmp_path):
    """World 5.2 (three moving targets, static obstacles) in 400 episodes, with updates of 64
    transitions at every other step (1-2 minutes on one core).

    Made easier than the thesis set-up in two ways: turns also move the robot 5 cm forward
    (a robot turning in place can dither left-right forever under a greedy policy, since the
    state has no heading), and a collision costs -50 instead of -20.
    """
    config = make(
        task="DynNav-MovingTarget-v1", reward_mode="distance_orientation_always",
        reward_params={"collision_reward": -50.0}, task_kwargs={"turn_forward_step": 0.05},
        algorithm="ddqn", episodes=400, learning_rate=0.001, lr_schedule="linear", learning_rate_end=0.0001,
        lr_decay_episodes=400, epsilon_decay_episodes=200, batch_size=64, train_frequency=2,
        target_update_interval=100, checkpoint_every=400, runs_dir=str(tmp_path), progress=False,
        eval_after_training=False, seed=1,
    ).validate()
    run = train(config)
    summary = evaluate(run, episodes=100, picture=False, verbose=False)
    assert summary["success_rate"] >= 0.9, summary
    assert summary["spl"] > 0.5, summary


def test_learns_cartpole(tmp_path):
    """200 episodes with a small network (64, 64) updated every 4th step: a few seconds."""
    config = make(
        task="CartPole-v1", algorithm="ddqn", episodes=200, gamma=0.99, learning_rate=0.001, epsilon_start=1.0,
        epsilon_decay_episodes=100, hidden_sizes=(64, 64), batch_size=64, train_frequency=4,
        target_update_interval=50, checkpoint_every=200, runs_dir=str(tmp_path), progress=False,
        eval_after_training=False, seed=1,
    ).validate()
    run = train(config)
    summary = evaluate(run, episodes=20, verbose=False)
    assert summary["avg_return"] >= 195, summary  # CartPole's "solved" mark; a random policy averages about 22
    assert summary["collision_rate"] == 0 and "spl" not in summary
