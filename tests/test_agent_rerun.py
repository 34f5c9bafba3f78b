"""Rerun recordings of training, of the test phase and of a trained policy."""

import pytest

from agents.training.config import Config
from agents.dqn import main, train
from agents.training.test_phase import evaluate
from agents.training.record import Args
from agents.training.record import main as record_main
from test_agent_training import small as small_run
from test_recording import column, read_back


def small(tmp_path, **overrides) -> Config:
    return small_run(tmp_path, **{"episodes": 5, "checkpoint_every": 5, **overrides})


def test_training_records_every_nth_episode_and_the_curves(tmp_path):
    path = tmp_path / "train.rrd"
    run = train(small(tmp_path, rerun=str(path), rerun_every=2))
    lengths = [int(line.split(",")[3]) for line in (run / "metrics.csv").read_text().splitlines()[1:]]
    data = read_back(path)
    episodes = column(data["/world/robot"], "episode")
    assert sorted(set(episodes)) == [0, 2, 4]  # every 2nd episode, the first included
    assert len(episodes) == sum(lengths[e] + 1 for e in (0, 2, 4))
    q_rows = column(data["/agent/q_values"], "BarChart:values")
    assert len(q_rows) == sum(lengths[e] for e in (0, 2, 4))
    # the training curves: one point per episode on the episode timeline
    assert column(data["/training/episode_return"], "episode") == [0, 1, 2, 3, 4]
    assert len(column(data["/training/success_rate"], "episode")) == 5


def test_test_phase_recording(tmp_path):
    run = train(small(tmp_path))
    path = tmp_path / "eval.rrd"
    evaluate(run, episodes=2, picture=False, verbose=False, rerun=path)
    data = read_back(path)
    outcomes = [row[0] for row in column(data["/episode/outcome"], "TextLog:text")]
    assert len(outcomes) == 2 and outcomes[0].startswith("episode 0: ")
    assert "/agent/q_values" in data


def test_record_cli_with_a_checkpoint(tmp_path, capsys):
    run = train(small(tmp_path))
    out = tmp_path / "trained.rrd"
    record_main(Args(checkpoint=run, episodes=1, out=out))
    assert "greedy policy" in capsys.readouterr().out
    data = read_back(out)
    assert len(column(data["/agent/q_values"], "BarChart:values")) == len(column(data["/agent/reward"], "step"))


def test_rerun_errors_are_clear_before_any_work(tmp_path):
    missing = tmp_path / "missing" / "x.rrd"
    with pytest.raises(SystemExit, match="does not exist"):
        main(["--task", "DynNav-MovingTarget-v1", "--episodes", "1", "--rerun", str(missing),
              "--runs-dir", str(tmp_path / "runs")])
    assert not (tmp_path / "runs").exists()  # nothing was started
    with pytest.raises(SystemExit, match="records dynnav tasks"):
        main(["--task", "CartPole-v1", "--episodes", "1", "--rerun", str(tmp_path / "x.rrd"),
              "--runs-dir", str(tmp_path / "runs")])
