"""``generate_world(spec, world_seed)``: one valid ``World`` per (spec, seed), the same everywhere.

An attempt draws, in this order, from one numpy ``Generator(PCG64)`` seeded by
``SeedSequence([world_seed, attempt])`` (integers only: no Python ``hash``, no iteration over
sets or dicts):

1. the arena's sides (multiples of 0.1 m in ``spec.arena_size``), the layout and the clutter
   density, then the layout's blocks (``layouts.py``);
2. the start point: a uniform grid cell with ``START_RADIUS`` of clearance; the start area is
   the 0.2 m x 0.2 m square around it, headings uniform in [-pi, pi);
3. the target: static or moving (``spec.target_motion``), centred on a uniform grid cell
   whose way from the start (``validity.within_steps``) is ``spec.target_distance`` long, its
   whole extent ``PATH_RADIUS`` clear of blocks and walls, at least 0.6 m from the start area,
   and in camera worlds with its marker visible from the start; up to ``TARGET_TRIES`` cells;
4. the moving obstacles: a count in ``spec.moving_obstacles``; per group a model of
   ``spec.motion_mix`` placed by ``moving.place_obstacle``;
5. only when ``spec.pedestrians`` allows some: their count and their model. They are drawn
   last, so a spec with pedestrians gives the same layout, start, target and boxes as the
   spec without them; the crowd (scenario "free_space" in the arena) places them at each reset.

The checks of ``validity.py`` hold by construction. An attempt that cannot complete a step
(no start cell, no target cell, an obstacle that fits nowhere) is dropped and the next
attempt, with the next derived seed, starts over; after ``MAX_ATTEMPTS`` a ``GenerationError``
names the field that failed most often. (Dropping attempts favours, a little, the draws in
which everything fits: e.g. corridors with room for the obstacles' motions.) The world lists
every static block as its own ``Obstacles`` group (in lattice order), then the moving
groups; all numbers are Python floats rounded to the millimetre.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..crowd.crowd import Pedestrians
from ..motion import Static
from ..world import Arena, Obstacles, StartArea, World
from .layouts import build_layout
from .moving import extent_of, place_obstacle, target_motion
from .spec import BLOCK, BLOCK_HALF, GenerationError, WorldSpec
from .validity import (
    GRID, PATH_RADIUS, START_HALF, START_RADIUS, BlockIndex, cell_center, clearance_grid, marker_visible,
    rects_apart, within_steps,
)

MAX_ATTEMPTS = 64
"""attempts (derived seeds) before a spec is declared impossible"""
TARGET_TRIES = 24
"""target cells tried per attempt"""
TARGET_START_GAP = 0.6
"""least distance (m) between the start area and a target's extent: twice the reach radius"""
MAX_WORLD_SEED = 2**64 - 1
"""largest world seed"""


def generate_world(spec: WorldSpec, world_seed: int) -> World:
    """The world of ``spec`` for ``world_seed`` (an integer in [0, 2**64)); see the module
    docstring. Raises ``GenerationError`` for a bad spec or seed, or a spec no world fits."""
    if not isinstance(spec, WorldSpec):
        raise GenerationError(f"spec must be a WorldSpec (see spec_for); got {type(spec).__name__}", "spec")
    if isinstance(world_seed, (bool, np.bool_)) or not isinstance(world_seed, numbers.Integral) \
            or not 0 <= int(world_seed) <= MAX_WORLD_SEED:
        raise GenerationError(f"world_seed must be an integer from 0 to 2**64 - 1; got {world_seed!r}", "world_seed")
    failures: dict[str, int] = {}
    for attempt in range(MAX_ATTEMPTS):
        rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([int(world_seed), attempt])))
        result = _attempt(spec, rng)
        if isinstance(result, World):
            return result
        failures[result] = failures.get(result, 0) + 1
    field = max(failures, key=failures.get)
    raise GenerationError(
        f"no valid world for this spec from world_seed {world_seed} in {MAX_ATTEMPTS} attempts "
        f"(failed steps: {failures}); relax WorldSpec.{field}: {spec}", field,
    )


def _side(rng: np.random.Generator, bounds: tuple[float, float]) -> float:
    """A multiple of 0.1 m in ``bounds`` (``bounds[0]`` if none is)."""
    k_lo, k_hi = math.ceil(bounds[0] * 10 - 1e-9), math.floor(bounds[1] * 10 + 1e-9)
    if k_lo > k_hi:
        return round(float(bounds[0]), 3)
    return round((k_lo + int(rng.integers(k_hi - k_lo + 1))) / 10, 1)


def _attempt(spec: WorldSpec, rng: np.random.Generator) -> World | str:
    """One attempt: the world, or the name of the spec field whose step failed."""
    size = (_side(rng, spec.arena_size), _side(rng, spec.arena_size))
    layout = spec.layout[int(rng.integers(len(spec.layout)))]
    density = spec.layout_density[0] + (spec.layout_density[1] - spec.layout_density[0]) * float(rng.random())
    lattice = (int(math.floor(size[0] / BLOCK + 1e-9)), int(math.floor(size[1] / BLOCK + 1e-9)))
    blocks, _ = build_layout(layout, lattice, density, rng)
    clearance = clearance_grid(blocks, size)
    starts = np.flatnonzero(clearance > START_RADIUS)
    if len(starts) == 0:
        return "layout_density"
    start_cell = int(starts[rng.integers(len(starts))])
    start = cell_center(start_cell, clearance.shape)
    start_rect = (
        (round(start[0] - START_HALF, 3), round(start[1] - START_HALF, 3)),
        (round(start[0] + START_HALF, 3), round(start[1] + START_HALF, 3)),
    )
    index = BlockIndex(blocks, size)
    target = _target(spec, rng, clearance, start_cell, start, start_rect, index)
    if target is None:
        return "target_distance"
    keep_away = (start_rect, extent_of(target))
    moving, left = [], int(spec.moving_obstacles[0] + rng.integers(spec.moving_obstacles[1] - spec.moving_obstacles[0] + 1))
    while left > 0:
        model = spec.motion_mix[int(rng.integers(len(spec.motion_mix)))]
        count = 2 if model == "route" and left >= 2 and rng.integers(2) else 1
        motion = place_obstacle(model, count, spec.relative_speed, index, keep_away, rng)
        if motion is None:
            return "moving_obstacles"
        moving.append(Obstacles(half_size=(BLOCK_HALF, BLOCK_HALF), motion=motion))
        left -= count
    pedestrians = None
    if spec.pedestrians[1] > 0:
        count = int(spec.pedestrians[0] + rng.integers(spec.pedestrians[1] - spec.pedestrians[0] + 1))
        model = spec.pedestrian_model[int(rng.integers(len(spec.pedestrian_model)))]
        if count:
            pedestrians = Pedestrians(count, model, "free_space", area=((0.0, size[0]), (0.0, size[1])))
    statics = tuple(
        Obstacles(half_size=(BLOCK_HALF, BLOCK_HALF), motion=Static((x, y))) for x, y in index.centers.tolist()
    )
    return World(
        targets=(target,),
        obstacles=statics + tuple(moving),
        arena=Arena(x_range=(0.0, size[0]), y_range=(0.0, size[1])),
        start=StartArea(x_range=(start_rect[0][0], start_rect[1][0]), y_range=(start_rect[0][1], start_rect[1][1])),
        target_marker=spec.camera,
        pedestrians=pedestrians,
    )


def _target(spec, rng, clearance, start_cell, start, start_rect, index):
    """The target's motion (see step 3 of the module docstring), or None."""
    moving = spec.target_motion[int(rng.integers(len(spec.target_motion)))] == "moving"
    low, high = spec.target_distance
    cell = np.unravel_index(start_cell, clearance.shape)
    far = within_steps(clearance, cell, int(math.floor(high / GRID + 1e-9)))
    near = within_steps(clearance, cell, int(math.ceil(low / GRID - 1e-9)) - 1)
    candidates = np.flatnonzero(far & ~near)
    if len(candidates) == 0:
        return None
    for _ in range(TARGET_TRIES):
        center = cell_center(int(candidates[rng.integers(len(candidates))]), clearance.shape)
        motion = target_motion(center, rng) if moving else Static(center)
        low_xy, high_xy = extent_of(motion)
        if moving and not index.clear(low_xy, high_xy, PATH_RADIUS):
            continue
        if not rects_apart(low_xy, high_xy, *start_rect, TARGET_START_GAP):
            continue
        if spec.camera:
            points = (center, low_xy, high_xy, (low_xy[0], high_xy[1]), (high_xy[0], low_xy[1]))
            if not all(marker_visible(index.centers, start, p) for p in points):
                continue
        return motion
    return None
