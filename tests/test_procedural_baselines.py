"""The baselines in generated worlds: the planner follows the way through walls and doorways,
the go-to-target floor drives straight, and the command line records both per difficulty and split."""

import json
import math

import numpy as np
import pytest

from dynnav_tasks.baselines.episodes import run_episodes
from dynnav_tasks.baselines.go_to_target import GoToTarget
from dynnav_tasks.baselines.state_planner import PlannerController, run_planner
from dynnav_tasks.baselines.way_grid import StaticBuckets, WayGrid, static_boxes
from dynnav_tasks.motion import Static
from dynnav_tasks.world import Arena, Obstacles, StartArea, World

TASK = "DynNav-Procedural-v1"
BLOCK = (0.25, 0.25)


def _world(blocks, target, start=(2.0, 2.0), side=8.0):
    """A world of this task: 0.5 m blocks at ``blocks`` (centres), a static target, a 0.2 m start area."""
    return World(targets=(Static(target),), obstacles=tuple(Obstacles(BLOCK, Static(b)) for b in blocks),
                 arena=Arena((0.0, side), (0.0, side)),
                 start=StartArea((start[0] - 0.1, start[0] + 0.1), (start[1] - 0.1, start[1] + 0.1)))


# a wall of blocks from the south wall up to y = 6.5 between the start (2, 2) and the target
# (6.5, 2); the only way is through the 1.5 m doorway at its north end, 11 m long
WALL_WITH_DOOR = _world([(4.25, 0.25 + 0.5 * j) for j in range(13)], (6.5, 2.0))


def test_the_way_grid_goes_round_a_wall_through_its_doorway():
    grid = WayGrid(WALL_WITH_DOOR, clearance=0.3)
    field = grid.to((6.5, 2.0))
    assert not grid.line_free((2.0, 2.0), (6.5, 2.0))
    assert 10.5 < field.distance(2.0, 2.0) < 12.5  # the straight line is 4.5 m
    ax, ay = field.aim(2.0, 2.0)
    assert ay > 2.0 + 0.3  # the way leaves northwards, towards the doorway
    assert grid.line_free((2.0, 2.0), (2.0, 6.0)) and field.distance(6.5, 2.4) < 0.4 + 2 * 0.1  # within about a cell of the truth


def test_static_buckets_find_every_box_within_the_clearance():
    boxes = static_boxes(WALL_WITH_DOOR)
    buckets = StaticBuckets(boxes, (0.0, 8.0), (0.0, 8.0), clearance=0.33)
    rng = np.random.default_rng(0)
    for x, y in rng.uniform(0.0, 8.0, size=(2000, 2)):
        near = [b for b in boxes if math.hypot(max(b[0] - x, x - b[2], 0), max(b[1] - y, y - b[3], 0)) < 0.33]
        assert set(near) <= set(buckets.near(x, y))


def test_the_planner_finds_the_doorway_of_a_wall_across_the_straight_way():
    # searched along the straight line, the planner pushes at the wall until the time is up
    result = run_episodes("wall", TASK, [0], PlannerController(), options={"world": WALL_WITH_DOOR})
    assert result.outcomes == ["success"], result.summary()
    assert result.episodes[0].path_length > 10.0


def test_the_planner_reaches_the_target_of_a_generated_world_the_straight_line_search_missed():
    # medium train, seed 10: world 1667601684, where the straight-line search timed out
    result = run_planner(TASK, [10], task_kwargs=dict(difficulty="medium", split="train"))
    assert result.outcomes == ["success"], result.summary()
    assert result.episodes[0].world_seed == 1667601684 and 0.5 < result.spl() <= 1.0


def test_go_to_target_reaches_a_target_in_the_open_and_hits_a_block_in_its_way():
    open_world = _world([], (6.0, 5.0))
    result = run_episodes("open", TASK, [0, 1], GoToTarget(), options={"world": open_world})
    assert result.outcomes == ["success", "success"], result.summary()
    assert result.spl() > 0.9
    blocked = _world([(4.25, 3.75), (4.25, 4.25), (3.75, 3.75), (3.75, 4.25)], (6.0, 6.0))
    result = run_episodes("blocked", TASK, [0], GoToTarget(), options={"world": blocked})
    assert result.outcomes == ["collision"], result.summary()


def test_cells_are_recorded_per_controller_difficulty_and_split_and_bad_choices_are_refused(tmp_path):
    from types import SimpleNamespace

    from dynnav_tasks.baselines.cli import run_over_cells

    calls = []

    def fake_run(difficulty, split, seeds):
        calls.append((difficulty, split, list(seeds)))
        return SimpleNamespace(outcomes=["success", "timeout"], summary=lambda: "done",
                               numbers=lambda: dict(spl=0.4, steps_per_success=30.0, worlds=2))

    out = tmp_path / "procedural.json"
    run_over_cells(TASK, "easy", None, 2, 5, fake_run, controller="go_to_target", out=str(out))
    data = json.loads(out.read_text())
    assert sorted(data) == ["go_to_target/easy/ood", "go_to_target/easy/test", "go_to_target/easy/train"]
    assert data["go_to_target/easy/test"] == dict(task=TASK, difficulty="easy", split="test", success=0.5,
                                                  collision=0.0, timeout=0.5, episodes=2, first_seed=5, spl=0.4,
                                                  steps_per_success=30.0, worlds=2)
    assert calls[0] == ("easy", "train", [5, 6])
    calls.clear()
    with pytest.raises(SystemExit, match="Unknown difficulty 'medum'"):
        run_over_cells(TASK, "medum", None, 2, 0, fake_run, controller="x", out=str(out))
    with pytest.raises(SystemExit, match="Unknown split 'tset'"):
        run_over_cells(TASK, None, "tset", 2, 0, fake_run, controller="x", out=str(out))
    with pytest.raises(SystemExit, match="--episodes must be >= 1"):
        run_over_cells(TASK, None, None, 0, 0, fake_run, controller="x", out=str(out))
    assert calls == [] and sorted(json.loads(out.read_text())) == sorted(data)


def test_dwa_goes_round_blocks_and_through_a_doorway_on_the_scan_and_the_static_map():
    """The dynamic window on the continuous drive, reading the 16 laser rays: round a 1 m block
    that stands on the straight way, and through the doorway of a wall (the way through the static
    map gives its heading), without touching either; the discrete drive is refused."""
    from dynnav_tasks.baselines.dwa import DWA, DWAConfig

    blocked = _world([(4.25, 3.75), (4.25, 4.25), (3.75, 3.75), (3.75, 4.25)], (6.0, 6.0))
    for world in (blocked, WALL_WITH_DOOR):
        result = run_episodes("dwa", TASK, [0, 1], DWA(), options={"world": world}, control_mode="diff_drive_vel")
        assert result.outcomes == ["success", "success"], result.summary()
    # without the map's way it stalls in front of the wall, pushing towards the target: never a collision
    result = run_episodes("dwa", TASK, [0], DWA(DWAConfig(follow_way=False)), options={"world": WALL_WITH_DOOR},
                          control_mode="diff_drive_vel")
    assert result.outcomes == ["timeout"], result.summary()
    with pytest.raises(ValueError, match=r"commands velocities: make the task with control_mode='diff_drive_vel', "
                                         r"not 'discrete_drive'"):
        run_episodes("dwa", TASK, [0], DWA(), options={"world": blocked})
