"""The shortcuts the step takes compute exactly what the plain numpy forms compute."""

import math

import numpy as np
import pytest

from dynnav_tasks import motion
from dynnav_tasks.snapshot import box_distance, nearest_box_distance, take_snapshot


def test_uniform_range_draws_what_generator_uniform_draws():
    ranges = [(-math.pi / 4, math.pi / 4), (0.05, 0.5), (0.05, 0.15), (-3.0, 7.25), (2.0, 2.0)]
    fast, plain = np.random.default_rng(7), np.random.default_rng(7)
    for i in range(20000):
        low, high = ranges[i % len(ranges)]
        assert motion._UniformRange(low, high).draw(fast) == plain.uniform(low, high)
    assert fast.bit_generator.state == plain.bit_generator.state


def test_nearest_box_distance_is_box_distance_to_the_last_bit():
    rng = np.random.default_rng(0)
    for i in range(5000):
        n = int(rng.integers(1, 6))
        centers, half = rng.uniform(-3, 5, (n, 2)), rng.uniform(0.05, 0.5, (n, 2))
        point = rng.uniform(-3, 5, 2) if i % 4 else centers[0] + half[0] * rng.choice([-1.0, 1.0], 2)
        boxes = [(*c, *h) for c, h in zip(centers.tolist(), half.tolist())]
        assert nearest_box_distance(*point.tolist(), boxes) == float(box_distance(point, centers, half).min())
    assert nearest_box_distance(0.0, 0.0, []) == math.inf


@pytest.mark.parametrize(
    "spec",
    [
        motion.RandomInRect(x_range=(0.0, 0.3), y_range=(0.0, 0.2), speed_range=(0.05, 0.9), max_turn=3.0),
        motion.RandomInRect(x_range=(0.5, 1.5), y_range=(1.7, 3.0), start=(1.0, 2.0)),
        motion.Route(waypoints=((0, 0), (0, 2), (2, 2), (2, 0)), speed_range=(0.05, 3.0), count=3),
        motion.BackAndForth(center=(0, 0), direction=(1, 2), amplitude=0.1, speed=0.45),
        motion.Static(at=(1.0, 2.0)),
    ],
)
def test_movers_return_float64_arrays_of_their_count(spec):
    mover, rng = spec.mover(), np.random.default_rng(1)
    for xy in [mover.reset(rng)] + [mover.advance(rng) for _ in range(50)]:
        assert xy.dtype == np.float64 and xy.shape == (spec.count, 2)
    arrays, points = spec.mover(), spec.mover()
    rng_a, rng_p = np.random.default_rng(2), np.random.default_rng(2)
    arrays.reset(rng_a), points.reset(rng_p)
    for _ in range(50):  # advance_points gives advance's positions as tuples of floats
        assert [tuple(p) for p in arrays.advance(rng_a).tolist()] == points.advance_points(rng_p)


def test_take_snapshot_copies_its_inputs_and_checks_the_box_count():
    lasers, target = np.full(16, 5.0, dtype=np.float32), np.array([3.0, 3.0])
    s = take_snapshot(step=1, pose=(0.0, 0.0, 0.0), lasers=lasers, target_xy=target, static_xy=[(1.0, 1.0)],
                      moving_xy=np.zeros((0, 2)), obstacle_half=[(0.25, 0.25)], contact=False)
    lasers[0], target[0] = 1.0, 9.0
    assert s.lasers[0] == 5.0 and s.target_xy[0] == 3.0
    for array in (s.lasers, s.target_xy, s.obstacle_xy, s.obstacle_half):
        assert not array.flags.writeable
    with pytest.raises(ValueError, match="half sizes"):
        take_snapshot(step=1, pose=(0.0, 0.0, 0.0), lasers=lasers, target_xy=target, static_xy=[(1.0, 1.0)],
                      moving_xy=[(2.0, 2.0)], obstacle_half=[(0.25, 0.25)], contact=False)


@pytest.mark.parametrize("task", ["DynNav-MovingTarget-v1", "DynNav-MotionAreasRoute-v1"])
def test_the_tasks_snapshots_are_read_only_and_their_own(make_env, task):
    env = make_env(task)
    env.reset(seed=0)
    base = env.unwrapped
    before = base.snapshot
    kept = {name: getattr(before, name).copy() for name in ("lasers", "target_xy", "obstacle_xy", "obstacle_half")}
    for _ in range(3):
        env.step(1)
    after = base.snapshot
    for name, value in kept.items():
        array = getattr(after, name)
        assert not array.flags.writeable and not getattr(before, name).flags.writeable
        assert np.array_equal(getattr(before, name), value)  # later steps did not change it
        with pytest.raises(ValueError):
            array[0] = 0.0


def _maniskill_rng_state(base):
    states = [rng.get_state()[1].tobytes() for rng in base._batched_main_rng.rngs + base._batched_episode_rng.rngs]
    return list(base._main_seed), base._episode_seed.tolist(), base._main_rng.get_state()[1].tobytes(), states


def test_seeded_reset_leaves_maniskill_and_torch_as_maniskills_own_does(make_env):
    """``NavEnv.reset`` seeds ManiSkill's generators itself and skips torch's seeding (the
    task draws nothing from torch): the result is ManiSkill's seeded reset's."""
    import gymnasium as gym
    import torch
    from mani_skill.envs.sapien_env import BaseEnv

    ours, theirs = make_env("DynNav-MotionAreas-v1").unwrapped, make_env("DynNav-MotionAreas-v1").unwrapped
    for seed in (5, 6):
        torch_state = torch.get_rng_state()
        ours.reset(seed=seed)
        assert torch.equal(torch.get_rng_state(), torch_state)
        gym.Env.reset(theirs, seed=seed)
        BaseEnv.reset(theirs, seed=seed)
        assert _maniskill_rng_state(ours) == _maniskill_rng_state(theirs)
        assert np.array_equal(ours.state_vector(), theirs.state_vector())
        assert ours.np_random.bit_generator.state == theirs.np_random.bit_generator.state
