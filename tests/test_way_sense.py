"""The way through the static layout (``way=True``): readings against geometry worked out by hand."""

import math

import gymnasium as gym
import numpy as np
import pytest

import dynnav_tasks
from dynnav_tasks.motion import Static
from dynnav_tasks.way_sense import CLEARANCE, WaySense
from dynnav_tasks.world import Arena, Obstacles, StartArea, World

# a wall of 0.5 m blocks across an 8 m arena at x = 4.0-4.5, from the south wall up to y = 6: the
# only way from the west half to the east half passes north of it, through the gap y = 6-8
WALL = tuple((4.25, 0.25 + 0.5 * i) for i in range(12))


def world(blocks=WALL, target=(6.0, 2.0)) -> World:
    return World(targets=(Static(target),), obstacles=tuple(Obstacles((0.25, 0.25), Static(b)) for b in blocks),
                 arena=Arena((0.0, 8.0), (0.0, 8.0)), start=StartArea((1.9, 2.1), (1.9, 2.1)))


def test_an_open_line_is_the_straight_way():
    sense = WaySense(world(blocks=()))
    length, s, c = sense.read(2.0, 2.0, 0.3, 5.0, 4.0)
    assert length == pytest.approx(math.hypot(3.0, 2.0), abs=1e-9)
    assert math.atan2(s, c) == pytest.approx(math.atan2(2.0, 3.0) - 0.3, abs=1e-9)


def test_the_way_goes_round_a_wall_through_its_gap():
    sense = WaySense(world())
    length, s, c = sense.read(2.0, 2.0, 0.0, 6.0, 2.0)
    # by hand: from (2, 2) over the wall's top corners (4, 6) and (4.5, 6) down to (6, 2) is
    # 4.47 + 0.5 + 4.27 = 9.24 m, nothing shorter exists; passing the corners at the clearance,
    # over (4, 6.32) and (4.5, 6.32): 4.77 + 0.5 + 4.58 = 9.85 m, which the grid's eight directions
    # lengthen by up to 8% (a line at 22.5 degrees) and its cells by a few more
    hand = math.hypot(2.0, 4.0 + CLEARANCE) + 0.5 + math.hypot(1.5, 4.0 + CLEARANCE)
    assert 9.24 <= length <= hand * 1.12
    bearing = math.degrees(math.atan2(s, c))
    assert 30.0 < bearing < 80.0  # to the left, towards the gap (the target itself is straight ahead: 0)


def test_a_robot_closer_to_the_wall_than_the_margin_still_reads_its_way():
    sense = WaySense(world())
    far_length = sense.read(2.0, 2.0, 0.0, 6.0, 2.0)[0]
    length, s, c = sense.read(3.8, 2.0, 0.0, 6.0, 2.0)  # 0.2 m from the wall's face, inside the margin
    assert length < far_length  # nearer the gap than (2, 2) is, and not "unreachable"
    assert math.atan2(s, c) > 0.5  # still round the wall to the north


def test_the_task_state_holds_the_way_reading():
    env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Procedural-v1", way=True))
    try:
        task = env.unwrapped
        layout = dict(task.task_state_layout())
        assert layout["way"] == 3 and env.observation_space.shape == (16 + 3 + 3 + 5 * 4,)
        env.reset(seed=0, options={"world": world()})
        state = task.place_robot(2.0, 2.0, 0.0)
        way = state[16 + 3:16 + 6]
        expected = WaySense(world()).read(2.0, 2.0, 0.0, 6.0, 2.0)
        np.testing.assert_allclose(way, expected, atol=2e-3)  # the robot stands where it was put, to a mm
        assert env.observation_space.contains(state)
    finally:
        env.close()


def test_mixed_difficulty_draws_each_difficulty_and_refuses_other_splits():
    env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Procedural-v1", difficulty="mixed"))
    try:
        seen = []
        for seed in range(12):
            env.reset(seed=seed)
            seen.append(env.unwrapped.world_difficulty)
            assert env.unwrapped.world.arena.size.max() <= 14.0  # a train world of one of the three
        assert set(seen) == {"easy", "medium", "hard"}
        env.reset(seed=5)
        first = (env.unwrapped.world_difficulty, env.unwrapped.world_seed)
        env.reset(seed=5)
        assert (env.unwrapped.world_difficulty, env.unwrapped.world_seed) == first  # the seed picks both
        with pytest.raises(ValueError, match="one difficulty"):
            env.reset(options={"world_seed": 3})
    finally:
        env.close()
    with pytest.raises(ValueError, match="split 'test' needs one difficulty"):
        gym.make("DynNav-Procedural-v1", difficulty="mixed", split="test")


def test_the_procedural_task_plays_a_study_world_through_its_own_state():
    env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Procedural-v1", study_world=5.3, way=True))  # as options read it
    try:
        targets = set()
        for seed in range(8):
            obs, _ = env.reset(seed=seed)
            world = env.unwrapped.world
            assert world.moving_obstacle_count == 2 and tuple(world.arena.size) == (6.5, 6.5)
            targets.add(world.targets[0].at)
            assert obs.shape == (42,) and env.unwrapped.world_seed is None
        assert targets == {(3.0, 3.0), (3.0, 1.0)}  # the seed draws one of 5.3's two targets
        with pytest.raises(ValueError, match="study_world"):
            env.reset(options={"world_seed": 3})
    finally:
        env.close()
    transfer = gym.make("DynNav-Procedural-v1", study_world="5.3-transfer")
    try:
        transfer.reset(seed=0)
        assert transfer.unwrapped.world.moving_obstacle_count == 4
    finally:
        transfer.close()


def test_the_straight_line_check_tests_every_half_cell_of_the_segment():
    """``WayGrid.line_free`` against its definition: the segment's points at every half cell
    (numpy's linspace), each in a free cell; on random segments around and across the wall."""
    grid = WaySense(world()).grid
    rng = np.random.default_rng(3)
    answers = []
    for _ in range(2000):
        a, b = rng.uniform(-0.5, 8.5, 2), rng.uniform(0.0, 8.0, 2)
        n = max(1, math.ceil(math.hypot(*(b - a)) / (grid.cell / 2)))
        points = a + np.outer(np.linspace(0.0, 1.0, n + 1), b - a)
        i = np.clip(((points[:, 0] - grid.x0) // grid.cell).astype(int), 0, grid.nx - 1)
        j = np.clip(((points[:, 1] - grid.y0) // grid.cell).astype(int), 0, grid.ny - 1)
        answers.append(bool(grid.free[i, j].all()))
        assert grid.line_free(tuple(a), tuple(b)) == answers[-1], (a, b)
    assert 0.2 < np.mean(answers) < 0.8  # both answers were asked for
