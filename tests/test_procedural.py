"""DynNav-Procedural-v1: worlds per episode from the generator, splits, the world swap, and
what the robot senses in a world it was just moved into (lasers, contacts, snapshots)."""

import math

import gymnasium as gym
import numpy as np
import pytest

import dynnav_tasks
from dynnav_tasks import generation
from dynnav_tasks.motion import RandomInRect, Static
from dynnav_tasks.snapshot import box_distance, footprint_overlaps
from dynnav_tasks.world import Arena, Obstacles, StartArea, World

TASK = "DynNav-Procedural-v1"
FORWARD, LEFT = 0, 1


def contract_world(blocks=(), moving=(), target=(7.0, 7.0), size=8.0) -> World:
    """A world as the generator makes them: 0.5 m blocks and boxes, one target, the arena
    from the origin, the robot starting around (1, 1)."""
    obstacles = [Obstacles(half_size=(0.25, 0.25), motion=Static(xy)) for xy in blocks]
    obstacles += [Obstacles(half_size=(0.25, 0.25), motion=m) for m in moving]
    return World(
        targets=(Static(target),),
        obstacles=tuple(obstacles),
        arena=Arena(x_range=(0.0, size), y_range=(0.0, size)),
        start=StartArea(x_range=(0.9, 1.1), y_range=(0.9, 1.1)),
    )


def parked_at(xy) -> RandomInRect:
    """A moving box that starts at ``xy`` and wanders slowly near it."""
    x, y = xy
    return RandomInRect(x_range=(x - 0.05, x + 0.05), y_range=(y - 0.05, y + 0.05), speed_range=(0.01, 0.02), start=xy)


# a row of blocks along the north wall: enough static blocks that a snapshot tests only those
# near the robot (sensing.CULL_ABOVE), which must not change what it finds
NORTH_ROW = tuple((0.25 + 0.5 * i, 7.75) for i in range(12))


@pytest.fixture(scope="module")
def env():
    e = dynnav_tasks.NumpyWrapper(gym.make(TASK, difficulty="easy", split="train"))
    yield e
    e.close()


def rollout(env, seed, actions, **reset):
    obs, _ = env.reset(seed=seed, **reset)
    out = [obs]
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(a)
        out.append(np.append(obs, reward))
        if terminated or truncated:
            break
    return out


def test_a_seeded_reset_replays_bit_for_bit_and_seeds_differ(env):
    actions = [FORWARD, LEFT, FORWARD, FORWARD, 2, FORWARD] * 5
    first = rollout(env, 11, actions)
    world, seed = env.unwrapped.world, env.unwrapped.world_seed
    rollout(env, 12, actions)  # another world in between
    assert env.unwrapped.world_seed != seed and env.unwrapped.world != world
    again = rollout(env, 11, actions)
    assert env.unwrapped.world == world and env.unwrapped.world_seed == seed
    assert len(first) == len(again)
    for a, b in zip(first, again):
        np.testing.assert_array_equal(a, b)
    spec = generation.spec_for("easy", "train")
    seeds = set()
    for s in range(5):
        env.reset(seed=s)
        seeds.add(env.unwrapped.world_seed)
        assert env.unwrapped.world == generation.generate_world(spec, env.unwrapped.world_seed)
    assert len(seeds) == 5


def test_the_world_seed_option_picks_the_world_and_is_checked(env):
    test_seeds = generation.test_world_seeds("easy")
    k = generation.train_world_seed("easy", 7)
    env.reset(seed=0, options={"world_seed": k})
    assert env.unwrapped.world_seed == k
    assert env.unwrapped.world == generation.generate_world(generation.spec_for("easy", "train"), k)
    for bad in (-1, 1.5, True, "3"):
        with pytest.raises(ValueError, match="non-negative integer"):
            env.reset(options={"world_seed": bad})
    with pytest.raises(ValueError, match="is a test world"):
        env.reset(options={"world_seed": test_seeds[0]})
    with pytest.raises(ValueError, match="either 'world' or 'world_seed'"):
        env.reset(options={"world_seed": k, "world": contract_world()})


def test_train_never_draws_a_test_world_and_test_draws_only_listed_ones(env):
    test_seeds = set(generation.test_world_seeds("easy"))
    assert len(test_seeds) >= 100
    drawn = set()
    for s in range(300):
        env.reset(seed=s)
        drawn.add(env.unwrapped.world_seed)
    assert not drawn & test_seeds and len(drawn) > 290
    test = dynnav_tasks.NumpyWrapper(gym.make(TASK, difficulty="easy", split="test", obstacle_k=0))
    try:
        ordered = generation.test_world_seeds("easy")
        for s in range(len(ordered)):  # seeds 0 .. n-1 cover the list once
            test.reset(seed=s)
            assert test.unwrapped.world_seed == ordered[s]
        for _ in range(20):  # unseeded resets draw from the list too
            test.reset()
            assert test.unwrapped.world_seed in test_seeds
        test.reset(options={"world_seed": ordered[3]})
        assert test.unwrapped.world_seed == ordered[3]
        with pytest.raises(ValueError, match="not one of the"):
            test.reset(options={"world_seed": generation.train_world_seed("easy", 0)})
    finally:
        test.close()


def test_bad_task_arguments_list_the_choices():
    assert TASK in dynnav_tasks.PROCEDURAL_TASK_IDS and TASK not in dynnav_tasks.TASK_IDS
    with pytest.raises(ValueError, match="easy, medium, hard"):
        dynnav_tasks.make(TASK, difficulty="extreme")
    with pytest.raises(ValueError, match="train, test, ood"):
        gym.make(TASK, split="validation")
    for k in (-1, 31, 2.0, None):
        with pytest.raises(ValueError, match="obstacle_k must be an integer from 0 to 30"):
            gym.make(TASK, obstacle_k=k)


def test_a_laser_meets_a_block_at_its_hand_computed_distance(env):
    block = (4.25, 2.0)  # west face at x = 4.0
    env.reset(seed=0, options={"world": contract_world(blocks=(block,) + NORTH_ROW)})
    lasers = env.unwrapped.place_robot(2.0, 2.0, 0.0)[:16]
    assert lasers[0] == pytest.approx(2.0, abs=1e-4)  # ray 0 straight ahead
    assert lasers[8] == pytest.approx(2.0, abs=1e-4)  # behind: the west wall at x = 0
    assert lasers[4] == pytest.approx(5.0)  # left: the north row's face at y = 7.5 is beyond range
    assert env.unwrapped.snapshot.d2 == pytest.approx(2.0)


def test_driving_into_a_block_is_a_collision(env):
    env.reset(seed=0, options={"world": contract_world(blocks=((3.0, 2.0),) + NORTH_ROW)})
    env.unwrapped.place_robot(2.0, 2.0, 0.0)  # 0.525 m from the block's face
    for step in range(1, 10):
        _, reward, terminated, truncated, info = env.step(FORWARD)
        if terminated:
            break
    assert terminated and info["collision"] and not info["success"] and reward == -20.0
    assert step <= 4


def test_after_a_world_swap_nothing_of_the_last_world_is_there(env):
    blocked = contract_world(blocks=((3.0, 2.0), (3.0, 4.0)) + NORTH_ROW, moving=(parked_at((5.0, 2.0)),))
    env.reset(seed=0, options={"world": blocked})
    assert env.unwrapped.place_robot(2.0, 2.0, 0.0)[0] == pytest.approx(0.75, abs=1e-4)
    open_world = contract_world(size=10.0, target=(9.0, 9.0))
    env.reset(seed=0, options={"world": open_world})
    assert env.unwrapped.world is open_world
    lasers = env.unwrapped.place_robot(2.0, 2.0, 0.0)[:16]
    np.testing.assert_allclose(lasers[[0, 4]], [5.0, 5.0])  # the east and north walls are 8 m away now
    assert lasers[8] == pytest.approx(2.0, abs=1e-4) and lasers[12] == pytest.approx(2.0, abs=1e-4)
    s = env.unwrapped.snapshot
    assert len(s.obstacle_xy) == 0 and s.d2 == math.inf
    for _ in range(25):  # through where the blocks and the moving box stood, to x = 5.75
        _, _, terminated, truncated, info = env.step(FORWARD)
        assert not terminated, info
    assert env.unwrapped.snapshot.pose[0] == pytest.approx(5.75, abs=0.05)


def test_snapshots_see_the_current_worlds_boxes_and_rewards_its_bound(env):
    world = contract_world(blocks=((3.0, 2.0),) + NORTH_ROW, moving=(parked_at((5.0, 5.0)),), size=12.0)
    env.reset(seed=3, options={"world": world})
    u = env.unwrapped
    s = u.snapshot
    assert s.moving_count == 1 and len(s.obstacle_xy) == 14
    np.testing.assert_array_equal(s.obstacle_xy[:13], np.array(((3.0, 2.0),) + NORTH_ROW))
    assert u.reward_bound == u.reward_bound_of(world) > u.reward_bound_of(contract_world())
    rng = np.random.default_rng(0)
    for _ in range(30):  # the culled footprint and d2 tests agree with tests against every box
        x, y, yaw = rng.uniform(0.5, 11.5), rng.uniform(0.5, 11.5), rng.uniform(-math.pi, math.pi)
        u.place_robot(x, y, yaw)
        s = u.snapshot
        assert s.d2 == box_distance(np.array(s.pose[:2]), s.obstacle_xy, s.obstacle_half).min()
        boxes = [(*c, *h) for c, h in zip(s.obstacle_xy.tolist(), s.obstacle_half.tolist())]
        if footprint_overlaps(s.pose, (0.225, 0.19), boxes):
            _, _, terminated, _, info = env.step(LEFT)
            assert terminated and info["collision"]
            env.reset(seed=3, options={"world": world})


def test_bad_worlds_are_refused_before_anything_changes(env):
    env.reset(seed=0)
    seed = env.unwrapped.world_seed
    too_big = contract_world(size=24.0)
    with pytest.raises(ValueError, match="up to 20 m a side"):
        env.reset(options={"world": too_big})
    wide = World(targets=(Static((5.0, 5.0)),), obstacles=(Obstacles((0.5, 0.25), Static((3.0, 3.0))),),
                 arena=Arena((0.0, 8.0), (0.0, 8.0)))
    with pytest.raises(ValueError, match="0.5 m x 0.5 m x 0.5 m box"):
        env.reset(options={"world": wide})
    with pytest.raises(ValueError, match="must be a dynnav_tasks.world.World"):
        env.reset(options={"world": "open"})
    assert env.unwrapped.world_seed == seed


@pytest.mark.parametrize("difficulty", generation.DIFFICULTIES)
def test_every_split_of_every_difficulty_runs_in_its_own_worlds(difficulty):
    for split in generation.SPLITS:
        env = dynnav_tasks.NumpyWrapper(gym.make(TASK, difficulty=difficulty, split=split, obstacle_k=3))
        try:
            u = env.unwrapped
            assert u.world_spec == generation.spec_for(difficulty, split)
            for seed in range(3):
                obs, info = env.reset(seed=seed)
                assert env.observation_space.contains(obs) and not info["collision"]  # a free start
                assert u.snapshot.moving_count == u.world.moving_obstacle_count
                assert max(u.world.arena.size) <= 20.0 and u.reward_bound == u.reward_bound_of(u.world)
                for _ in range(5):
                    obs, _, _, _, info = env.step(FORWARD)
                    assert env.observation_space.contains(obs)
                    if info["collision"] or info["success"]:
                        break
        finally:
            env.close()


def test_pedestrians_walk_the_procedural_worlds_and_leave_with_them():
    """``pedestrians=3``: each generated world holds three walkers, in the state's human slots
    (``human_k``); a world passed with one shows it to the lasers where it stands, and a world
    passed without pedestrians shows none of them."""
    from dataclasses import replace

    from dynnav_tasks.crowd.crowd import Pedestrians

    env = dynnav_tasks.NumpyWrapper(gym.make(TASK, difficulty="easy", split="test", pedestrians=3, human_k=2))
    try:
        obs, _ = env.reset(seed=4)
        u = env.unwrapped
        assert u.world.pedestrians.count == 3 and obs.shape == (19 + 5 * 4 + 5 * 2,)
        layout = dict(u.task_state_layout())
        assert layout["human1"] == 5 and "human2" not in layout
        assert u.snapshot.human_xy.shape == (3, 2)
        one = Pedestrians(1, scenario="free_space", area=((0.0, 10.0), (0.0, 10.0)))
        env.reset(seed=0, options={"world": replace(contract_world(size=10.0, target=(9.0, 9.0)), pedestrians=one)})
        u.place_pedestrians([(5.0, 5.0)])
        lasers = u.place_robot(3.5, 5.0, 0.0)[:16]
        assert lasers[0] == pytest.approx(1.2, abs=1e-3)  # 1.5 m to its centre, 0.3 m radius
        env.reset(seed=0, options={"world": contract_world(size=10.0, target=(9.0, 9.0))})
        assert len(u.snapshot.human_xy) == 0
        lasers = u.place_robot(5.0, 5.0, 0.0)[:16]
        np.testing.assert_allclose(lasers[[0, 4, 8, 12]], [5.0, 5.0, 5.0, 5.0], atol=1e-3)  # only the walls
    finally:
        env.close()
