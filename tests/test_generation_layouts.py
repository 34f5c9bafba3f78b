"""Each layout looks as documented, read from the generated worlds' static blocks."""

from __future__ import annotations

import numpy as np
import pytest

from dynnav_tasks.generation import WorldSpec, generate_world

SPEC = dict(arena_size=(10.0, 12.0), moving_obstacles=(0, 2), target_distance=(2.0, 8.0))


def lattice(world) -> np.ndarray:
    """The worlds' static blocks as a boolean lattice of 0.5 m cells."""
    shape = (int(world.arena.x_range[1] / 0.5), int(world.arena.y_range[1] / 0.5))
    grid = np.zeros(shape, dtype=bool)
    for group in world.obstacles:
        if not group.moving:
            x, y = group.motion.at
            assert (x - 0.25) % 0.5 == 0 and (y - 0.25) % 0.5 == 0, "blocks sit on the 0.5 m lattice"
            grid[int(x / 0.5), int(y / 0.5)] = True
    return grid


def walls(grid: np.ndarray) -> list[np.ndarray]:
    """Lines of the lattice (columns, then rows) at least 55% covered by blocks."""
    return [grid[i, :] for i in range(grid.shape[0]) if grid[i, :].mean() >= 0.55] + \
           [grid[:, j] for j in range(grid.shape[1]) if grid[:, j].mean() >= 0.55]


def doorways(line: np.ndarray) -> list[int]:
    """Widths (cells) of the runs of empty cells along a wall line."""
    runs, run = [], 0
    for blocked in line.tolist() + [True]:
        if blocked:
            if run:
                runs.append(run)
            run = 0
        else:
            run += 1
    return runs


def test_open_has_no_blocks():
    for seed in range(20):
        world = generate_world(WorldSpec(layout="open", **SPEC), seed)
        assert not lattice(world).any()


def test_clutter_covers_about_the_density():
    for density in (0.05, 0.15):
        cover = []
        for seed in range(20):
            grid = lattice(generate_world(WorldSpec(layout="clutter", layout_density=density, **SPEC), seed))
            cover.append(grid.mean())
        assert abs(float(np.mean(cover)) - density) < 0.02


@pytest.mark.parametrize("layout", ["corridors", "rooms"])
def test_corridors_and_rooms_have_walls_with_doorways(layout):
    for seed in range(20):
        grid = lattice(generate_world(WorldSpec(layout=layout, layout_density=(0.0, 0.0), **SPEC), seed))
        found = walls(grid)
        assert found, f"{layout} world {seed} has no wall"
        for line in found:
            assert any(w >= 2 for w in doorways(line)), "every wall has a doorway of 1 m or more"


def test_corridor_walls_run_one_way_and_rooms_both_ways():
    for seed in range(20):
        corridors = lattice(generate_world(WorldSpec(layout="corridors", layout_density=(0.0, 0.0), **SPEC), seed))
        columns = any(corridors[i, :].mean() >= 0.55 for i in range(corridors.shape[0]))
        rows = any(corridors[:, j].mean() >= 0.55 for j in range(corridors.shape[1]))
        assert columns != rows, "corridor walls are parallel"
    both = 0
    for seed in range(20):
        rooms = lattice(generate_world(WorldSpec(layout="rooms", layout_density=(0.0, 0.0), **SPEC), seed))
        both += any(rooms[i, :].mean() >= 0.55 for i in range(rooms.shape[0])) and \
            any(rooms[:, j].mean() >= 0.55 for j in range(rooms.shape[1]))
    assert both >= 10, "rooms of 3-5 m in a 10-12 m arena: walls across both ways"
