"""Tests with other task options: the ``key=value,...`` text (dynnav_tasks.task_options), the test
settings eval_task_kwargs / also_test_on (config, command line), and a real run tested on the
procedural test and ood worlds, its tests in tests/<options>/ and in the run table."""

import json
from pathlib import Path

import pytest

from agents.dqn import main
from agents.study.run_record import read_run
from agents.study.table import add_runs, read_table
from agents.training.config_io import make, parse_args
from agents.training.loop import train
from agents.training.test_phase import evaluate, evaluate_as_configured
from dynnav_tasks import generation
from dynnav_tasks.task_options import options_name, parse_task_options

ROOT = Path(__file__).resolve().parents[1]
TEST = "difficulty=easy,split=test"
OOD = "difficulty=easy,split=ood"


# ---------------------------------------------------------------------------------------- the text
def test_task_options_read_as_numbers_flags_and_words_and_name_back():
    options = parse_task_options("obstacle_count=4, obstacle_speed_scale=1.5,split=ood,camera=true,scale=0.05")
    assert options == dict(obstacle_count=4, obstacle_speed_scale=1.5, split="ood", camera=True, scale=0.05)
    assert [type(options[k]) for k in ("obstacle_count", "obstacle_speed_scale", "split", "camera")] == [
        int, float, str, bool]
    name = options_name(options)
    assert name == "camera=true,obstacle_count=4,obstacle_speed_scale=1.5,scale=0.05,split=ood"  # keys sorted
    assert parse_task_options(name) == options
    assert options_name(dict(split="ood", difficulty="easy")) == OOD  # one name whatever the order
    assert options_name(dict(flag=False)) == "flag=false" and parse_task_options("flag=false") == dict(flag=False)
    assert options_name({}) == ""
    # no YAML 1.1 surprises: words stay words, and floats name back as floats
    assert parse_task_options("split=no,mode=null,turn=on") == dict(split="no", mode="null", turn="on")
    assert parse_task_options(options_name(dict(noise=1e-05, big=1e20))) == dict(noise=1e-05, big=1e20)


@pytest.mark.parametrize("text, problem", [
    ("split", "key=value"),              # no '='
    ("=ood", "key=value"),               # empty key
    ("split=", "key=value"),             # empty value
    ("split=ood,", "key=value"),         # an empty part
    ("split=ood,split=test", "split twice"),
    ("sizes=[1]", "the value of sizes must be a number, true/false or a word"),
    ("world={a: 1}", "the value of world must be"),
    ("split=a b", "the value of split must be"),
])
def test_malformed_task_options_are_refused_naming_the_text(text, problem):
    with pytest.raises(ValueError) as err:
        parse_task_options(text)
    assert repr(text) in str(err.value) and problem in str(err.value)


# ---------------------------------------------------------------------------------------- config and command line
def test_a_bad_also_test_on_entry_is_refused_by_the_config():
    assert make(also_test_on=("split=ood", "obstacle_count=4,obstacle_speed_scale=1.5")).validate()
    with pytest.raises(ValueError, match="'split=ood,obstacle_count'"):
        make(also_test_on=("split=ood", "split=ood,obstacle_count")).validate()
    with pytest.raises(ValueError, match="'split:ood'"):
        parse_args(["--task", "DynNav-Procedural-v1", "--also-test-on", "split:ood"])


def test_eval_takes_the_test_options_from_the_command_line_and_nothing_else():
    # the checkpoint is only opened when the test runs, not when the flags are read
    config = parse_args(["--eval", "--checkpoint", "no/such/run", "--eval-task-kwargs", "split", "ood",
                         "obstacle_count", "4", "--also-test-on", OOD, "split=train"])
    assert config.eval and config.checkpoint == "no/such/run"
    assert config.test.eval_task_kwargs == dict(split="ood", obstacle_count=4)
    assert type(config.test.eval_task_kwargs["obstacle_count"]) is int
    assert config.test.also_test_on == (OOD, "split=train")
    with pytest.raises(ValueError, match="--learning-rate cannot change them"):
        parse_args(["--eval", "--checkpoint", "x", "--learning-rate", "0.1"])
    with pytest.raises(ValueError, match="--task-kwargs cannot change them"):
        parse_args(["--eval", "--checkpoint", "x", "--task-kwargs", "split", "ood"])


def test_eval_task_kwargs_on_the_command_line_are_laid_over_the_config_files():
    config = parse_args(["--config", str(ROOT / "configs/procedural/procedural-easy.yaml"),
                         "--eval-task-kwargs", "split", "ood"])
    assert config.test.eval_task_kwargs == dict(difficulty="easy", split="ood")
    assert config.test.also_test_on == ("difficulty=easy,split=train", OOD)


# ---------------------------------------------------------------------------------------- a real run
def tiny_procedural_run(tmp_path: Path):
    """(config, run directory): 2 episodes on the easy train worlds without a single update,
    tested on 3 episodes of the held-out test worlds and, after that, 3 of the ood worlds."""
    config = make(task="DynNav-Procedural-v1", task_kwargs=dict(difficulty="easy"), episodes=2, seed=1,
                  learning_starts=100_000, batch_size=16, buffer_size=1000, hidden_sizes=(16,), checkpoint_every=2,
                  runs_dir=str(tmp_path / "runs"), progress=False, eval_after_training=False, eval_episodes=3,
                  eval_picture=False, eval_task_kwargs=dict(difficulty="easy", split="test"),
                  also_test_on=(OOD,)).validate()
    return config, train(config)


def files_of(folder: Path) -> dict[str, tuple[int, bytes]]:
    return {str(p.relative_to(folder)): (p.stat().st_mtime_ns, p.read_bytes())
            for p in sorted(folder.rglob("*")) if p.is_file()}


def test_a_run_is_tested_on_held_out_and_ood_worlds_and_each_test_is_a_table_row(tmp_path, capsys):
    config, run = tiny_procedural_run(tmp_path)
    evaluate_as_configured(config, run, verbose=False)

    own = json.loads((run / "eval.json").read_text())
    assert own["tested_on"] == TEST and own["task_kwargs"] == dict(difficulty="easy", split="test")
    held_out = set(generation.test_world_seeds("easy"))
    assert len(own["episodes"]) == 3 and all(e["world_seed"] in held_out for e in own["episodes"])
    assert all(6.0 <= e["arena_side"] <= 8.0 and 0 <= e["moving_obstacles"] <= 3 for e in own["episodes"])
    ood = json.loads((run / "tests" / OOD / "eval.json").read_text())
    assert ood["tested_on"] == OOD and len(ood["episodes"]) == 3
    # the easy ood spec (dynnav_tasks/generation/presets.py): 14-20 m arenas, 6-12 moving obstacles
    assert all(e["arena_side"] >= 14.0 and 6 <= e["moving_obstacles"] <= 12 for e in ood["episodes"])

    # a sweep finding the finished run runs only the tests it lacks: here none
    before = files_of(run)
    evaluate_as_configured(config, run, verbose=False, only_missing=True)
    assert files_of(run) == before

    table = tmp_path / "table"
    assert add_runs(table, [run]) == dict(added=2, replaced=0, kept=0, runs=2)
    rows = read_table(table)
    assert [r["tested_on"] for r in rows] == [OOD, TEST]
    assert [r["test_episodes"] for r in rows] == [3, 3] and rows[0]["config_hash"] == rows[1]["config_hash"]
    episodes = read_table(table, episodes=True)
    assert len(episodes) == 6
    assert [e["world_seed"] for e in episodes if e["tested_on"] == TEST] == [e["world_seed"] for e in own["episodes"]]
    assert all(e["arena_side"] >= 14.0 for e in episodes if e["tested_on"] == OOD)
    assert all(e["moving_obstacles"] is not None for e in episodes)

    # --eval with other options: a test of its own in tests/<options>/, the run's own test untouched
    main(["--eval", "--checkpoint", str(run), "--eval-episodes", "2", "--no-eval-picture",
          "--eval-task-kwargs", "difficulty", "easy", "split", "train"])
    assert "difficulty=easy,split=train" in capsys.readouterr().out
    assert files_of(run)["eval.json"] == before["eval.json"]
    train_test = json.loads((run / "tests" / "difficulty=easy,split=train" / "eval.json").read_text())
    assert train_test["tested_on"] == "difficulty=easy,split=train" and len(train_test["episodes"]) == 2
    assert not {e["world_seed"] for e in train_test["episodes"]} & held_out
    assert add_runs(table, [run], replace=False) == dict(added=1, replaced=0, kept=2, runs=3)


def test_every_test_an_eval_command_makes_is_read_into_the_table(tmp_path):
    _, run = tiny_procedural_run(tmp_path)
    evaluate(run, episodes=1, picture=False, verbose=False)  # the run's own test (the table needs it)
    main(["--eval", "--checkpoint", str(run), "--eval-episodes", "2", "--no-eval-picture",
          "--eval-task-kwargs", "difficulty", "easy", "split", "train", "--also-test-on", OOD])
    assert len(list(run.rglob("eval.json"))) == 3
    rows, _ = read_run(run)
    assert sorted(r["tested_on"] for r in rows) == sorted(["", "difficulty=easy,split=train", OOD])
