"""Geometric facts of each world, proved from the task's own definitions."""

import math

import numpy as np
import pytest

from dynnav_tasks.motion import BackAndForth, Route, Static
from dynnav_tasks.robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH
from dynnav_tasks.tasks import MovingObstaclesEnv, MovingTargetEnv

ROBOT_RADIUS = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)


def _obstacle_boxes(world):
    """(low, high) corners of the area each obstacle group can occupy."""
    for group in world.obstacles:
        lo, hi = group.motion.extent()
        yield np.asarray(lo) - group.half_size, np.asarray(hi) + group.half_size


def _rect_gap(lo_a, hi_a, lo_b, hi_b):
    d = np.maximum(np.maximum(lo_b - hi_a, lo_a - hi_b), 0.0)
    return float(np.hypot(*d))


@pytest.mark.parametrize("cls", [MovingTargetEnv, MovingObstaclesEnv])
def test_start_area_is_clear_and_inside(cls):
    world = cls.world
    s = world.start
    lo, hi = np.array([s.x_range[0], s.y_range[0]]), np.array([s.x_range[1], s.y_range[1]])
    for o_lo, o_hi in _obstacle_boxes(world):
        assert _rect_gap(lo, hi, o_lo, o_hi) > ROBOT_RADIUS + 0.1
    (x0, x1), (y0, y1) = world.arena.x_range, world.arena.y_range
    assert x0 + ROBOT_RADIUS < lo[0] and hi[0] < x1 - ROBOT_RADIUS
    assert y0 + ROBOT_RADIUS < lo[1] and hi[1] < y1 - ROBOT_RADIUS


@pytest.mark.parametrize("cls", [MovingTargetEnv, MovingObstaclesEnv])
def test_targets_are_reachable(cls):
    """Every point a target can be at leaves room for the robot within the reach radius."""
    world = cls.world
    for target in world.targets:
        lo, hi = target.extent()
        for o_lo, o_hi in _obstacle_boxes(world):
            assert _rect_gap(np.asarray(lo), np.asarray(hi), o_lo, o_hi) > ROBOT_RADIUS
        assert world.arena.x_range[0] + ROBOT_RADIUS < lo[0] and hi[0] < world.arena.x_range[1] - ROBOT_RADIUS
        assert world.arena.y_range[0] + ROBOT_RADIUS < lo[1] and hi[1] < world.arena.y_range[1] - ROBOT_RADIUS


def test_world_5_2_matches_the_thesis():
    world = MovingTargetEnv.world
    centers = [t.center for t in world.targets]
    assert centers == [(-0.5, 3.0), (3.0, 3.0), (3.0, -0.5)]
    for t in world.targets:
        assert isinstance(t, BackAndForth) and t.amplitude == 0.5 and t.speed == 0.05
    assert [t.direction for t in world.targets] == [(0, 1), (0, 1), (1, 0)]
    assert all(isinstance(o.motion, Static) for o in world.obstacles)


def test_world_5_3_matches_the_thesis():
    world = MovingObstaclesEnv.world
    assert [t.at for t in world.targets] == [(3.0, 3.0), (3.0, 1.0)]
    (group,) = world.obstacles
    route = group.motion
    assert isinstance(route, Route) and route.count == 2
    assert route.speed_range == (0.05, 0.5)
    assert route.signed_area() < 0, "the route must run clockwise seen from above"
    # the loop separates the start area from both targets: it spans their y values and lies between in x
    lo, hi = route.extent()
    assert world.start.x_range[1] < lo[0] and hi[0] < min(t.at[0] for t in world.targets)
    assert lo[1] <= min(t.at[1] for t in world.targets) and hi[1] >= max(t.at[1] for t in world.targets)


def test_back_and_forth_stays_on_its_segment_and_reverses():
    spec = BackAndForth(center=(0.0, 0.0), direction=(0, 1), amplitude=0.5, speed=0.05)
    mover = spec.mover()
    rng = np.random.default_rng(0)
    ys = [mover.reset(rng)[0, 1]] + [mover.advance(rng)[0, 1] for _ in range(100)]
    steps = np.diff(ys)
    assert max(abs(y) for y in ys) <= 0.5 + 1e-12
    assert np.allclose(np.abs(steps[np.abs(steps) > 0.049]), 0.05)  # full speed between reversals
    assert (steps > 0).any() and (steps < 0).any()


def test_route_keeps_bodies_spaced_at_one_speed():
    spec = Route(waypoints=((0, 0), (0, 2), (2, 2), (2, 0)), speed_range=(0.1, 0.3), count=2)
    mover = spec.mover()
    rng = np.random.default_rng(1)
    p = mover.reset(rng)
    assert 0.1 <= mover.speed <= 0.3
    for _ in range(50):
        q = mover.advance(rng)
        moved = np.abs(q - p).sum(axis=1)  # Manhattan distance: exact on this axis-aligned loop, off corners
        p = q
        assert np.all(moved <= mover.speed + 1e-9)
    assert spec.length() == pytest.approx(8.0)
    assert np.allclose(spec.position_at(5.0), (2, 1))
    assert spec.signed_area() < 0  # (0,0) -> (0,2) -> (2,2) -> (2,0) is clockwise
