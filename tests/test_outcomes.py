"""agents.analysis.outcomes: test episodes grouped by what their seeds drew."""

import json

import gymnasium as gym
import pytest

import dynnav_tasks  # noqa: F401
from agents.analysis.outcomes import STILL, breakdown, render, route_speed, speed_bin, standing_still

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
    outcomes = ["success", "collision", "timeout", "success", "success", "timeout"]
    episodes = [dict(seed=s, outcome=o, target_start=list(drawn[s][1])) for s, o in zip(range(6), outcomes)]
    # seed 2 times out turning in place for its last 30 steps, seed 5 driving on to the end
    episodes[2]["trajectory"] = [[0.15 * i, 0.0] for i in range(170)] + [[25.35, 0.0]] * 30
    episodes[5]["trajectory"] = [[0.15 * i, 0.0] for i in range(200)]
    a = _eval(tmp_path / "a", TASK, episodes[:3])
    b = _eval(tmp_path / "b", TASK, episodes[3:])
    groups = breakdown([a, b], width=0.1)
    assert sum(sum(v for k, v in c.items() if k != STILL) for c in groups.values()) == 6
    for seed, outcome in zip(range(6), outcomes):
        speed, target = drawn[seed]
        assert groups[(speed_bin(speed, 0.1), target)][outcome] >= 1
    assert sum(c[STILL] for c in groups.values()) == 1
    assert groups[(speed_bin(drawn[2][0], 0.1), drawn[2][1])][STILL] == 1
    table = render(groups, 0.1)
    assert table.count("\n") == len(groups) + 1 and "| (3, " in table
    assert "timeout standing still" in table.splitlines()[0]


def test_standing_still_means_the_last_steps_stay_within_a_centimetre():
    turning = [[0.15 * i, 0.0] for i in range(10)] + [[1.5, 0.0]] * 20
    assert standing_still(turning, steps=19)
    assert not standing_still(turning, steps=20)  # 20 steps before the end it stood 0.15 m back
    creeping = [[0.15 * i, 0.0] for i in range(10)] + [[1.5 + 0.001 * i, 0.0] for i in range(25)]
    assert standing_still(creeping, steps=9) and not standing_still(creeping, steps=11)  # 1 mm a step
    assert not standing_still(None) and not standing_still([[0.0, 0.0]] * 5, steps=20)


def test_runs_without_a_test_phase_or_of_two_tasks_are_refused(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(FileNotFoundError, match="eval.json not found"):
        breakdown([tmp_path / "empty"])
    a = _eval(tmp_path / "a", TASK, [])
    b = _eval(tmp_path / "b", "DynNav-MovingTarget-v1", [])
    with pytest.raises(ValueError, match="different tasks"):
        breakdown([a, b])
