"""agents.analysis.collision_views: where the obstacle that ended a collision stood, seen from the robot."""

import json
import math

import gymnasium as gym
import numpy as np
import pytest

import dynnav_tasks  # noqa: F401
from agents.analysis.collision_views import collision_views, motion_heading, relative_bearing, replay_obstacles, summarize


def test_heading_comes_from_the_last_move_long_enough_and_bearings_are_signed():
    path = [[0.0, 0.0], [0.1, 0.1], [0.1, 0.1], [0.1, 0.12]]  # a diagonal step, a turn in place, a 2 cm creep
    assert math.degrees(motion_heading(path, 3)) == pytest.approx(math.degrees(math.atan2(0.12, 0.1)))
    assert math.degrees(motion_heading(path, 1)) == pytest.approx(45.0)
    assert motion_heading([[1.0, 1.0]] * 4, 3) is None
    assert relative_bearing([0, 0], 0.0, [1, 0]) == pytest.approx(0.0)
    assert relative_bearing([0, 0], 0.0, [0, 1]) == pytest.approx(90.0)  # left is positive
    assert relative_bearing([1, 1], math.pi / 2, [2, 1]) == pytest.approx(-90.0)
    assert abs(relative_bearing([0, 0], 0.0, [-1, 0])) == pytest.approx(180.0)


@pytest.mark.parametrize("task", ["DynNav-VisualTargets-v1", "DynNav-MovingObstacles-v1"])
def test_moving_obstacles_replay_whatever_the_robot_does(task):
    """The replay's premise: obstacles (wandering ones included) move the same for any actions."""
    env = gym.make(task)
    env.reset(seed=11)
    driven = [env.unwrapped.snapshot.moving_obstacle_xy.copy()]
    actions = np.random.default_rng(0).integers(0, 3, size=25)
    for a in actions:
        _, _, terminated, truncated, _ = env.step(int(a))
        driven.append(env.unwrapped.snapshot.moving_obstacle_xy.copy())
        if terminated or truncated:
            break
    replayed = replay_obstacles(env, 11, len(driven) - 1)
    env.close()
    assert len(driven) > 5
    np.testing.assert_allclose(replayed, np.array(driven), atol=1e-6)


def test_collisions_report_the_nearest_obstacle_and_its_bearing(tmp_path):
    task = "DynNav-VisualStaticTarget-v1"
    env = gym.make(task)
    boxes = replay_obstacles(env, 3, 10)
    env.close()
    bx, by = boxes[10, 0]  # obstacle 0 (the box along y = 1) after 10 steps
    # one robot drives east into the box's west face (box dead ahead), one north away from it
    east = [[bx - 0.5 - 0.1 * (10 - i), by] for i in range(11)]
    north = [[bx, by + 0.5 - 0.1 * (10 - i)] for i in range(11)]
    episodes = [dict(seed=3, outcome="collision", trajectory=east), dict(seed=3, outcome="collision", trajectory=north),
                dict(seed=3, outcome="success", trajectory=east)]
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "eval.json").write_text(json.dumps({"task": task, "episodes": episodes}))
    records = collision_views([tmp_path / "run"], before=5)
    assert len(records) == 2
    ahead, behind = records
    assert ahead["obstacle"] == 0 and ahead["distance"] == pytest.approx(0.5, abs=1e-6)
    assert ahead["bearing_end"] == pytest.approx(0.0, abs=1e-6)
    assert abs(behind["bearing_end"]) == pytest.approx(180.0, abs=1e-6)
    assert ahead["bearing_before"] == pytest.approx(0.0, abs=1e-6)  # the box runs along the robot's line
    assert behind["bearing_before"] == pytest.approx(relative_bearing(north[5], math.pi / 2, boxes[5, 0]))
    assert abs(behind["bearing_before"]) > 34.4  # beside the robot, out of view
    text = summarize(records, half_fov_deg=34.4, near=0.7, before=5)
    assert "collisions: 2" in text and "at the end: 1, 5 steps before: 1" in text


def test_runs_without_a_test_phase_are_refused(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(FileNotFoundError, match="eval.json not found"):
        collision_views([tmp_path / "empty"])
