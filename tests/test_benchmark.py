"""dynnav-benchmark: a callable, a pretrained navigator and an SB3 model scored, the same seeds
giving the same card twice, and every bad input a one-line error before any episode."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from agents.benchmark.cli import Args, main, plan
from agents.benchmark.policies import BenchmarkError, PolicySpec
from agents.benchmark.scoring import run_cells, score
from agents.benchmark.suites import Cell, suite_cells

HERE = Path(__file__).resolve().parent
TASK = "DynNav-OneObstacle-v1"


@pytest.fixture(autouse=True)
def importable(monkeypatch):
    monkeypatch.syspath_prepend(str(HERE))


def test_a_callable_scores_the_same_seeds_the_same_way_twice_in_one_process_or_two(tmp_path):
    cells = [Cell(TASK, {}, episodes=12)]
    policy = PolicySpec("bench_policies:toward_target")
    here = run_cells(policy, cells, workers=0, progress=False)
    again = run_cells(policy, cells, workers=2, progress=False)
    assert here == again and [r["seed"] for r in here[0]] == list(range(1_000_000, 1_000_012))
    s = score(here[0])
    assert s["episodes"] == 12 and s["success"] + s["collision"] + s["timeout"] == pytest.approx(1.0)
    lo, hi = s["success_ci95"]
    assert lo <= s["success"] <= hi
    assert all((r["spl"] > 0) == (r["outcome"] == "success") for r in here[0])
    import bench_policies
    assert bench_policies.calls["reset"] >= 12  # the module's reset() before every episode


def test_the_command_writes_a_card_with_its_command_version_and_references(tmp_path, capsys):
    out = tmp_path / "card.json"
    argv = ["--policy", "bench_policies:toward_target", "--task", TASK, "--episodes", "6", "--workers", "0",
            "--out", str(out), "--no-progress"]
    main(argv)
    card = json.loads(out.read_text())
    assert card["command"] == "dynnav-benchmark " + " ".join(argv) and card["suite"] == TASK
    (cell,) = card["cells"]
    assert cell["episodes"] == 6 and cell["references"]["planner"] is not None  # the planner's ceiling of 5.1
    md = out.with_suffix(".md").read_text()
    assert f"| {TASK} | 6 |" in md and "planner" in md
    main(argv)  # the same seeds: the same card
    assert json.loads(out.read_text()) == card


def test_a_pretrained_navigator_scores_the_same_seeds_identically_twice():
    cells = [Cell("DynNav-MovingObstacles-v1", {}, episodes=6)]
    policy = PolicySpec("pretrained:5.3")
    first = run_cells(policy, cells, workers=0, progress=False)
    assert first == run_cells(policy, cells, workers=2, progress=False)
    assert len(first[0]) == 6 and sum(r["outcome"] == "success" for r in first[0]) >= 5  # its card: 99%


def test_a_stable_baselines3_model_is_scored(tmp_path):
    sb3 = pytest.importorskip("stable_baselines3")
    import dynnav_tasks

    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(TASK, control_mode="diff_drive_vel"))
    model = sb3.PPO("MlpPolicy", env, n_steps=64, batch_size=32, seed=0, device="cpu")
    model.learn(64)
    model.save(tmp_path / "ppo.zip")
    env.close()
    policy = PolicySpec(str(tmp_path / "ppo.zip"), "ppo", dict(control_mode="diff_drive_vel"))
    policy.check()
    (records,) = run_cells(policy, [Cell(TASK, {}, episodes=3)], workers=0, progress=False)
    assert len(records) == 3 and {r["outcome"] for r in records} <= {"success", "collision", "timeout"}
    wrong = PolicySpec(str(tmp_path / "ppo.zip"), "ppo")  # the discrete drive's task reads differently
    with pytest.raises(BenchmarkError, match=r"reads observations of shape \(26,\); DynNav-OneObstacle-v1 gives \(22,\)"):
        run_cells(wrong, [Cell(TASK, {}, episodes=1)], workers=0, progress=False)


def test_a_scripted_controller_scores_as_the_baselines_own_episodes_do():
    """controller:go_to_target under the benchmark's protocol gives each seed the outcome and steps that the
    baselines' episode runner gives it; DWA is opened on the velocity drive it commands."""
    from dynnav_tasks.baselines.go_to_target import run_go_to_target

    seeds = range(1_000_000, 1_000_005)
    (records,) = run_cells(PolicySpec("controller:go_to_target"), [Cell(TASK, {}, episodes=5)], workers=0, progress=False)
    own = run_go_to_target(TASK, seeds).episodes
    assert [(r["outcome"], r["steps"]) for r in records] == [(e.outcome, e.steps) for e in own]
    actor = PolicySpec("controller:dwa").open(TASK, {})
    assert actor.env.action_space.shape == (2,)
    actor.env.close()


@pytest.mark.parametrize("argv, message", [
    (["--policy", "controller:nope", "--suite", "study"], "no scripted controller 'nope'; the controllers: planner"),
    (["--policy", "bench_policies:toward_target", "--suite", "city"], "unknown suite 'city'"),
    (["--policy", "bench_policies:toward_target"], "give either --suite"),
    (["--policy", "nothing_here:act", "--suite", "study"], "cannot import 'nothing_here'"),
    (["--policy", "bench_policies:absent", "--suite", "study"], "has no function 'absent'"),
    (["--policy", "just-a-name", "--suite", "study"], "is not a policy"),
    (["--policy", "pretrained:nope", "--suite", "study"], "no pretrained model 'nope'"),
    (["--policy", "model.zip", "--suite", "study"], "model.zip does not exist"),
    (["--policy", "bench_policies:toward_target", "--task", "DynNav-Nowhere-v1"], "Unknown task id"),
    (["--policy", "bench_policies:toward_target", "--task", TASK, "--episodes", "0"], "--episodes must be 1"),
])
def test_bad_input_is_a_one_line_error_before_any_episode(argv, message, tmp_path):
    with pytest.raises(SystemExit, match=message) as info:
        main(argv + ["--out", str(tmp_path / "c.json"), "--no-progress", "--workers", "0"])
    assert "\n" not in str(info.value) and not (tmp_path / "c.json").exists()


def test_an_action_that_does_not_fit_the_task_names_the_space(tmp_path):
    with pytest.raises(SystemExit, match=r"action 7 does not fit DynNav-OneObstacle-v1's action space Discrete\(3\)"):
        main(["--policy", "bench_policies:wrong_action", "--task", TASK, "--episodes", "1", "--workers", "0",
              "--out", str(tmp_path / "c.json"), "--no-progress"])
    with pytest.raises(SystemExit, match="plays DynNav-MovingObstacles-v1, not DynNav-OneObstacle-v1"):
        main(["--policy", "pretrained:5.3", "--task", TASK, "--episodes", "1", "--workers", "0",
              "--out", str(tmp_path / "c.json"), "--no-progress"])


def test_the_suites_are_fixed():
    assert len(suite_cells("study")) == 9 and all(c.episodes == 100 for c in suite_cells("study"))
    proc = suite_cells("procedural")
    assert [c.name for c in proc][:2] == ["DynNav-Procedural-v1 [difficulty=easy,split=test]",
                                          "DynNav-Procedural-v1 [difficulty=easy,split=ood]"]
    (crowd,) = suite_cells("crowd")
    assert crowd.episodes == 500 and crowd.options == dict(scenario="circle_crossing", humans=5, on_arrival="stop")


def test_the_leaderboard_is_made_from_the_committed_cards_byte_for_byte(tmp_path):
    from agents.benchmark.leaderboard import CARDS, PAGE, main as leaderboard, read_cards, render

    assert render(read_cards(CARDS)) == PAGE.read_text(encoding="utf-8"), (
        "docs/leaderboard.md differs from results/scorecards/: run python -m agents.benchmark.leaderboard")
    (tmp_path / "bad.json").write_text('{"cells": []}')
    with pytest.raises(SystemExit, match="bad.json is not a score card"):
        leaderboard(["--cards", str(tmp_path), "--out", str(tmp_path / "page.md")])


def test_a_card_is_a_row_of_its_suite_under_the_references(tmp_path):
    from agents.benchmark.leaderboard import read_cards, render

    out = tmp_path / "cards" / "mine.json"
    main(["--policy", "bench_policies:toward_target", "--task", TASK, "--episodes", "3", "--workers", "0",
          "--out", str(out), "--no-progress"])
    page = render(read_cards(out.parent))
    card = json.loads(out.read_text())
    assert f"## {TASK}" in page and "| full-state planner (the ceiling) |" in page
    assert f"| `bench_policies:toward_target` | {card['cells'][0]['success']:.0%} |" in page
    named = tmp_path / "cards" / "named.json"  # --name names the row
    main(["--policy", "bench_policies:toward_target", "--task", TASK, "--episodes", "3", "--workers", "0",
          "--name", "turn and drive", "--out", str(named), "--no-progress"])
    assert f"| turn and drive | {card['cells'][0]['success']:.0%} |" in render(read_cards(out.parent))
    assert named.with_suffix(".md").read_text().startswith(f"# turn and drive on {TASK}")


def test_navigators_on_either_drive_share_a_column_and_the_row_names_the_drive(tmp_path):
    """A continuous-drive card (an SB3 model made with control_mode=diff_drive_vel) and a discrete one of the
    same task are one column of the leaderboard; the drive belongs to the navigator's row."""
    from agents.benchmark.leaderboard import read_cards, render

    def card(policy, options, success):
        return dict(policy=policy, algo="ppo" if options else None, suite=TASK, cells=[dict(
            task=TASK, options=options, name=TASK, episodes=100, success=success, references={"planner": 0.9})])

    (tmp_path / "a.json").write_text(json.dumps(card("pretrained:5.1", {}, 0.97)))
    (tmp_path / "b.json").write_text(json.dumps(card("ppo.zip", {"control_mode": "diff_drive_vel"}, 0.5)))
    page = render(read_cards(tmp_path))
    assert "| navigator | OneObstacle-v1 |" in page
    assert "| `pretrained:5.1` | 97% |" in page and "| `ppo.zip` (ppo) (continuous drive) | 50% |" in page
