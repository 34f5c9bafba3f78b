"""A World from an occupancy map (World.from_occupancy_map) and DynNav-Map-v1: boxes against the
map drawn here, the start and targets given or drawn with the generated worlds' checks, moving
boxes and pedestrians in free space, every bad input refused, and the shipped office floor read
by the lasers where its walls stand."""


import gymnasium as gym
import numpy as np
import pytest
from PIL import Image

import dynnav_tasks
from dynnav_tasks.baselines.way_grid import WayGrid
from dynnav_tasks.generation.validity import PATH_RADIUS
from dynnav_tasks.occupancy_map import MapError
from dynnav_tasks.world import World

RES = 0.1
FREE, WALL, UNKNOWN = 254, 0, 205


def draw(folder, rows: list[str], origin=(-2.0, 1.0), negate: int = 0, name: str = "floor"):
    """A map of ``rows`` (top row first; # wall, . free, ? unknown) at 0.1 m a cell."""
    values = {"#": WALL, ".": FREE, "?": UNKNOWN}
    pixels = np.array([[values[c] for c in row] for row in rows], np.uint8)
    Image.fromarray(255 - pixels if negate else pixels, mode="L").save(folder / f"{name}.png")
    path = folder / f"{name}.yaml"
    path.write_text(f"image: {name}.png\nresolution: {RES}\norigin: [{origin[0]}, {origin[1]}, 0.0]\nnegate: {negate}\n"
                    "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    return path


def two_rooms(door: bool = True) -> list[str]:
    """Two 3 m x 4 m rooms side by side (a wall of 0.2 m between, with a 1 m door or none),
    outer walls 0.2 m, an unknown patch in the east room's north-east corner."""
    rows = []
    for j in range(44):  # 4.4 m, top row first
        row = ""
        for i in range(66):  # 6.6 m
            wall = i < 2 or i >= 64 or j < 2 or j >= 42 or (32 <= i < 34 and not (door and 18 <= j < 28))
            row += "#" if wall else ("?" if i >= 58 and j < 8 else ".")
        rows.append(row)
    return rows


def occupied_of(world: World, shape) -> np.ndarray:
    """The cells (column, row from the bottom) the world's static boxes cover."""
    grid = np.zeros(shape, bool)
    x0, y0 = world.arena.x_range[0], world.arena.y_range[0]
    for group in world.obstacles:
        if group.moving:
            continue
        (cx, cy), (hx, hy) = group.motion.at, group.half_size
        i0, i1 = round((cx - hx - x0) / RES), round((cx + hx - x0) / RES)
        j0, j1 = round((cy - hy - y0) / RES), round((cy + hy - y0) / RES)
        assert not grid[i0:i1, j0:j1].any()  # no cell in two boxes
        grid[i0:i1, j0:j1] = True
    return grid


@pytest.mark.parametrize("negate", [0, 1])
def test_the_boxes_cover_the_maps_walls_and_unknown_cells_cell_by_cell(tmp_path, negate):
    rows = two_rooms()
    world = World.from_occupancy_map(draw(tmp_path, rows, negate=negate), start=(-0.5, 3.2), target=(3.0, 3.2))
    expected = np.array([[c != "." for c in row] for row in rows[::-1]]).T  # [column, row from the bottom]
    np.testing.assert_array_equal(occupied_of(world, expected.shape), expected)
    assert world.arena.x_range == pytest.approx((-2.0, 4.6)) and world.arena.y_range == pytest.approx((1.0, 5.4))
    assert len(world.obstacles) < 12  # merged: the walls, the door's two pieces, the unknown patch
    assert [t.at for t in world.targets] == [(3.0, 3.2)]
    assert world.start.x_range == pytest.approx((-0.6, -0.4)) and world.start.y_range == pytest.approx((3.1, 3.3))


def test_drawn_targets_are_reachable_in_range_and_the_draw_replays(tmp_path):
    path = draw(tmp_path, two_rooms())
    a = World.from_occupancy_map(path, targets=5, seed=3, target_distance=(2.0, 5.0))
    assert a == World.from_occupancy_map(path, targets=5, seed=3, target_distance=(2.0, 5.0))
    assert a != World.from_occupancy_map(path, targets=5, seed=4, target_distance=(2.0, 5.0))
    start = (sum(a.start.x_range) / 2, sum(a.start.y_range) / 2)
    way = WayGrid(a, PATH_RADIUS).to(start)
    assert len(a.targets) == 5
    for t in a.targets:
        assert 2.0 - 0.15 <= way.distance(*t.at) <= 5.0 + 0.15  # a grid cell's slack


def test_moving_boxes_and_pedestrians_go_in_free_space(tmp_path):
    world = World.from_occupancy_map(draw(tmp_path, two_rooms()), start=(-0.5, 3.2), target=(3.0, 3.2),
                                     moving_obstacles=2, pedestrians=3, pedestrian_model="social_force")
    assert world.moving_obstacle_count == 2 and world.pedestrians.count == 3
    assert world.pedestrians.scenario == "free_space" and world.pedestrians.area == (world.arena.x_range,
                                                                                      world.arena.y_range)
    walls = [g for g in world.obstacles if not g.moving]
    for g in (g for g in world.obstacles if g.moving):
        (lx, ly), (hx, hy) = g.motion.extent()
        for w in walls:  # the box's whole sweep clears every wall
            (cx, cy), (wx, wy) = w.motion.at, w.half_size
            assert lx - 0.25 >= cx + wx or hx + 0.25 <= cx - wx or ly - 0.25 >= cy + wy or hy + 0.25 <= cy - wy


@pytest.mark.parametrize("change, message", [
    (dict(start=(-1.95, 3.0)), "the start .* is not free"),
    (dict(start=(-0.5, 3.2), target=(3.0, 3.2), door=False), "no free way from the start"),
    (dict(start=(-0.5, 3.2), target=(-0.3, 3.2)), "less than .* from the start"),
    (dict(targets=0), "targets must be 1 or more"),
    (dict(moving_obstacles=31), "moving_obstacles must be an integer from 0 to 30"),
    (dict(pedestrian_model="zombie"), "pedestrian_model must be one of"),
    (dict(start=(-0.5, 3.2), target_distance=(30.0, 40.0)), "no free place reachable from the start"),
])
def test_bad_options_are_one_line_errors_naming_the_map(tmp_path, change, message):
    door = change.pop("door", True)
    path = draw(tmp_path, two_rooms(door))
    with pytest.raises(MapError, match=message) as info:
        World.from_occupancy_map(path, **change)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_a_map_larger_than_the_scene_is_refused(tmp_path):
    Image.new("L", (410, 20), FREE).save(tmp_path / "long.png")  # 41 m at 0.1 m
    (tmp_path / "long.yaml").write_text("image: long.png\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    with pytest.raises(MapError, match=r"long.yaml: the map is 41 m x 2 m; the scene holds maps up to 40 m"):
        World.from_occupancy_map(tmp_path / "long.yaml")


def test_the_office_floor_plays_and_its_walls_are_where_the_lasers_read_them():
    """The shipped office: 16 m x 10 m from (-8, -5); the corridor runs along y = 0 between walls
    at y = -0.8 and 0.8, the east wall's inner face at x = 7.8. From (5, 0) facing east the front
    laser reads 2.8 m, the left (north) one 0.8 m."""
    env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Map-v1", start=(-6.0, 0.0), target=(6.0, 0.0), way=True))
    try:
        obs, _ = env.reset(seed=0)
        u = env.unwrapped
        assert obs.shape == (22 + 5 * 4,) and u.world.arena.size.tolist() == pytest.approx([16.0, 10.0])
        lasers = u.place_robot(5.0, 0.0, 0.0)[:16]
        assert lasers[0] == pytest.approx(2.8, abs=1e-3) and lasers[4] == pytest.approx(0.8, abs=1e-3)
        u.place_robot(-6.0, 0.0, 0.0)
        done, steps = False, 0
        while not done:  # straight east along the corridor to the target, 12 m less the reach
            _, _, terminated, truncated, info = env.step(0)
            done, steps = terminated or truncated, steps + 1
        assert info["success"] and abs(steps - (12.0 - 0.3) / 0.15) <= 1  # 78 steps of 0.15 m, give or take a rounding
    finally:
        env.close()
