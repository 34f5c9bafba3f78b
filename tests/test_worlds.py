"""Geometric facts of each world, proved from the task's own definitions."""

import math

import numpy as np
import pytest

from mani_skill.utils.registration import REGISTERED_ENVS

import dynnav_tasks
from dynnav_tasks.motion import BackAndForth, RandomInRect, Route, Static
from dynnav_tasks.robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH
from dynnav_tasks.tasks import (
    MotionAreasEnv,
    MotionAreasRouteEnv,
    MovingObstaclesEnv,
    MovingTargetEnv,
    OneObstacleEnv,
    OverlappingAreasEnv,
    VisualMovingTargetsEnv,
    VisualStaticTargetEnv,
    VisualTargetsEnv,
)

ROBOT_RADIUS = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)


def _obstacle_boxes(world):
    """(low, high) corners of the area each obstacle group can occupy."""
    for group in world.obstacles:
        lo, hi = group.motion.extent()
        yield np.asarray(lo) - group.half_size, np.asarray(hi) + group.half_size


def _rect_gap(lo_a, hi_a, lo_b, hi_b):
    d = np.maximum(np.maximum(lo_b - hi_a, lo_a - hi_b), 0.0)
    return float(np.hypot(*d))


ALL_TASKS = [REGISTERED_ENVS[t].cls for t in dynnav_tasks.TASK_IDS]


def _area(motion):
    lo, hi = motion.extent()
    return np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)


def _overlap(a, b):
    """Intersection rectangle of two (lo, hi) rectangles, or None."""
    lo, hi = np.maximum(a[0], b[0]), np.minimum(a[1], b[1])
    return (lo, hi) if np.all(lo < hi) else None


def _contains(a, b):
    return bool(np.all(a[0] <= b[0]) and np.all(b[1] <= a[1]))


@pytest.mark.parametrize("cls", ALL_TASKS, ids=lambda c: c.__name__)
def test_start_area_is_clear_and_inside(cls):
    world = cls.world
    s = world.start
    lo, hi = np.array([s.x_range[0], s.y_range[0]]), np.array([s.x_range[1], s.y_range[1]])
    for o_lo, o_hi in _obstacle_boxes(world):
        assert _rect_gap(lo, hi, o_lo, o_hi) > ROBOT_RADIUS + 0.1
    (x0, x1), (y0, y1) = world.arena.x_range, world.arena.y_range
    assert x0 + ROBOT_RADIUS < lo[0] and hi[0] < x1 - ROBOT_RADIUS
    assert y0 + ROBOT_RADIUS < lo[1] and hi[1] < y1 - ROBOT_RADIUS


@pytest.mark.parametrize("cls", ALL_TASKS, ids=lambda c: c.__name__)
def test_everything_moves_inside_the_walls(cls):
    world = cls.world
    (x0, x1), (y0, y1) = world.arena.x_range, world.arena.y_range
    for target in world.targets:
        lo, hi = _area(target)
        assert x0 + ROBOT_RADIUS < lo[0] and hi[0] < x1 - ROBOT_RADIUS
        assert y0 + ROBOT_RADIUS < lo[1] and hi[1] < y1 - ROBOT_RADIUS
    for o_lo, o_hi in _obstacle_boxes(world):
        assert x0 < o_lo[0] and o_hi[0] < x1 and y0 < o_lo[1] and o_hi[1] < y1


@pytest.mark.parametrize("cls", [MovingTargetEnv, MovingObstaclesEnv, OneObstacleEnv, MotionAreasEnv,
                                 VisualStaticTargetEnv, VisualTargetsEnv, VisualMovingTargetsEnv],
                         ids=lambda c: c.__name__)
def test_targets_are_reachable(cls):
    """Wherever a target can be, no obstacle can be within a robot's width of it (all worlds
    but 5.4b and 5.4c, whose obstacles are meant to reach the targets)."""
    world = cls.world
    for target in world.targets:
        lo, hi = _area(target)
        for o_lo, o_hi in _obstacle_boxes(world):
            assert _rect_gap(lo, hi, o_lo, o_hi) > ROBOT_RADIUS


def test_5_4a_target_and_obstacle_areas_are_disjoint():
    world = MotionAreasEnv.world
    assert all(isinstance(t, RandomInRect) for t in world.targets)
    assert all(isinstance(o.motion, RandomInRect) for o in world.obstacles)
    for t in world.targets:
        for o_lo, o_hi in _obstacle_boxes(world):  # the whole area an obstacle's box can cover
            assert _overlap(_area(t), (o_lo, o_hi)) is None


def _free_path_exists(world, goal, clearance, cell=0.05):
    """Whether the robot's centre can go from the start area to ``goal`` (a (lo, hi) area) on a
    grid, keeping ``clearance`` from the walls and from every area a randomly moving obstacle's
    box can cover."""
    (x0, x1), (y0, y1) = world.arena.x_range, world.arena.y_range
    xs, ys = np.arange(x0, x1 + 1e-9, cell), np.arange(y0, y1 + 1e-9, cell)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    free = (X - x0 >= clearance) & (x1 - X >= clearance) & (Y - y0 >= clearance) & (y1 - Y >= clearance)
    for group in world.obstacles:
        if isinstance(group.motion, RandomInRect):
            lo, hi = _area(group.motion)
            lo, hi = lo - group.half_size - clearance, hi + group.half_size + clearance
            free &= ~((X >= lo[0]) & (X <= hi[0]) & (Y >= lo[1]) & (Y <= hi[1]))
    (sx0, sx1), (sy0, sy1) = world.start.x_range, world.start.y_range
    reached = free & (X >= sx0) & (X <= sx1) & (Y >= sy0) & (Y <= sy1)
    assert reached.any(), "the start area itself is not clear"
    while True:  # flood fill over 4-neighbours
        grown = reached.copy()
        grown[1:] |= reached[:-1]
        grown[:-1] |= reached[1:]
        grown[:, 1:] |= reached[:, :-1]
        grown[:, :-1] |= reached[:, 1:]
        grown &= free
        if (grown == reached).all():
            break
        reached = grown
    lo, hi = goal[0] - cell, goal[1] + cell  # a static target's area is a point: one cell around it
    return bool((reached & (X >= lo[0]) & (X <= hi[0]) & (Y >= lo[1]) & (Y <= hi[1])).any())


@pytest.mark.parametrize("cls", [MotionAreasEnv, MotionAreasRouteEnv, VisualTargetsEnv, VisualMovingTargetsEnv],
                         ids=lambda c: c.__name__)
def test_a_lane_clear_of_the_wandering_obstacles_reaches_every_target_area(cls):
    # the robot's circumscribed radius plus 0.25 m to spare on each side: a lane >= 1.1 m wide
    for target in cls.world.targets:
        assert _free_path_exists(cls.world, _area(target), clearance=ROBOT_RADIUS + 0.25)
    # and the check can fail: closing the lane (obstacle areas 0.5 m taller) cuts the targets off
    import dataclasses

    blocked = dataclasses.replace(cls.world, obstacles=tuple(
        dataclasses.replace(o, motion=dataclasses.replace(o.motion, y_range=(o.motion.y_range[0] - 0.3, o.motion.y_range[1] + 0.3)))
        if isinstance(o.motion, RandomInRect) else o for o in cls.world.obstacles))
    assert not all(_free_path_exists(blocked, _area(t), clearance=ROBOT_RADIUS + 0.25) for t in cls.world.targets)


def test_5_4b_regular_route_crosses_one_target_area():
    world = MotionAreasRouteEnv.world
    assert world.obstacles[:2] == MotionAreasEnv.world.obstacles and world.targets == MotionAreasEnv.world.targets
    route = world.obstacles[2].motion
    assert isinstance(route, Route) and route.signed_area() < 0  # regular, clockwise
    crossed = []
    for t in world.targets:
        lo, hi = _area(t)
        # sample the route densely: a point strictly inside the target area means crossing
        pts = np.array([route.position_at(s) for s in np.linspace(0, route.length(), 2001)])
        crossed.append(bool(np.any(np.all((pts > lo) & (pts < hi), axis=1))))
    assert crossed.count(True) == 1


def test_5_4c_obstacle_areas_partly_overlap_target_areas():
    world = OverlappingAreasEnv.world
    assert world.targets == MotionAreasEnv.world.targets
    for o in world.obstacles:
        areas = [_area(t) for t in world.targets]
        overlaps = [_overlap(_area(o.motion), a) for a in areas]
        hit = [a for a, ov in zip(areas, overlaps) if ov is not None]
        assert len(hit) == 1  # each obstacle area overlaps one target area...
        (a,) = hit
        assert not _contains(a, _area(o.motion)) and not _contains(_area(o.motion), a)  # ...partly


def test_random_in_rect_stays_inside_and_varies_speed():
    spec = RandomInRect(x_range=(0.0, 1.0), y_range=(0.0, 0.5), speed_range=(0.05, 0.5))
    mover = spec.mover()
    rng = np.random.default_rng(3)
    p = mover.reset(rng)
    steps = []
    for _ in range(500):
        q = mover.advance(rng)
        assert 0.0 <= q[0, 0] <= 1.0 and 0.0 <= q[0, 1] <= 0.5
        steps.append(np.linalg.norm(q - p))
        p = q
    assert max(steps) <= 0.5 + 1e-9 and min(steps) < 0.1 and np.std(steps) > 0.05


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
