"""Reinforcement learning on top of a teacher (``demos`` settings): the large-margin loss, the
demonstrations in the minibatch, and a DQN run that starts from a cloned student."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
import torch

from agents.core.demo_replay import DemoReplay
from agents.core.demonstrations import Demonstrations
from agents.core.learner import DQNLearner
from agents.core.policy import build_q_network
from agents.core.replay import Batch
from agents.imitation.config import ImitationConfig
from agents.imitation.dagger import train as imitate
from agents.training import checkpoint as ckpt
from agents.training import loop
from agents.training.config_io import load_yaml
from agents.training.envs import make_env_from
from agents.training.experience import make_features

ROOT = Path(__file__).resolve().parents[1]


def test_the_margin_loss_by_hand():
    learner = DQNLearner(torch.nn.Linear(2, 3), Batch(2, [((2,), np.float32)]), margin_weight=1.0, margin=0.8)
    q = torch.tensor([[1.0, 2.0, 0.0], [3.0, 1.0, 2.5], [0.0, 0.0, 0.0]])
    # row 0, teacher's action 0: max(1 + 0, 2 + 0.8, 0 + 0.8) - 1 = 1.8
    # row 1, teacher's action 0: max(3, 1.8, 3.3) - 3 = 0.3;  row 2: no label, left out
    assert float(learner.margin_loss(q, torch.tensor([0, 0, -1]))) == pytest.approx((1.8 + 0.3) / 2)
    assert float(learner.margin_loss(q, torch.tensor([-1, -1, -1]))) == 0.0
    q = torch.tensor([[5.0, 4.0, 4.2]])  # the teacher's action leads by at least the margin: nothing to learn
    assert float(learner.margin_loss(q, torch.tensor([0]))) == 0.0


def test_demonstrations_fill_their_share_of_the_minibatch_with_their_labels():
    n = 50
    obs = np.arange(n * 2, dtype=np.float32).reshape(n, 2)
    demos = DemoReplay(obs, obs + 1000, np.zeros(n), np.full(n, 7.0), np.ones(n), np.arange(n) % 3, share=0.25)
    batch = Batch(16, [((2,), np.float32)])
    batch.obs[0][:] = -1.0
    batch.labels[:] = 2  # what the last minibatch left
    demos.sample_into(batch, np.random.default_rng(0))
    k = demos.rows(batch)
    assert k == 4
    rows = (batch.obs[0][:k, 0] / 2).astype(int)  # each demonstration row is a stored transition, whole
    np.testing.assert_array_equal(batch.next_obs[0][:k], obs[rows] + 1000)
    np.testing.assert_array_equal(batch.labels[:k], rows % 3)
    np.testing.assert_array_equal(batch.rewards[:k], 7.0)
    assert (batch.labels[k:] == -1).all() and (batch.obs[0][k:] == -1.0).all()  # the agent's rows untouched


@pytest.fixture(scope="module")
def student(tmp_path_factory):
    """A tiny imitation run on easy worlds: its directory and the training config it used."""
    folder = tmp_path_factory.mktemp("teacher")
    config_path = folder / "student.yaml"
    config_path.write_text(f"base: {ROOT / 'configs/procedural/generalist.yaml'}\n"
                           "env:\n  task_kwargs: {difficulty: easy, split: train, way: true, turn_forward_step: 0.0}\n"
                           "dqn: {hidden_sizes: [64, 64], learning_starts: 100000}\n"
                           "test:\n  eval_after_training: false\n  also_test_on: []\n"
                           "run: {progress: false}\n")
    cfg = ImitationConfig(student=str(config_path), teacher_episodes=6, rounds=0, epochs=40, workers=0,
                          runs_dir=str(folder / "runs"), progress=False, dataset=False)
    return imitate(cfg), load_yaml(config_path)


def run_config(config, tmp_path, **demos):
    return dataclasses.replace(config, episodes=2, run=dataclasses.replace(config.run, runs_dir=str(tmp_path)),
                               demos=dataclasses.replace(config.demos, **demos))


def test_a_run_starts_from_the_cloned_student(student, tmp_path):
    run, config = student
    run_dir = loop.train(run_config(config, tmp_path, init_from=str(run)))  # learning_starts: no update in 2 episodes
    theirs = ckpt.load(run, memory=False)["learner"]["q"]
    ours = ckpt.load(run_dir, memory=False)["learner"]
    for name, value in theirs.items():
        torch.testing.assert_close(ours["q"][name], value)
        torch.testing.assert_close(ours["target"][name], value)


def test_pretraining_on_the_demonstrations_keeps_the_teachers_choices(student, tmp_path):
    run, config = student
    config = run_config(config, tmp_path, init_from=str(run), demonstrations=str(run), pretrain_updates=300)
    run_dir = loop.train(config)
    env = make_env_from(config)
    try:
        features = make_features(env, config)
    finally:
        env.close()
    data = Demonstrations.load(run / "demonstrations.npz")
    x, labels = data.states()
    net = build_q_network(config, features.input_specs, 3)
    net.load_state_dict(ckpt.load(run_dir, memory=False)["learner"]["q"])  # the run's Q-network after pre-training
    with torch.no_grad():
        q = net(torch.as_tensor(features(x).astype(np.float32))).numpy()
    assert (q.argmax(1) == labels).mean() >= 0.9  # the margin keeps the teacher's action on top
    assert np.abs(q).max() > 1.0  # and the TD loss has given the Q-values the rewards' scale


def test_demonstrations_of_another_reward_are_refused_before_any_file(student, tmp_path):
    run, config = student
    config = run_config(config, tmp_path / "runs", demonstrations=str(run))
    config = dataclasses.replace(config, env=dataclasses.replace(config.env, reward_mode="sparse"))
    with pytest.raises(ValueError, match="reward_mode"):
        loop.train(config)
    assert not (tmp_path / "runs").exists()


def test_a_teacher_pattern_finds_the_newest_run_of_the_seed(tmp_path):
    from agents.training.teacher import teacher_run

    for name in ("T__g__2__20260101-000000", "T__g__2__20260102-000000", "T__g__3__20260103-000000"):
        (tmp_path / name).mkdir()
    pattern = str(tmp_path / "T__g__{seed}__*")
    assert teacher_run(pattern, 2, "init_from") == tmp_path / "T__g__2__20260102-000000"
    assert teacher_run(str(tmp_path / "plain"), 2, "init_from") == tmp_path / "plain"  # no pattern: as given
    with pytest.raises(ValueError, match="no folder matches .*__4__"):
        teacher_run(pattern, 4, "demonstrations")
