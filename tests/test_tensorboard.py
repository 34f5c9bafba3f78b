"""TensorBoard scalars (--tensorboard): the event files a run writes read back as its metrics."""

import csv
import dataclasses
from pathlib import Path

import pytest
from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

from agents.dqn import main
from agents.imitation.config import ImitationConfig
from agents.imitation.dagger import train as imitate

ROOT = Path(__file__).resolve().parents[1]


def scalars(run_dir: Path) -> dict[str, list]:
    events = EventAccumulator(str(run_dir / "tensorboard"))
    events.Reload()
    return {tag: events.Scalars(tag) for tag in events.Tags()["scalars"]}


def test_a_dqn_run_writes_every_episode_as_tensorboard_scalars(tmp_path):
    main(["--task", "CartPole-v1", "--episodes", "6", "--learning-starts", "20", "--batch-size", "8",
          "--runs-dir", str(tmp_path), "--tensorboard", "--no-eval-after-training", "--no-progress"])
    (run_dir,) = tmp_path.iterdir()
    with open(run_dir / "metrics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    points = scalars(run_dir)
    for tag in ("charts/episodic_return", "charts/success", "charts/collision", "charts/epsilon",
                "charts/learning_rate", "charts/SPS", "charts/episodic_length"):
        assert [p.step for p in points[tag]] == [int(r["global_step"]) for r in rows], tag
    assert [p.value for p in points["charts/episodic_return"]] == pytest.approx([float(r["return"]) for r in rows])
    assert [p.value for p in points["charts/epsilon"]] == pytest.approx([float(r["epsilon"]) for r in rows])
    with_loss = [r for r in rows if r["loss"]]
    assert with_loss and [p.value for p in points["losses/td_loss"]] == pytest.approx([float(r["loss"]) for r in with_loss],
                                                                                         rel=1e-5)


def test_an_imitation_run_writes_its_loss_and_dagger_iterations(tmp_path):
    student = tmp_path / "student.yaml"
    student.write_text(f"base: {ROOT / 'configs/procedural/generalist.yaml'}\n"
                       "env:\n  task_kwargs: {difficulty: easy, split: train, way: true, turn_forward_step: 0.0}\n"
                       "dqn: {hidden_sizes: [32]}\ntest: {eval_after_training: false}\n")
    cfg = ImitationConfig(student=str(student), teacher_episodes=2, rounds=1, round_episodes=2, epochs=3, workers=0,
                          runs_dir=str(tmp_path / "runs"), progress=False, dataset=False, tensorboard=True)
    run_dir = imitate(cfg)
    points = scalars(run_dir)
    assert [p.step for p in points["imitation/loss"]] == [1, 2, 3, 4, 5, 6]  # 3 epochs in each of 2 fits
    assert [p.value for p in points["imitation/dagger_iteration"]] == [0.0, 1.0]
    assert [p.value for p in points["imitation/beta"]] == [1.0, 0.5]
    with open(run_dir / "rounds.csv", newline="") as f:
        accuracy = [float(r["train_accuracy"]) for r in csv.DictReader(f)]
    assert [p.value for p in points["imitation/train_accuracy"]] == pytest.approx(accuracy)


def test_asking_for_tensorboard_without_the_package_is_an_error_first(tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "tensorboard" else real(name, *a))
    with pytest.raises(SystemExit, match="dynnav\\[tensorboard\\]"):
        main(["--task", "CartPole-v1", "--episodes", "2", "--runs-dir", str(tmp_path / "runs"), "--tensorboard"])
    assert not (tmp_path / "runs").exists()
    with pytest.raises(ValueError, match="tensorboard"):
        dataclasses.replace(ImitationConfig(), tensorboard=True).validate()
