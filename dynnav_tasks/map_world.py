"""A ``World`` from a building's occupancy map: ``World.from_occupancy_map(path, ...)``.

The map (``occupancy_map.read_map``: a ``map_server`` YAML and its PGM or PNG) becomes the
arena, its extent from the map's origin, and its occupied and unknown cells become static boxes
(``occupancy_map.merge_boxes``: few rectangles, each covering whole cells). Then, with the
checks the generated worlds pass (``generation.validity``'s radii):

* **the start**: given as (x, y), or drawn (``seed``) among the places where the robot has
  ``START_RADIUS`` (0.495 m) clear around it, in the largest region it can drive through; the
  start area is the 0.2 m x 0.2 m square around it, any heading. A given start that is not
  that clear is an error.
* **the targets**: given as (x, y) (one target), or ``targets`` of them drawn among the places
  whose way from the start through the map (on a grid inflated by ``PATH_RADIUS``, 0.345 m) is
  ``target_distance`` long; every episode plays one of them (the task draws it). A target the
  robot cannot reach from the start, or nearer the start than 0.6 m, is an error.
* **moving boxes** (``moving_obstacles``): 0.5 m boxes on the generator's motion models
  (``generation.moving.place_obstacle``: back and forth, routes, at random in rectangles, at
  0.3-1 times the robot's speed), clear of the map's boxes and away from the start and every
  target as in generated worlds.
* **pedestrians** (``pedestrians``): walkers in the map's free space (``crowd``'s
  ``free_space`` scenario), moved by ``pedestrian_model``.

Everything is drawn from ``numpy.random.default_rng(seed)``, so a map, its options and a seed
give the same world everywhere. Bad input is a ``MapError`` naming the file and what is wrong:
a missing image, a resolution <= 0, a map larger than ``MAX_MAP_SIDE`` or with more than
``MAX_MAP_BOXES`` boxes, a start or target that is not free, no way from the start to a target.
"""

from __future__ import annotations

import math
import numbers
from pathlib import Path
from typing import Optional, Sequence

import numpy as np
from scipy import ndimage

from .baselines.way_grid import WayGrid
from .crowd.crowd import MODELS, Pedestrians
from .generation.generator import TARGET_START_GAP
from .generation.moving import place_obstacle
from .generation.spec import BLOCK_HALF, MAX_MOVING_OBSTACLES, MAX_PEDESTRIANS, MOTIONS
from .generation.validity import PATH_RADIUS, START_HALF, START_RADIUS
from .motion import BackAndForth, Motion, RandomInRect, Route, Static
from .occupancy_map import MapError, merge_boxes, read_map
from .world import Arena, Obstacles, StartArea, World, install_map_reader

MAX_MAP_SIDE = 40.0
"""metres: the longest side of a map the scene holds"""
MAX_MAP_BOXES = 3000
"""the most boxes a map may merge into"""
TARGET_DISTANCE = (2.0, 20.0)
"""metres: the range of a drawn target's way from the start, unless told otherwise"""
RELATIVE_SPEED = (0.3, 1.0)
"""the moving boxes' speeds, in robot forward steps (the medium difficulty's)"""
PLACEMENT_ROUNDS = 20
"""models drawn for one moving obstacle (each tried as the generator tries) before giving up"""
WALL_HEIGHT = 0.5
"""metres: the height of the map's boxes (the lasers' plane and the camera see them)"""


class _MapIndex:
    """``generation.moving``'s view of the map's boxes, in coordinates from the arena's corner."""

    def __init__(self, boxes: np.ndarray, origin: tuple[float, float], size: tuple[float, float]):
        self._boxes, self._origin, self.size = boxes, origin, size

    def clear(self, low, high, margin: float) -> bool:
        """Whether the rectangle ``low``-``high`` grown by ``margin`` misses every box and stays
        inside the arena."""
        lo = (low[0] - margin, low[1] - margin)
        hi = (high[0] + margin, high[1] + margin)
        if lo[0] < 0 or lo[1] < 0 or hi[0] > self.size[0] or hi[1] > self.size[1]:
            return False
        b, (ox, oy) = self._boxes, self._origin
        overlap = (b[:, 0] < hi[0] + ox) & (b[:, 2] > lo[0] + ox) & (b[:, 1] < hi[1] + oy) & (b[:, 3] > lo[1] + oy)
        return not bool(overlap.any())


def _shift(motion: Motion, dx: float, dy: float) -> Motion:
    """``motion`` moved by (dx, dy) (the generator places motions from the arena's corner)."""
    def r(v: float) -> float:
        return round(float(v), 3)

    if isinstance(motion, BackAndForth):
        return BackAndForth(center=(r(motion.center[0] + dx), r(motion.center[1] + dy)), direction=motion.direction,
                            amplitude=motion.amplitude, speed=motion.speed)
    if isinstance(motion, Route):
        return Route(waypoints=tuple((r(x + dx), r(y + dy)) for x, y in motion.waypoints),
                     speed_range=motion.speed_range, count=motion.count)
    return RandomInRect(x_range=(r(motion.x_range[0] + dx), r(motion.x_range[1] + dx)),
                        y_range=(r(motion.y_range[0] + dy), r(motion.y_range[1] + dy)), speed_range=motion.speed_range)


def _point(value, name: str, source: str) -> Optional[tuple[float, float]]:
    if value is None:
        return None
    if not (isinstance(value, (list, tuple)) and len(value) == 2 and all(
            isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v) for v in value)):
        raise MapError(f"{source}: {name} must be an (x, y) point in metres, got {value!r}")
    return float(value[0]), float(value[1])


def _count(value, name: str, high: int, source: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not 0 <= value <= high:
        raise MapError(f"{source}: {name} must be an integer from 0 to {high}, got {value!r}")
    return int(value)


def world_from_map(path: str | Path, start: Optional[Sequence[float]] = None, target: Optional[Sequence[float]] = None,
                   targets: int = 8, seed: int = 0, moving_obstacles: int = 0, pedestrians: int = 0,
                   pedestrian_model: str = "orca",
                   target_distance: tuple[float, float] = TARGET_DISTANCE) -> World:
    """The world of the occupancy map ``path`` (module docstring)."""
    source = str(path)
    start, target = _point(start, "start", source), _point(target, "target", source)
    targets = _count(targets, "targets", 64, source)
    if target is None and targets < 1:
        raise MapError(f"{source}: targets must be 1 or more when no target is given, got {targets}")
    moving_obstacles = _count(moving_obstacles, "moving_obstacles", MAX_MOVING_OBSTACLES, source)
    pedestrians = _count(pedestrians, "pedestrians", MAX_PEDESTRIANS, source)
    if pedestrian_model not in MODELS:
        raise MapError(f"{source}: pedestrian_model must be one of {', '.join(MODELS)}, got {pedestrian_model!r}")
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise MapError(f"{source}: seed must be a non-negative integer, got {seed!r}")
    low, high = (float(v) for v in target_distance)
    if not 0.0 < low <= high:
        raise MapError(f"{source}: target_distance must be a (low, high) range with 0 < low <= high, got {target_distance!r}")

    grid_map = read_map(path)
    width, height = grid_map.size
    if max(width, height) > MAX_MAP_SIDE + 1e-9:
        raise MapError(f"{source}: the map is {width:g} m x {height:g} m; the scene holds maps up to "
                       f"{MAX_MAP_SIDE:g} m a side (crop the image or raise its resolution's cell size)")
    rects = merge_boxes(grid_map.occupied)
    if len(rects) > MAX_MAP_BOXES:
        raise MapError(f"{source}: the map's occupied cells merge into {len(rects)} boxes, more than the "
                       f"{MAX_MAP_BOXES} a scene holds (clean up speckles or coarsen the map)")
    x0, y0 = grid_map.origin
    arena = Arena(x_range=(x0, x0 + width), y_range=(y0, y0 + height))
    statics = tuple(Obstacles(half_size=half, motion=Static(center), height=WALL_HEIGHT)
                    for center, half in map(grid_map.box_of, rects))
    layout = World(targets=(Static(tuple(float(v) for v in arena.center)),), obstacles=statics, arena=arena)
    rng = np.random.default_rng(int(seed))

    paths = WayGrid(layout, PATH_RADIUS, lists=False)
    regions, _ = ndimage.label(paths.free)
    start = _start(layout, paths, regions, start, rng, source)
    region = regions[paths.cell_of(*start)]
    field = paths.to(start)
    if target is not None:
        if not _inside(arena, target) or regions[paths.cell_of(*target)] != region:
            raise MapError(f"{source}: no free way from the start {start} to the target {target} (the robot needs "
                           f"{PATH_RADIUS:g} m clear on each side of its way)")
        if math.dist(start, target) < TARGET_START_GAP + START_HALF:
            raise MapError(f"{source}: the target {target} is less than {TARGET_START_GAP + START_HALF:g} m from the "
                           f"start {start}")
        goals = [target]
    else:
        cells = np.argwhere(regions == region)
        centres = [paths.center(int(i), int(j)) for i, j in cells]
        far = [c for c in centres if low <= field.distance(*c) <= high
               and math.dist(c, start) >= TARGET_START_GAP + START_HALF]
        if not far:
            raise MapError(f"{source}: no free place reachable from the start {start} with a way of {low:g}-{high:g} m "
                           "(give another start, or a target_distance the map holds)")
        picks = rng.choice(len(far), size=min(targets, len(far)), replace=False)
        goals = [tuple(round(v, 3) for v in far[int(k)]) for k in picks]

    start_rect = ((start[0] - START_HALF, start[1] - START_HALF), (start[0] + START_HALF, start[1] + START_HALF))
    keep_away = (((start_rect[0][0] - x0, start_rect[0][1] - y0), (start_rect[1][0] - x0, start_rect[1][1] - y0)),) + \
        tuple(((gx - x0, gy - y0), (gx - x0, gy - y0)) for gx, gy in goals)
    index = _MapIndex(np.array([(c[0] - h[0], c[1] - h[1], c[0] + h[0], c[1] + h[1])
                                for c, h in map(grid_map.box_of, rects)], dtype=np.float64).reshape(-1, 4),
                      (x0, y0), (width, height))
    moving, left = [], moving_obstacles
    while left > 0:
        for _ in range(PLACEMENT_ROUNDS):  # a model that fits nowhere: draw another
            model = MOTIONS[int(rng.integers(len(MOTIONS)))]
            count = 2 if model == "route" and left >= 2 and rng.integers(2) else 1
            motion = place_obstacle(model, count, RELATIVE_SPEED, index, keep_away, rng)
            if motion is not None:
                break
        else:
            raise MapError(f"{source}: no room for moving obstacle {moving_obstacles - left + 1} of {moving_obstacles} "
                           "clear of the walls, the start and the targets; ask for fewer")
        moving.append(Obstacles(half_size=(BLOCK_HALF, BLOCK_HALF), motion=_shift(motion, x0, y0)))
        left -= count
    walkers = Pedestrians(pedestrians, pedestrian_model, "free_space", area=(arena.x_range, arena.y_range)) \
        if pedestrians else None
    return World(targets=tuple(Static(g) for g in goals), obstacles=statics + tuple(moving), arena=arena,
                 start=StartArea(x_range=(start[0] - START_HALF, start[0] + START_HALF),
                                 y_range=(start[1] - START_HALF, start[1] + START_HALF)),
                 pedestrians=walkers)


def _inside(arena: Arena, point) -> bool:
    return arena.x_range[0] <= point[0] <= arena.x_range[1] and arena.y_range[0] <= point[1] <= arena.y_range[1]


def _start(layout: World, paths: WayGrid, regions: np.ndarray, start, rng, source: str) -> tuple[float, float]:
    """The given start, checked, or one drawn in the largest region the robot can drive through."""
    roomy = WayGrid(layout, START_RADIUS, lists=False).free
    if start is not None:
        if not _inside(layout.arena, start) or not roomy[paths.cell_of(*start)]:
            raise MapError(f"{source}: the start {start} is not free: the robot needs {START_RADIUS:g} m clear "
                           "around it, inside the map")
        return start
    sizes = np.bincount(regions.ravel())
    sizes[0] = 0
    if sizes.max() == 0:
        raise MapError(f"{source}: the map has no free place the robot fits in ({PATH_RADIUS:g} m clear around it)")
    cells = np.argwhere(roomy & (regions == int(np.argmax(sizes))))
    if not len(cells):
        raise MapError(f"{source}: the map has no place with {START_RADIUS:g} m clear around it for the start")
    i, j = cells[int(rng.integers(len(cells)))]
    return tuple(round(v, 3) for v in paths.center(int(i), int(j)))


install_map_reader(world_from_map)
