"""The run table (agents.study.table): a run directory as a row, adding without duplicates, the files' bytes."""

import gzip
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from agents.study.run_record import BLOCK, config_hash, episodes_to_converge, parse_curve, read_run
from agents.study.table import EPISODE_COLUMNS, EPISODES, RUN_COLUMNS, RUNS, add_runs, main, read_table

CONFIG = """task: DynNav-MovingTarget-v1
name: {name}
seed: {seed}
episodes: {episodes}
env:
  reward_mode: distance
  reward_params: {{distance_gamma: {gamma}}}
dqn:
  gamma: 0.97
test:
  eval_after_training: {after}
  eval_episodes: 4
run:
  runs_dir: {runs_dir}
"""
OUTCOMES = ["success", "success", "collision", "timeout"]


def make_run(parent: Path, name: str = "5.2", seed: int = 1, episodes: int = 120, gamma: float = 0.2,
             success_from: int = 60, test: bool = True, after: str = "false") -> Path:
    """A finished run directory as agents.dqn writes it: ``episodes`` training episodes that fail
    until ``success_from`` and succeed after, and a 4-episode test (2 successes)."""
    run = parent / f"DynNav-MovingTarget-v1__{name}__{seed}__20260101-000000"
    run.mkdir(parents=True)
    (run / "config.yaml").write_text(CONFIG.format(name=name, seed=seed, episodes=episodes, gamma=gamma,
                                                   after=after, runs_dir=parent))
    lines = ["episode,global_step,return,length,success,collision,timeout,loss,epsilon,learning_rate,"
             "steps_per_s,wall_time_s"]
    for i in range(episodes):
        won = int(i >= success_from)
        loss = "" if i < 10 else f"{1.0 / (i + 1):.6f}"
        lines.append(f"{i},{(i + 1) * 50},{float(i)},50,{won},{1 - won},0,{loss},0.5,0.001,100.0,{(i + 1) * 0.5}")
    (run / "metrics.csv").write_text("\n".join(lines) + "\n")
    if test:
        eps = [dict(seed=1000000 + k, outcome=o, steps=30 + k, ret=-1.5 * k, spl=0.8 if o == "success" else 0.0,
                    trajectory=[[0.0, 0.0]]) for k, o in enumerate(OUTCOMES)]
        summary = dict(episodes=4, epsilon=0.0, success_rate=0.5, collision_rate=0.25, timeout_rate=0.25,
                       avg_steps_success=30.5, avg_return=-2.25, spl=0.4)
        (run / "eval.json").write_text(json.dumps(dict(task="DynNav-MovingTarget-v1", summary=summary, episodes=eps)))
        (run / "sweep_run.json").write_text(json.dumps(dict(experiment=name, seed=seed, eval_s=2.25)))
    return run


def add_test(run: Path, tested_on: str, outcomes: list[str]) -> None:
    """A test of the run with other task options as agents.training.test_phase writes it:
    tests/<tested_on>/eval.json, each episode recording its world (world seed 500 + k, arena
    side 16 + k m, 8 + k moving obstacles for episode k)."""
    folder = run / "tests" / tested_on
    folder.mkdir(parents=True)
    eps = [dict(seed=1000000 + k, outcome=o, steps=40 + k, ret=-1.0 * k, spl=0.5 if o == "success" else 0.0,
                world_seed=500 + k, arena_side=16.0 + k, moving_obstacles=8 + k, trajectory=[[0.0, 0.0]])
           for k, o in enumerate(outcomes)]
    share = {o: outcomes.count(o) / len(outcomes) for o in ("success", "collision", "timeout")}
    summary = dict(episodes=len(outcomes), epsilon=0.0, success_rate=share["success"],
                   collision_rate=share["collision"], timeout_rate=share["timeout"], avg_steps_success=41.0,
                   avg_return=-1.0, spl=0.1)
    (folder / "eval.json").write_text(json.dumps(dict(task="DynNav-MovingTarget-v1", task_kwargs={},
                                                      tested_on=tested_on, summary=summary, episodes=eps)))


def test_a_run_directory_becomes_one_row_and_its_test_episodes(tmp_path):
    run = make_run(tmp_path, episodes=120, success_from=60)
    rows, episodes = read_run(run, commit="abc")
    (row,) = rows  # no tests/ folder: the run's own test only
    assert set(row) == set(RUN_COLUMNS)
    assert set(episodes[0]) == set(EPISODE_COLUMNS)
    assert (row["experiment"], row["seed"], row["task"], row["commit"]) == ("5.2", 1, "DynNav-MovingTarget-v1", "abc")
    # an eval.json written before tests had options: the run's own task, no world facts
    assert row["tested_on"] == "" and {e["tested_on"] for e in episodes} == {""}
    assert all(e["world_seed"] is None and e["arena_side"] is None for e in episodes)
    assert row["run"] == run.name
    assert (row["success_rate"], row["collision_rate"], row["timeout_rate"], row["test_episodes"]) == (0.5, 0.25, 0.25, 4)
    assert (row["episodes_planned"], row["episodes_done"], row["curve_block"]) == (120, 120, BLOCK)
    # training time is metrics.csv's last wall_time_s (60.0), the test time comes from sweep_run.json
    assert (row["train_s"], row["eval_s"], row["wall_clock_s"]) == (60.0, 2.2, 62.2)
    # 0% for 60 episodes then 100%: the final 100-episode rate is 60%, 90% of it (54%) is reached at episode 114
    assert row["converge_episode"] == episodes_to_converge(np.r_[np.zeros(60), np.ones(60)]) == 114
    success = parse_curve(row["curve_success"])
    assert success.tolist() == [0.0, 0.8, 1.0]  # blocks 0-49, 50-99 (40 of 50 won), 100-119
    ret = parse_curve(row["curve_return"])
    assert ret.tolist() == pytest.approx([24.5, 74.5, 109.5])
    loss = parse_curve(row["curve_loss"])
    assert loss[0] == pytest.approx(np.mean([1.0 / (i + 1) for i in range(10, 50)]), rel=1e-3)  # no loss before 10
    assert [e["outcome"] for e in episodes] == OUTCOMES and [e["episode"] for e in episodes] == [0, 1, 2, 3]
    assert episodes[3]["episode_seed"] == 1000003 and episodes[2]["episode_return"] == -3.0


def test_the_config_hash_ignores_where_and_with_which_seed_a_run_was_made():
    base = dict(task="T", name="a", seed=1, episodes=10, env=dict(reward_mode="distance"),
                test=dict(eval_after_training=True, eval_episodes=100, eval_out=None), run=dict(runs_dir="/x"))
    moved = dict(base, name="b", seed=7, run=dict(runs_dir="/elsewhere", device="cpu"),
                 test=dict(eval_after_training=False, eval_episodes=100, eval_out="/y"))
    assert config_hash(base) == config_hash(moved) and len(config_hash(base)) == 12
    assert config_hash(dict(base, episodes=11)) != config_hash(base)
    assert config_hash(dict(base, test=dict(base["test"], eval_episodes=50))) != config_hash(base)
    # which tests were asked for is each row's tested_on, and a description says nothing trained
    tested = dict(base, description="one more line", test=dict(base["test"], eval_task_kwargs={"split": "test"},
                                                                 also_test_on=["split=ood"]))
    assert config_hash(tested) == config_hash(base)


def test_a_test_with_other_task_options_is_a_row_of_its_own(tmp_path, capsys):
    run = make_run(tmp_path)
    add_test(run, "split=ood", ["collision", "success", "timeout", "collision"])
    rows, episodes = read_run(run)
    assert [r["tested_on"] for r in rows] == ["", "split=ood"]
    home, ood = rows
    for column in ("experiment", "config_hash", "seed", "task", "run", "episodes_done", "converge_episode",
                   "curve_success", "train_s"):  # one run, one training
        assert home[column] == ood[column]
    assert (home["success_rate"], home["collision_rate"], home["test_episodes"]) == (0.5, 0.25, 4)
    assert (ood["success_rate"], ood["collision_rate"], ood["timeout_rate"]) == (0.25, 0.5, 0.25)
    assert ood["test_episodes"] == 4
    tested = [e for e in episodes if e["tested_on"] == "split=ood"]
    assert [e["outcome"] for e in tested] == ["collision", "success", "timeout", "collision"]
    assert [(e["world_seed"], e["arena_side"], e["moving_obstacles"]) for e in tested] == [
        (500 + k, 16.0 + k, 8 + k) for k in range(4)]
    assert len(episodes) == 8

    table = tmp_path / "table"
    assert add_runs(table, [run]) == dict(added=2, replaced=0, kept=0, runs=2)
    assert add_runs(table, [run]) == dict(added=0, replaced=2, kept=0, runs=2)  # again: no duplicates
    assert [(r["tested_on"], r["success_rate"]) for r in read_table(table)] == [("", 0.5), ("split=ood", 0.25)]
    stored = read_table(table, episodes=True)
    assert len(stored) == 8
    assert [(e["episode"], e["world_seed"], e["arena_side"], e["moving_obstacles"]) for e in stored
            if e["tested_on"] == "split=ood"] == [(k, 500 + k, 16.0 + k, 8 + k) for k in range(4)]
    capsys.readouterr()
    main(["show", "--table", str(table)])  # the two tests are listed apart
    assert capsys.readouterr().out == ("5.2: 1 run(s), test success 50.0%\n"
                                       "5.2 (tested on split=ood): 1 run(s), test success 25.0%\n")


def test_the_runs_own_test_wins_over_a_tests_folder_with_the_same_options(tmp_path):
    run = make_run(tmp_path)
    record = json.loads((run / "eval.json").read_text())
    (run / "eval.json").write_text(json.dumps(dict(record, task_kwargs={"split": "test"}, tested_on="split=test")))
    add_test(run, "split=test", ["timeout"] * 4)  # the same test run again with --eval
    rows, episodes = read_run(run)
    assert [(r["tested_on"], r["success_rate"]) for r in rows] == [("split=test", 0.5)]
    assert [e["outcome"] for e in episodes] == OUTCOMES


def test_keeping_the_rows_adds_only_the_tests_the_table_lacks(tmp_path, capsys):
    run = make_run(tmp_path)
    table = tmp_path / "table"
    add_runs(table, [run])
    own_episodes = read_table(table, episodes=True)
    # later: the run's test phase was run again (other numbers), and a test in other worlds was added
    record = json.loads((run / "eval.json").read_text())
    record["summary"]["success_rate"] = 0.75
    record["episodes"][2]["outcome"] = "success"
    (run / "eval.json").write_text(json.dumps(record))
    add_test(run, "split=ood", ["success", "timeout", "timeout", "timeout"])
    assert add_runs(table, [run], replace=False) == dict(added=1, replaced=0, kept=1, runs=2)
    home, ood = read_table(table)
    assert (home["tested_on"], home["success_rate"]) == ("", 0.5)  # the row it had
    assert (ood["tested_on"], ood["success_rate"]) == ("split=ood", 0.25)
    episodes = read_table(table, episodes=True)
    assert [e for e in episodes if not e["tested_on"]] == own_episodes
    assert [e["outcome"] for e in episodes if e["tested_on"]] == ["success", "timeout", "timeout", "timeout"]
    # the command line's --keep: nothing is missing now, nothing changes
    files = {name: (table / name).read_bytes() for name in (RUNS, EPISODES)}
    capsys.readouterr()
    main(["add", str(run), "--table", str(table), "--keep"])
    assert "0 run(s) added, 0 replaced, 2 kept as they were, 2 in the table" in capsys.readouterr().out
    assert {name: (table / name).read_bytes() for name in (RUNS, EPISODES)} == files


def test_adding_a_run_again_replaces_its_row_and_the_files_are_deterministic(tmp_path):
    runs = [make_run(tmp_path / "sweep" / f"seed{s}", seed=s) for s in (2, 10, 1)]
    table = tmp_path / "table"
    assert add_runs(table, runs[:2]) == dict(added=2, replaced=0, kept=0, runs=2)
    assert add_runs(table, runs) == dict(added=1, replaced=2, kept=0, runs=3)
    rows = read_table(table)
    assert [r["seed"] for r in rows] == [1, 2, 10]  # sorted by key, 2 before 10
    assert len(read_table(table, episodes=True)) == 3 * 4
    first = (table / RUNS).read_bytes()
    assert first[4:8] == b"\0\0\0\0"  # gzip mtime 0
    # a sweep finding a finished run leaves the row it has
    assert add_runs(table, runs[:1], replace=False) == dict(added=0, replaced=0, kept=1, runs=3)
    assert (table / RUNS).read_bytes() == first
    # the same rows added in another order make the same bytes
    other = tmp_path / "other"
    add_runs(other, runs[::-1])
    assert (other / RUNS).read_bytes() == first and (other / EPISODES).read_bytes() == (table / EPISODES).read_bytes()


def test_a_run_continued_with_a_longer_config_replaces_its_earlier_row(tmp_path):
    run = make_run(tmp_path / "seed1", episodes=100)
    add_runs(tmp_path / "table", [run])
    (run / "config.yaml").write_text((run / "config.yaml").read_text().replace("episodes: 100", "episodes: 150"))
    assert add_runs(tmp_path / "table", [run]) == dict(added=0, replaced=1, kept=0, runs=1)
    (row,) = read_table(tmp_path / "table")
    assert row["episodes_planned"] == 150
    assert len(read_table(tmp_path / "table", episodes=True)) == 4


def test_nothing_is_written_when_one_of_the_runs_is_not_finished(tmp_path):
    done = make_run(tmp_path / "a", seed=1)
    unfinished = make_run(tmp_path / "b", seed=2, test=False)
    with pytest.raises(ValueError, match=r"not a finished run directory: no eval\.json .*--eval"):
        add_runs(tmp_path / "table", [done, unfinished])
    with pytest.raises(ValueError, match="no such folder"):
        add_runs(tmp_path / "table", [done, tmp_path / "missing"])
    with pytest.raises(ValueError, match="same run"):
        add_runs(tmp_path / "table", [done, done])
    assert not (tmp_path / "table").exists()


def test_a_file_that_is_not_a_table_is_refused(tmp_path):
    (tmp_path / RUNS).write_bytes(gzip.compress(b"a,b\n1,2\n"))
    with pytest.raises(ValueError, match="is not a run table"):
        read_table(tmp_path)
    (tmp_path / RUNS).write_text("plain text")
    with pytest.raises(ValueError, match="is not a run table"):
        read_table(tmp_path)
    assert read_table(tmp_path / "empty") == []


def test_a_table_written_before_the_social_columns_reads_with_them_empty(tmp_path):
    """The committed results table predates the social metrics: its rows read back (those
    columns None) and the next write keeps them and adds the columns."""
    from agents.study.table import encode

    run = make_run(tmp_path / "runs")
    rows, episodes = read_run(run, commit="abc")
    old = dict(list(RUN_COLUMNS.items())[:list(RUN_COLUMNS).index("human_collision_rate")])  # the columns before
    table = tmp_path / "table"
    table.mkdir()
    (table / RUNS).write_bytes(encode([{c: r[c] for c in old} for r in rows], old))
    (table / EPISODES).write_bytes(encode(episodes, EPISODE_COLUMNS))
    (back,) = read_table(table)
    assert back["success_rate"] == 0.5 and back["discomfort_frequency"] is None and back["jerk"] is None
    other = make_run(tmp_path / "more", name="other")
    add_runs(table, [other])
    header = gzip.decompress((table / RUNS).read_bytes()).decode().splitlines()[0]
    assert header.split(",") == list(RUN_COLUMNS) and len(read_table(table)) == 2


def test_a_crowd_tests_social_metrics_are_columns_of_its_row(tmp_path):
    run = make_run(tmp_path)
    ev = json.loads((run / "eval.json").read_text())
    ev["summary"]["social"] = dict(human_collision_rate=0.25, min_human_distance=0.31, personal_space_compliance=0.9,
                                   discomfort_frequency=0.04, time_to_goal=9.5, path_length=8.2,
                                   path_irregularity=0.12, jerk=4.0)
    (run / "eval.json").write_text(json.dumps(ev))
    (row,) = read_run(run)[0]
    assert (row["human_collision_rate"], row["discomfort_frequency"], row["time_to_goal"]) == (0.25, 0.04, 9.5)
    assert (row["min_human_distance"], row["personal_space_compliance"], row["jerk"]) == (0.31, 0.9, 4.0)
    add_runs(tmp_path / "table", [run])
    assert read_table(tmp_path / "table")[0]["discomfort_frequency"] == 0.04


def test_the_command_line_adds_runs_under_a_name_and_shows_them(tmp_path, capsys):
    runs = [make_run(tmp_path / f"seed{s}", name="mine", seed=s) for s in (1, 2)]
    table = str(tmp_path / "table")
    main(["add", *map(str, runs), "--experiment", "5.3-mine", "--table", table])
    assert "2 run(s) added, 0 replaced, 2 in the table" in capsys.readouterr().out
    main(["show", "--table", table])
    assert capsys.readouterr().out == "5.3-mine: 2 run(s), test success 50.0%\n"
    with pytest.raises(SystemExit, match="error: .*no such folder"):
        main(["add", str(tmp_path / "nothing"), "--table", table])


def _git(cwd: Path, *args: str) -> str:
    return subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args], cwd=cwd, check=True,
                          capture_output=True, text=True).stdout.strip()


def test_a_committed_run_gets_the_commit_that_added_it(tmp_path):
    repo = tmp_path / "repo"
    repo.mkdir()
    _git(repo, "init", "-q")
    old = make_run(repo / "results" / "seed1", seed=1)
    _git(repo, "add", ".")
    _git(repo, "commit", "-q", "-m", "run 1")
    added = _git(repo, "rev-parse", "HEAD")
    (repo / "notes.txt").write_text("later")
    _git(repo, "add", ".")
    _git(repo, "commit", "-q", "-m", "later")
    new = make_run(repo / "results" / "seed2", seed=2)  # not committed: the code's own commit
    add_runs(tmp_path / "table", [old, new])
    rows = {r["seed"]: r["commit"] for r in read_table(tmp_path / "table")}
    assert rows[1] == added
    here = subprocess.run(["git", "rev-parse", "HEAD"], cwd=Path(__file__).parent, capture_output=True, text=True)
    assert rows[2] == (here.stdout.strip() if here.returncode == 0 else "")
