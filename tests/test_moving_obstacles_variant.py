"""World 5.3 with more and faster boxes (DynNav-MovingObstacles-v1's obstacle_count and
obstacle_speed_scale), the transfer test of a 5.3 navigator: the boxes on the loop, their speed,
and a state that keeps its 24 values by listing the two boxes nearest to the robot."""

import gymnasium as gym
import numpy as np
import pytest

import dynnav_tasks

TASK = "DynNav-MovingObstacles-v1"
LOOP_LENGTH = 12.8  # (0.6, 3.8) -> (2.0, 3.8) -> (2.0, -1.2) -> (0.6, -1.2) and back


def make(**options):
    return dynnav_tasks.NumpyWrapper(gym.make(TASK, **options))


def nearest_two(snapshot) -> tuple[tuple[int, int], np.ndarray]:
    """The indices (in the world's order) and positions of the two boxes nearest to the robot."""
    boxes = [np.asarray(p, dtype=float) for p in snapshot.moving_obstacle_xy]
    robot = np.asarray(snapshot.pose[:2], dtype=float)
    distance = [float(np.hypot(*(p - robot))) for p in boxes]
    i, j = sorted(sorted(range(len(boxes)), key=lambda k: distance[k])[:2])
    return (i, j), np.concatenate([boxes[i], boxes[j]])


def drive(env, seeds, steps: int, rng):
    """Yield the observation after each reset and step: random actions, a new seed when an episode ends."""
    for seed in seeds:
        obs, _ = env.reset(seed=seed)
        yield obs
        for _ in range(steps):
            obs, _, terminated, truncated, _ = env.step(int(rng.integers(env.action_space.n)))
            yield obs
            if terminated or truncated:
                break


def test_four_boxes_one_and_a_half_times_as_fast_stay_evenly_spaced_on_the_loop():
    env = make(obstacle_count=4, obstacle_speed_scale=1.5)
    try:
        task = env.unwrapped
        assert task.world.moving_obstacle_count == 4
        (group,) = task.world.obstacles
        route = group.motion
        assert route.speed_range == pytest.approx((0.075, 0.75))
        speeds = []
        for seed in range(8):
            env.reset(seed=seed)
            before = [route.nearest_arc_length(p) for p in task.snapshot.moving_obstacle_xy]
            assert task.snapshot.moving_count == 4
            gaps = np.diff(before) % LOOP_LENGTH
            assert gaps == pytest.approx([LOOP_LENGTH / 4] * 3, abs=1e-4)  # a quarter of the loop apart
            env.step(0)
            after = [route.nearest_arc_length(p) for p in task.snapshot.moving_obstacle_xy]
            moved = (np.array(after) - np.array(before)) % LOOP_LENGTH
            assert moved == pytest.approx([moved[0]] * 4, abs=1e-4)  # one speed for all
            speeds.append(moved[0])
        assert all(0.075 - 1e-6 <= v <= 0.75 + 1e-6 for v in speeds)
        assert max(speeds) > 0.5  # faster than 5.3's boxes can be
    finally:
        env.close()


def test_the_state_lists_the_two_boxes_nearest_to_the_robot_in_the_worlds_order():
    env = make(obstacle_count=4, obstacle_speed_scale=1.5)
    try:
        task = env.unwrapped
        assert env.observation_space.shape == (24,)
        assert [name for name, _ in task.state_layout()][-2:] == ["obstacle0_xy", "obstacle1_xy"]
        pairs = set()
        for obs in drive(env, seeds=(0, 1, 2), steps=12, rng=np.random.default_rng(0)):
            snapshot = task.snapshot
            assert obs.shape == (24,) and obs.dtype == np.float32
            np.testing.assert_array_equal(obs, task.state_vector())
            np.testing.assert_allclose(obs[:16], snapshot.lasers)  # the lasers see every box
            np.testing.assert_allclose(obs[16:20], np.r_[snapshot.pose[:2], snapshot.target_xy], rtol=1e-6)
            pair, xy = nearest_two(snapshot)
            np.testing.assert_allclose(obs[20:], xy, rtol=1e-6)
            pairs.add(pair)
        assert len(pairs) > 1  # the boxes move: the nearest two change
    finally:
        env.close()


def test_the_default_world_is_the_study_5_3_and_its_state_unchanged():
    variant = make(obstacle_count=8, obstacle_speed_scale=4)
    variant.close()  # a variant made first does not change the worlds made after it
    env = make()
    try:
        task = env.unwrapped
        assert task.world.moving_obstacle_count == 2
        assert task.world.obstacles[0].motion.speed_range == (0.05, 0.5)
        assert env.observation_space.shape == (24,)
        for obs in drive(env, seeds=(0, 1), steps=8, rng=np.random.default_rng(1)):
            np.testing.assert_array_equal(obs, task.snapshot.state_vector())
    finally:
        env.close()


@pytest.mark.parametrize("option, value", [
    ("obstacle_count", 0), ("obstacle_count", 9), ("obstacle_count", True), ("obstacle_count", 2.5),
    ("obstacle_count", "4"),
    ("obstacle_speed_scale", 0), ("obstacle_speed_scale", -1), ("obstacle_speed_scale", 5),
    ("obstacle_speed_scale", "1.5"),
])
def test_impossible_options_are_refused_naming_the_option(option, value):
    with pytest.raises(ValueError, match=f"{option} must be .* got {value!r}"):
        gym.make(TASK, **{option: value})



def test_every_allowed_obstacle_count_keeps_the_24_values_of_the_state():
    for count in range(1, 9):
        try:
            env = make(obstacle_count=count)
        except ValueError:
            assert count == 1  # a single box is refused: the state has two obstacle places
            continue
        try:
            assert env.observation_space.shape == (24,), f"obstacle_count={count}"
        finally:
            env.close()
