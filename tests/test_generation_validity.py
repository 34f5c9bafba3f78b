"""Every generated world is valid, by checks written here from the world's own numbers.

The checks do not call the generator's validator: they take the ``World`` as a task would
(arena, static blocks, moving motions' extents, start area, target) and verify, with the
robot's real footprint (the circle of radius 0.295 m around it, so any heading fits):

* the arena is 6-20 m a side, at most 600 static blocks and 30 moving boxes, blocks inside
  the arena and not overlapping one another;
* the start area and the target's whole extent are clear of blocks and walls;
* no moving box can reach the start area, the target or a block at any time;
* a 4-connected breadth-first search on a 0.1 m occupancy grid finds a way from the start to
  the target through the static layout, no longer than the spec's ``target_distance``;
* in camera worlds, the line from the lens (0.36 m up) to the marker's top (1.2 m up) is
  above 0.5 m wherever it crosses a block.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dynnav_tasks.generation import (
    DIFFICULTIES, MAX_MOVING_OBSTACLES, MAX_STATIC_BLOCKS, generate_world, spec_for, train_world_seed,
)
from dynnav_tasks.robot import CAMERA_OFFSET, FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH
from dynnav_tasks.scene import TARGET_MARKER

ROBOT = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)
BOX = 0.25  # half side of every generated obstacle
CELL = 0.1
WORLDS = 1000


def rect_box_gap(low, high, centers):
    """Euclidean distance from the rectangle low-high to each 0.5 m block centred at ``centers``."""
    dx = np.maximum(np.maximum(centers[:, 0] - BOX - high[0], low[0] - centers[:, 0] - BOX), 0.0)
    dy = np.maximum(np.maximum(centers[:, 1] - BOX - high[1], low[1] - centers[:, 1] - BOX), 0.0)
    return np.hypot(dx, dy)


def occupancy(centers, size):
    """Grid cells whose centre is within the robot's radius of a block or a wall."""
    nx, ny = int(size[0] / CELL + 1e-9), int(size[1] / CELL + 1e-9)
    x, y = (np.arange(nx) + 0.5) * CELL, (np.arange(ny) + 0.5) * CELL
    blocked = (np.minimum(x, size[0] - x)[:, None] < ROBOT) | (np.minimum(y, size[1] - y)[None, :] < ROBOT)
    reach = ROBOT + BOX
    for cx, cy in centers:
        i0, i1 = max(int((cx - reach) / CELL), 0), min(int((cx + reach) / CELL) + 1, nx)
        j0, j1 = max(int((cy - reach) / CELL), 0), min(int((cy + reach) / CELL) + 1, ny)
        dx = np.maximum(np.abs(x[i0:i1] - cx) - BOX, 0.0)
        dy = np.maximum(np.abs(y[j0:j1] - cy) - BOX, 0.0)
        blocked[i0:i1, j0:j1] |= np.hypot(dx[:, None], dy[None, :]) < ROBOT
    return blocked


def way_steps(free, start, goal):
    """Breadth-first search over 4-connected free cells, one ring of the frontier per loop:
    the number of 0.1 m steps from ``start`` to ``goal``, or None if there is no way."""
    seen = np.zeros_like(free)
    seen[start] = True
    frontier, steps = seen.copy(), 0
    while frontier.any():
        if seen[goal]:
            return steps
        grown = np.zeros_like(free)
        grown[1:, :] |= frontier[:-1, :]
        grown[:-1, :] |= frontier[1:, :]
        grown[:, 1:] |= frontier[:, :-1]
        grown[:, :-1] |= frontier[:, 1:]
        frontier = grown & free & ~seen
        seen |= frontier
        steps += 1
    return None


def check_world(world, spec=None) -> None:
    """Assert everything the module docstring lists (and, given the spec, the way's length)."""
    size = (world.arena.x_range[1], world.arena.y_range[1])
    assert world.arena.x_range[0] == 0 and world.arena.y_range[0] == 0
    assert 6 <= size[0] <= 20 and 6 <= size[1] <= 20
    statics = np.array([o.motion.at for o in world.obstacles if not o.moving]).reshape(-1, 2)
    moving = [o for o in world.obstacles if o.moving]
    assert all(o.half_size == (BOX, BOX) for o in world.obstacles)
    assert len(statics) <= MAX_STATIC_BLOCKS and world.moving_obstacle_count <= MAX_MOVING_OBSTACLES
    if len(statics):
        assert np.all(statics >= BOX - 1e-9) and np.all(statics <= np.array(size) - BOX + 1e-9)
        apart = np.abs(statics[:, None, :] - statics[None, :, :]).max(axis=2) >= 2 * BOX - 1e-9
        np.fill_diagonal(apart, True)
        assert apart.all(), "two static blocks overlap"

    start_low = (world.start.x_range[0], world.start.y_range[0])
    start_high = (world.start.x_range[1], world.start.y_range[1])
    target_low, target_high = (tuple(map(float, v)) for v in world.targets[0].extent())
    assert len(world.targets) == 1
    for low, high in ((start_low, start_high), (target_low, target_high)):
        assert min(low) >= ROBOT and high[0] <= size[0] - ROBOT and high[1] <= size[1] - ROBOT
        if len(statics):
            assert rect_box_gap(low, high, statics).min() > ROBOT, "a block is where the robot must stand"

    for group in moving:
        low, high = (tuple(map(float, v)) for v in group.motion.extent())
        assert min(low) >= BOX and high[0] <= size[0] - BOX and high[1] <= size[1] - BOX
        for other_low, other_high in ((start_low, start_high), (target_low, target_high)):
            gap = np.hypot(max(other_low[0] - high[0], low[0] - other_high[0], 0),
                           max(other_low[1] - high[1], low[1] - other_high[1], 0))
            assert gap > BOX + ROBOT, f"{group.motion} can reach the start or the target"
        if len(statics):  # the moving box (extent + 0.25) never overlaps a block
            sep = np.maximum(np.maximum(statics[:, 0] - high[0], low[0] - statics[:, 0]),
                             np.maximum(statics[:, 1] - high[1], low[1] - statics[:, 1]))
            assert sep.min() >= 2 * BOX, f"{group.motion} runs into a block"

    free = ~occupancy(statics, size)
    start = tuple(int(((lo + hi) / 2) / CELL) for lo, hi in (world.start.x_range, world.start.y_range))
    goal = tuple(int(((lo + hi) / 2) / CELL) for lo, hi in zip(target_low, target_high))
    assert free[start] and free[goal]
    steps = way_steps(free, start, goal)
    assert steps is not None, "no way from the start to the target"
    if spec is not None:
        assert steps * CELL <= spec.target_distance[1] + 1e-9, "the way to the target is longer than the spec allows"


def marker_in_sight(world) -> bool:
    """Whether the line from the lens at the start to the marker's top clears every block."""
    start = np.array([sum(world.start.x_range) / 2, sum(world.start.y_range) / 2])
    low, high = world.targets[0].extent()
    target = (np.asarray(low) + np.asarray(high)) / 2
    statics = np.array([o.motion.at for o in world.obstacles if not o.moving]).reshape(-1, 2)
    t = np.linspace(0.0, 1.0, 2001)
    points = start + t[:, None] * (target - start)
    height = CAMERA_OFFSET[2] + t * (TARGET_MARKER.height - CAMERA_OFFSET[2])
    for c in statics:
        inside = np.all(np.abs(points - c) < BOX, axis=1)
        if np.any(inside & (height < 0.5)):
            return False
    return True


@pytest.mark.parametrize("difficulty", DIFFICULTIES)
def test_train_worlds_are_valid(difficulty):
    spec = spec_for(difficulty, "train")
    for k in range(WORLDS):
        check_world(generate_world(spec, train_world_seed(difficulty, k)), spec)


@pytest.mark.parametrize("difficulty", DIFFICULTIES)
def test_ood_worlds_are_valid(difficulty):
    spec = spec_for(difficulty, "ood")
    for seed in range(WORLDS):
        check_world(generate_world(spec, seed), spec)


@pytest.mark.parametrize("difficulty", DIFFICULTIES)
def test_camera_worlds_show_the_marker_from_the_start(difficulty):
    for split in ("train", "ood"):
        spec = spec_for(difficulty, split, camera=True)
        for seed in range(100):
            world = generate_world(spec, seed)
            assert world.target_marker
            check_world(world, spec)
            assert marker_in_sight(world), f"{difficulty} {split} world {seed}: the marker is hidden"


def test_the_checks_catch_an_invalid_world():
    """The checks above fail on a world with its way cut, and on one with a block on the start."""
    from dataclasses import replace

    from dynnav_tasks.motion import Static
    from dynnav_tasks.world import Obstacles

    world = generate_world(spec_for("easy", "train"), 3)
    sx, tx = sum(world.start.x_range) / 2, world.targets[0].extent()[0][0]
    wall_x = round((sx + tx) / 2 / 0.5) * 0.5 + 0.25  # a full wall of blocks between start and target
    assert abs(wall_x - sx) > 0.8 and abs(wall_x - tx) > 0.8  # the wall stands clear of both
    wall = tuple(Obstacles((BOX, BOX), Static((wall_x, 0.25 + 0.5 * j))) for j in range(int(world.arena.y_range[1] / 0.5)))
    statics = tuple(o for o in world.obstacles if not o.moving)
    with pytest.raises(AssertionError):
        check_world(replace(world, obstacles=wall))
    on_start = Obstacles((BOX, BOX), Static((sx, sum(world.start.y_range) / 2)))
    with pytest.raises(AssertionError):
        check_world(replace(world, obstacles=statics + (on_start,)))


def test_the_sight_check_catches_a_hidden_marker():
    """A block on the first twelfth of the line from the start to the target hides the marker."""
    from dataclasses import replace

    from dynnav_tasks.motion import Static
    from dynnav_tasks.world import Obstacles

    world = generate_world(spec_for("easy", "train", camera=True), 0)
    start = np.array([sum(world.start.x_range) / 2, sum(world.start.y_range) / 2])
    target = np.asarray(world.targets[0].extent()[0])
    assert marker_in_sight(world)
    near = start + (target - start) / 12
    blocker = Obstacles((BOX, BOX), Static((float(near[0]), float(near[1]))))
    assert not marker_in_sight(replace(world, obstacles=world.obstacles + (blocker,)))
