"""agents.outcomes: test episodes grouped by what their seeds drew."""

import json

import gymnasium as gym
import pytest

import dynnav_tasks  # noqa: F401
from agents.outcomes import breakdown, render, route_speed, speed_bin

TASK = "DynNav-MovingObstacles-v1"


def _eval(path, task, episodes):
    path.mkdir()
    (path / "eval.json").write_text(json.dumps({"task": task, "episodes": episodes}))
    return path


def test_episodes_are_grouped_by_the_speed_and_target_their_seed_drew(tmp_path):
    env = gym.make(TASK)
    drawn = {}
    for seed in range(6):
        env.reset(seed=seed)
        drawn[seed] = (route_speed(env), tuple(float(v) for v in env.unwrapped.snapshot.target_xy))
    env.close()
    assert all(0.05 <= s <= 0.5 for s, _ in drawn.values())  # the task's speed range
    outcomes = ["success", "collision", "timeout", "success", "success", "collision"]
    episodes = [dict(seed=s, outcome=o, target_start=list(drawn[s][1])) for s, o in zip(range(6), outcomes)]
    a = _eval(tmp_path / "a", TASK, episodes[:3])
    b = _eval(tmp_path / "b", TASK, episodes[3:])
    groups = breakdown([a, b], width=0.1)
    assert sum(sum(c.values()) for c in groups.values()) == 6
    for seed, outcome in zip(range(6), outcomes):
        speed, target = drawn[seed]
        assert groups[(speed_bin(speed, 0.1), target)][outcome] >= 1
    table = render(groups, 0.1)
    assert table.count("\n") == len(groups) + 1 and "| (3, " in table


def test_runs_without_a_test_phase_or_of_two_tasks_are_refused(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(FileNotFoundError, match="eval.json not found"):
        breakdown([tmp_path / "empty"])
    a = _eval(tmp_path / "a", TASK, [])
    b = _eval(tmp_path / "b", "DynNav-MovingTarget-v1", [])
    with pytest.raises(ValueError, match="different tasks"):
        breakdown([a, b])
