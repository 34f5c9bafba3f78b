"""Teacher-student learning (agents.imitation): DAgger beats its behaviour-cloning start, the data
loads back as it was written (numpy and Minari), and bad input writes nothing."""

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from agents.imitation.collector import Collector
from agents.imitation.config import ImitationConfig
from agents.imitation.dagger import DATA_FILE, ROUNDS_FILE, train
from agents.core.demonstrations import Demonstrations
from agents.imitation.offline_dataset import load_minari, write_minari
from agents.training.config_io import load_yaml, to_yaml_dict
from agents.study.run_record import read_run
from agents.training.test_phase import evaluate

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def student(tmp_path_factory) -> Path:
    """The generalist's student on easy train worlds only, with no test phase of its own."""
    path = tmp_path_factory.mktemp("student") / "student.yaml"
    path.write_text(f"base: {ROOT / 'configs/procedural/generalist.yaml'}\n"
                    "env:\n  task_kwargs: {difficulty: easy, split: train, way: true, turn_forward_step: 0.0}\n"
                    "test:\n  eval_after_training: false\n  also_test_on: []\n")
    return path


def settings(student: Path, runs: Path, **changes) -> ImitationConfig:
    return dataclasses.replace(ImitationConfig(student=str(student), teacher_episodes=8, rounds=0, round_episodes=8,
                                               epochs=50, workers=0, runs_dir=str(runs), progress=False,
                                               dataset=False), **changes)


def success(run_dir: Path, out: Path) -> float:
    """Greedy success of the run's student on 40 easy train episodes (the same ones every time)."""
    return evaluate(run_dir, episodes=40, seed=5000, picture=False, out_dir=out, verbose=False)["success_rate"]


def test_dagger_improves_on_its_behaviour_cloning_start(student, tmp_path):
    cfg = settings(student, tmp_path / "runs")
    run_dir = train(cfg)  # round 0: behaviour cloning on 8 of the planner's episodes
    cloned = success(run_dir, tmp_path / "bc")
    from agents.imitation.__main__ import parse_args

    assert parse_args(["--resume", str(run_dir)]) == dataclasses.replace(cfg, resume=str(run_dir))  # its own settings
    assert parse_args(["--resume", str(run_dir), "--rounds", "2"]).rounds == 2  # ... with what a flag changes
    run_dir = train(dataclasses.replace(cfg, resume=str(run_dir), rounds=2))  # two DAgger rounds of 8 episodes
    dagger = success(run_dir, run_dir)  # the test phase into the run directory, as a DQN run's
    assert dagger >= cloned + 0.075, (cloned, dagger)

    (row,), episodes = read_run(run_dir)  # the student is a row of the run table
    assert row["experiment"] == "student-dagger" and row["episodes_done"] == 24  # the episodes it learned from
    assert row["success_rate"] == dagger and len(episodes) == 40 and row["train_s"] > 0

    data = Demonstrations.load(run_dir / DATA_FILE)
    assert sorted(set(data.rounds)) == [0, 1, 2] and len(data.rollouts) == 24
    first = [r for r, k in zip(data.rollouts, data.rounds) if k == 0]
    assert all((r.actions == r.labels).all() for r in first)  # round 0: the teacher drove
    later = [r for r, k in zip(data.rollouts, data.rounds) if k > 0]
    assert any((r.actions != r.labels).any() for r in later)  # DAgger: the student drove, the teacher labelled
    rows = (run_dir / ROUNDS_FILE).read_text().splitlines()
    assert [row.split(",")[0] for row in rows[1:]] == ["0", "1", "2"]  # one row per round, none twice


def test_demonstrations_load_back_as_numpy_and_as_a_minari_data_set(student, tmp_path, monkeypatch):
    config = load_yaml(student)
    with Collector(to_yaml_dict(config), workers=0) as collector:
        rollouts = collector.play([(11, 1.0), (12, 1.0), (13, 1.0)])
    data = Demonstrations()
    data.add(rollouts, 0)
    (tmp_path / "d.npz").write_bytes(data.to_npz())
    back = Demonstrations.load(tmp_path / "d.npz")
    for a, b in zip(data.rollouts, back.rollouts):
        assert dataclasses.asdict(a).keys() == dataclasses.asdict(b).keys()
        for field, value in dataclasses.asdict(a).items():
            np.testing.assert_array_equal(value, dataclasses.asdict(b)[field], err_msg=field)

    from agents.imitation.dagger import EnvSpec, _spec_fields
    from agents.training.envs import make_env_from

    env = make_env_from(config)
    monkeypatch.chdir(tmp_path)  # a run directory is given relative to the working folder, as runs/imitation/...
    try:
        folder = write_minari(rollouts, Path("runs") / "dataset", EnvSpec(**_spec_fields(env, config)),
                              env.observation_space, env.action_space, description="three test episodes")
    finally:
        env.close()
    dataset = load_minari(folder)
    assert dataset.total_episodes == 3 and dataset.total_steps == sum(r.steps for r in rollouts)
    for episode, r in zip(dataset.iterate_episodes(), rollouts):
        np.testing.assert_array_equal(episode.observations, r.observations)
        np.testing.assert_array_equal(episode.actions, r.actions)
        np.testing.assert_allclose(episode.rewards, r.rewards)
        np.testing.assert_array_equal(episode.infos["label"], np.concatenate([r.labels, [-1]]))
        assert bool(episode.terminations[-1]) == r.terminated and bool(episode.truncations[-1]) == r.truncated
    recovered = dataset.recover_environment()  # the task as the episodes saw it, options included
    try:
        obs, _ = recovered.reset(seed=11)
        np.testing.assert_allclose(obs, rollouts[0].observations[0], atol=1e-5)
    finally:
        recovered.close()


def test_an_imitation_run_ends_with_its_students_test_phase(tmp_path):
    student = tmp_path / "student.yaml"
    student.write_text(f"base: {ROOT / 'configs/procedural/generalist.yaml'}\n"
                       "env:\n  task_kwargs: {difficulty: easy, split: train, way: true, turn_forward_step: 0.0}\n"
                       "dqn: {hidden_sizes: [32]}\n"
                       "test: {eval_episodes: 2, eval_picture: false, eval_task_kwargs: {split: test},\n"
                       "       also_test_on: [study_world=5.3]}\n")
    run_dir = train(settings(student, tmp_path / "runs", teacher_episodes=2, epochs=2))
    rows, _ = read_run(run_dir)  # the run's own test and the one in tests/, as rows of the run table
    assert sorted(r["tested_on"] for r in rows) == ["split=test", "study_world=5.3"]
    assert all(r["test_episodes"] == 2 and r["episodes_done"] == 2 for r in rows)


def test_bad_settings_end_with_one_line_and_write_nothing(student, tmp_path):
    runs = tmp_path / "runs"
    result = subprocess.run([sys.executable, "-m", "agents.imitation", "--student", str(student), "--rounds", "-1",
                             "--beta-decay", "1.5", "--runs-dir", str(runs)], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode != 0
    assert "rounds must be an integer >= 0" in result.stderr and "beta_decay must be a number in [0.0, 1.0]" in result.stderr
    assert not runs.exists()


def test_episodes_seen_again_through_other_sensors_keep_their_states(student):
    from agents.imitation.reobserve import reobserve

    config = load_yaml(student)
    with Collector(to_yaml_dict(config), workers=0) as collector:
        rollouts = collector.play([(21, 1.0), (22, 1.0)])
    more = dataclasses.replace(config, env=dataclasses.replace(
        config.env, task_kwargs={**config.env.task_kwargs, "laser_rays": 64, "way": False}))
    seen = reobserve(rollouts, more)
    for a, b in zip(rollouts, seen):
        assert b.observations.shape == (a.steps + 1, 64 + 3 + 20)
        # ray 4k of 64 points where ray k of 16 does (360 k / n degrees from straight ahead): the same wall
        np.testing.assert_allclose(b.observations[:, :64:4], a.observations[:, :16], atol=1e-4)
        np.testing.assert_allclose(b.observations[:, 64:67], a.observations[:, 16:19], atol=1e-5)  # the target
        np.testing.assert_allclose(b.observations[:, 67:], a.observations[:, 22:], atol=1e-5)  # the boxes
        np.testing.assert_array_equal(b.labels, a.labels)
    broken = dataclasses.replace(rollouts[0], actions=rollouts[0].actions[:-1], labels=rollouts[0].labels[:-1],
                                 rewards=rollouts[0].rewards[:-1])
    with pytest.raises(ValueError, match="does not replay"):
        reobserve([broken], more)


def test_a_student_with_memory_learns_from_whole_episodes_and_drives_with_it(tmp_path):
    student = tmp_path / "gru.yaml"
    student.write_text(f"base: {ROOT / 'configs/procedural/generalist.yaml'}\n"
                       "env:\n  task_kwargs: {difficulty: easy, split: train, way: true, turn_forward_step: 0.0}\n"
                       "dqn: {recurrent: gru, hidden_sizes: [64], recurrent_size: 64}\n"
                       "test: {eval_after_training: false}\n")
    cfg = settings(student, tmp_path / "runs", teacher_episodes=6, rounds=1, round_episodes=4, epochs=30,
                   validation_every=0)  # every episode fitted: the accuracy is the fit's
    run_dir = train(cfg)
    rows = (run_dir / ROUNDS_FILE).read_text().splitlines()[1:]
    assert float(rows[-1].split(",")[9]) > 0.8  # train accuracy over the unrolled episodes
    data = Demonstrations.load(run_dir / DATA_FILE)
    assert any((r.actions != r.labels).any() for r in data.rollouts[6:])  # round 1: the GRU student drove
    summary = evaluate(run_dir, episodes=5, seed=5000, picture=False, out_dir=tmp_path / "test", verbose=False)
    assert summary["episodes"] == 5  # the test phase drives it, its hidden state carried and reset


def test_a_fit_keeps_the_epoch_that_agrees_best_with_held_out_labels():
    import torch

    from agents.imitation.fit import accuracy, fit

    rng = np.random.default_rng(0)
    x = rng.normal(size=(400, 4)).astype(np.float32)
    labels = (x[:, 0] > 0).astype(np.int64)
    noisy = np.where(rng.random(400) < 0.4, rng.integers(0, 3, 400), labels)  # 40% of the fitted labels at random
    held_x = rng.normal(size=(300, 4)).astype(np.float32)
    held = (held_x[:, 0] > 0).astype(np.int64)
    scores = []
    torch.manual_seed(0)
    net = torch.nn.Sequential(torch.nn.Linear(4, 256), torch.nn.ReLU(), torch.nn.Linear(256, 3))
    report = fit(net, x, noisy, 60, 32, 0.01, np.random.default_rng(1), (held_x, held),
                 on_epoch=lambda _: scores.append(accuracy(net, held_x, held)))
    assert report.validation_accuracy == pytest.approx(max(scores))  # the best epoch's score ...
    assert accuracy(net, held_x, held) == pytest.approx(max(scores))  # ... and its weights, restored
    assert report.best_epoch == int(np.argmax(scores)) + 1 and report.best_epoch < 60


def test_a_fresh_fit_is_a_new_network_fitted_to_every_label(student, tmp_path):
    import torch

    from agents.core.policy import build_q_network
    from agents.imitation.dagger import _split
    from agents.imitation.fit import fit_rollouts
    from agents.training import checkpoint as ckpt
    from agents.training.envs import make_env_from
    from agents.training.experience import make_features

    cfg = settings(student, tmp_path / "runs", teacher_episodes=4, rounds=1, round_episodes=3, epochs=3,
                   fresh_fit=True, validation_every=3)
    run_dir = train(cfg)
    config = load_yaml(run_dir / "config.yaml")
    env = make_env_from(config)
    try:
        features = make_features(env, config)
        net = build_q_network(config, features.input_specs, 3)  # round 1's student, made by hand
        fitted, held = _split(Demonstrations.load(run_dir / DATA_FILE), 3)
        fit_rollouts(net, features, fitted, held, 3, cfg.batch_size, cfg.learning_rate, np.random.default_rng([1, 1]))
    finally:
        env.close()
    saved = ckpt.load(run_dir, memory=False)["learner"]["q"]
    for name, value in net.state_dict().items():
        torch.testing.assert_close(saved[name], value)
