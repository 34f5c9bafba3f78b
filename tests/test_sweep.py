"""Sweeps on local Ray (agents.study.sweep), the run table they fill and the report made from it, with tiny runs."""

import json
import shutil
from pathlib import Path

import pytest
import ray

from agents.study.report import write_report
from agents.study.sweep import SUMMARY, find_run_dir, plan, run_sweep
from agents.study.table import read_table

TINY = """task: DynNav-MovingTarget-v1
reward_mode: distance
reward_params: {{distance_gamma: {gamma}}}
episodes: {episodes}
hidden_sizes: [16]
batch_size: 16
learning_starts: 50
checkpoint_every: 2
eval_episodes: 3
eval_picture: false
"""

# Named like two experiments of the study's Fig. 6.7 so that the report draws that figure.
A, B = "5.2-g0.1", "5.2-g0.3"


@pytest.fixture(scope="module")
def local_ray():
    ray.init(address="local", num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


@pytest.fixture(scope="module")
def sweep(tmp_path_factory, local_ray):
    """A finished two-run sweep: (config paths, sweep folder, summary)."""
    root = tmp_path_factory.mktemp("sweep")
    configs = []
    for name, gamma in ((A, 0.1), (B, 0.3)):
        path = root / f"{name}.yaml"
        path.write_text(TINY.format(gamma=gamma, episodes=4))
        configs.append(str(path))
    out = root / "out"
    summary = run_sweep(configs, [1], out, verbose=False)
    return configs, out, summary


def _run_dir(out: Path, experiment: str) -> Path:
    run_dir = find_run_dir(out / experiment / "seed1")
    assert run_dir is not None
    return run_dir


def test_sweep_runs_every_experiment_and_the_report_shows_them(sweep, tmp_path):
    configs, out, summary = sweep
    assert summary["counts"]["done"] == 2 and summary["counts"]["failed"] == 0
    assert json.loads((out / SUMMARY).read_text()) == summary
    rows = {r["experiment"]: r for r in read_table(out)}  # each finished run was added to the sweep's table
    assert sorted(rows) == [A, B]
    for name, gamma in ((A, 0.1), (B, 0.3)):
        run_dir = _run_dir(out, name)
        result = json.loads((run_dir / "eval.json").read_text())
        assert result["trained_episodes"] == 4 and result["summary"]["episodes"] == 3
        assert f"distance_gamma: {gamma}" in (run_dir / "config.yaml").read_text()
        assert len((run_dir / "metrics.csv").read_text().splitlines()) == 1 + 4
        row = rows[name]
        assert (row["seed"], row["run"], row["episodes_done"], row["test_episodes"]) == (1, run_dir.name, 4, 3)
        assert row["success_rate"] == result["summary"]["success_rate"]
        assert len(row["curve_return"].split()) == 1  # 4 episodes: one block
    assert len(read_table(out, episodes=True)) == 2 * 3
    # the report reads the table only: with the run folders gone it shows the same rows
    kept = tmp_path / "kept"
    kept.mkdir()
    for name in ("runs.csv.gz", "episodes.csv.gz"):
        shutil.copy(out / name, kept / name)
    report = write_report(kept, tmp_path / "RESULTS.md")
    text = report.read_text()
    assert "without a run in the table yet: `5.2`" in text  # the study's other experiments
    for name in (A, B):
        row = next(line for line in text.splitlines() if line.startswith(f"| `{name}`"))
        assert f"| 1 | {rows[name]['success_rate']:.0%} (" in row  # one seed, its own rate
    assert (tmp_path / "docs" / "results" / "fig6_7_distance_gamma.png").is_file()
    assert "docs/results/fig6_7_distance_gamma.png" in text


def test_a_sweep_adds_its_runs_to_the_table_it_is_given_once(sweep, tmp_path):
    configs, out, _ = sweep
    table = tmp_path / "table"
    again = run_sweep(configs, [1], out, verbose=False, table=table)  # finished: skipped, but added
    assert [r["status"] for r in again["runs"]] == ["skipped", "skipped"]
    first = (table / "runs.csv.gz").read_bytes()
    assert sorted(r["experiment"] for r in read_table(table)) == [A, B]
    run_sweep(configs, [1], out, verbose=False, table=table)
    assert (table / "runs.csv.gz").read_bytes() == first  # not listed twice, not rewritten
    with pytest.raises(ValueError, match="is a file"):
        run_sweep(configs, [1], out, verbose=False, table=table / "runs.csv.gz")


def test_restarted_sweep_skips_finished_runs_and_resumes_the_others(sweep):
    configs, out, _ = sweep
    run_a, run_b = _run_dir(out, A), _run_dir(out, B)
    b_checkpoint = (run_b / "checkpoint" / "meta.json").stat().st_mtime_ns
    # A: test phase missing and two more episodes wanted -> continued from its checkpoint
    (run_a / "eval.json").unlink()
    Path(configs[0]).write_text(TINY.format(gamma=0.1, episodes=6))
    summary = run_sweep(configs, [1], out, verbose=False)
    status = {r["experiment"]: r["status"] for r in summary["runs"]}
    assert status == {A: "resumed", B: "skipped"}
    assert _run_dir(out, A) == run_a  # the same directory, not a new run
    info = json.loads((run_a / "sweep_run.json").read_text())
    assert info["resumed_at_episode"] == 4
    episodes = [line.split(",")[0] for line in (run_a / "metrics.csv").read_text().splitlines()[1:]]
    assert episodes == [str(i) for i in range(6)]
    assert json.loads((run_a / "eval.json").read_text())["trained_episodes"] == 6
    # its config changed, so did its hash: its row is replaced, not joined by a second one
    rows = {r["experiment"]: r for r in read_table(out)}
    assert len(read_table(out)) == 2 and rows[A]["episodes_done"] == 6 and rows[A]["episodes_planned"] == 6
    assert (run_b / "checkpoint" / "meta.json").stat().st_mtime_ns == b_checkpoint


def test_a_failing_run_is_reported_with_its_error(tmp_path, local_ray):
    bad = tmp_path / "bad_task.yaml"
    bad.write_text(TINY.format(gamma=0.2, episodes=2).replace("DynNav-MovingTarget-v1", "DynNav-NoSuchWorld-v1"))
    summary = run_sweep([str(bad)], [1], tmp_path / "out", max_retries=0, verbose=False)
    (run,) = summary["runs"]
    assert run["status"] == "failed" and "DynNav-NoSuchWorld-v1" in run["error"]
    assert summary["counts"]["failed"] == 1


def test_two_sweeps_on_one_folder_both_stay_in_its_summary(tmp_path, local_ray):
    # one sweep per core on one folder, as agents/study/REPRODUCE.md runs the study
    out = tmp_path / "out"
    configs = []
    for name in (A, B):
        configs.append(tmp_path / f"{name}.yaml")
        configs[-1].write_text(TINY.format(gamma=0.2, episodes=2))
    first = run_sweep([str(configs[0])], [1], out, verbose=False)
    second = run_sweep([str(configs[1])], [1], out, verbose=False)
    assert [r["experiment"] for r in first["runs"]] == [A] and [r["experiment"] for r in second["runs"]] == [B]
    both = json.loads((out / SUMMARY).read_text())
    assert [(r["experiment"], r["status"]) for r in both["runs"]] == [(A, "done"), (B, "done")]
    assert both["counts"]["done"] == 2
    again = run_sweep([str(configs[0])], [1], out, verbose=False)  # a record is replaced, not repeated
    assert [r["status"] for r in again["runs"]] == ["skipped"]
    assert [(r["experiment"], r["status"]) for r in json.loads((out / SUMMARY).read_text())["runs"]] == [
        (A, "skipped"), (B, "done")]


def test_a_wrong_config_is_an_error_before_anything_runs(tmp_path):
    wrong = tmp_path / "typo.yaml"
    wrong.write_text("task: DynNav-MovingTarget-v1\nepisodez: 4\n")
    with pytest.raises(ValueError, match=r"typo\.yaml.*'episodez'.*'episodes'"):
        plan([str(wrong)], [1], tmp_path / "out")
    with pytest.raises(ValueError, match="does not exist"):
        plan([str(tmp_path / "missing.yaml")], [1], tmp_path / "out")
