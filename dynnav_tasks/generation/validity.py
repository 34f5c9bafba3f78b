"""The checks that make a generated world valid: clearance, a way through, a visible target.

Geometry (m). Static blocks sit on a lattice of 0.5 m cells from the arena's corner (0, 0);
cell (i, j) is the box [0.5 i, 0.5 i + 0.5] x [0.5 j, 0.5 j + 0.5]. The occupancy grid has
cells of ``GRID`` (0.1 m, five per block side, so grid cells never straddle a block's edge).

* **Clearance** (``clearance_grid``): for every grid cell centre, the exact distance to the
  nearest block or arena wall (each block stamps its distance field onto the grid), capped at
  0.55 m.
* **A way through** (``within_steps``): a cell is free for the robot when its clearance exceeds
  ``PATH_RADIUS`` = the robot's circumscribed radius (0.295 m) + a 0.05 m margin, so the
  robot fits there at every heading and may turn in place anywhere on the way. A
  breadth-first search from the start cell through free cells joined by their four side
  neighbours measures each cell's way in 0.1 m steps (at most 1.42 times the shortest
  way, as it moves along x and y only); the target is a cell it reaches, so a collision-free
  way through the static layout exists, and no longer than ``WorldSpec.target_distance``.
* **Start and target** (``START_RADIUS``): the start point's clearance exceeds
  ``PATH_RADIUS`` + 0.15 m, so the whole 0.2 m x 0.2 m start area (half diagonal 0.14 m) is
  free; a target's whole extent, inflated by ``PATH_RADIUS``, is clear of blocks and walls.
* **Moving obstacles**: a motion's extent (the rectangle its box centre can reach), inflated by
  ``EXCLUSION`` = box half size (0.25) + robot radius + 0.05 m, never touches the start area
  or the target's extent, so no moving box reaches the robot at the start or at the target;
  inflated by the box half size + 0.05 m it is clear of every block and wall.
* **A visible marker** (``marker_visible``, camera worlds): from the centre of the start
  area, the straight line from the lens (0.36 m up) to the top of the target's red marker
  (1.2 m up) passes over every block. The line climbs above the blocks' 0.5 m tops after a
  sixth of the way ((0.5 - 0.36) / (1.2 - 0.36)), so only blocks on that first sixth can hide
  the marker; that part of the line is tested exactly against every block (a slab test). A
  moving target passes the test at its extent's centre and at its four corners.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from ..scene import TARGET_MARKER
from .spec import BLOCK, BLOCK_HALF, CAMERA_HEIGHT, ROBOT_RADIUS

GRID = 0.1
"""side (m) of an occupancy grid cell"""
CELLS_PER_BLOCK = 5
PATH_RADIUS = ROBOT_RADIUS + 0.05
"""clearance (m) a grid cell needs to be on the robot's way"""
START_HALF = 0.1
"""half side (m) of the square start area"""
START_RADIUS = PATH_RADIUS + math.hypot(START_HALF, START_HALF) + 0.01
"""clearance (m) of a start point: the whole start area is at least ``PATH_RADIUS`` clear"""
OBSTACLE_MARGIN = 0.05
"""gap (m) a moving box keeps from blocks and walls"""
EXCLUSION = BLOCK_HALF + ROBOT_RADIUS + 0.05
"""distance (m) every moving box's centre keeps from the start area and the target's extent"""
BLOCK_HEIGHT = 0.5
SIGHT_FRACTION = (BLOCK_HEIGHT - CAMERA_HEIGHT) / (TARGET_MARKER.height - CAMERA_HEIGHT)
"""fraction of the way to the marker after which the line of sight is above every block"""

_CROSS = ndimage.generate_binary_structure(2, 1)  # the four side neighbours
_STAMP_REACH = int(math.ceil(START_RADIUS / GRID)) + 1  # grid cells a block's distance field reaches out


def _stamp() -> np.ndarray:
    """Distance (m) from each grid cell centre around one block to the block's box."""
    u = np.arange(-_STAMP_REACH, CELLS_PER_BLOCK + _STAMP_REACH) + 0.5
    d = np.maximum(0.0, np.maximum(-u, u - CELLS_PER_BLOCK)) * GRID
    return np.hypot(d[:, None], d[None, :])


_STAMP = _stamp()
_CAP = (_STAMP_REACH - 0.5) * GRID  # every clearance below this is exact


def grid_shape(size: tuple[float, float]) -> tuple[int, int]:
    """Grid cells (x, y) wholly inside an arena of ``size`` (m)."""
    return int(math.floor(size[0] / GRID + 1e-9)), int(math.floor(size[1] / GRID + 1e-9))


def cell_center(index: int, shape: tuple[int, int]) -> tuple[float, float]:
    """Centre (m) of the grid cell with flat (row-major, x first) ``index``."""
    i, j = divmod(int(index), shape[1])
    return round((i + 0.5) * GRID, 3), round((j + 0.5) * GRID, 3)


def clearance_grid(blocks: np.ndarray, size: tuple[float, float]) -> np.ndarray:
    """Distance (m) from each grid cell centre to the nearest block or wall (exact below about
    0.55 m, capped there). ``blocks`` is the boolean block lattice, shape (nx, ny)."""
    gx, gy = grid_shape(size)
    x = (np.arange(gx) + 0.5) * GRID
    y = (np.arange(gy) + 0.5) * GRID
    wall_x = np.minimum(x, size[0] - x)
    wall_y = np.minimum(y, size[1] - y)
    grid = np.minimum(np.minimum(wall_x[:, None], wall_y[None, :]), _CAP)
    side, reach = _STAMP.shape[0], _STAMP_REACH
    for i, j in np.argwhere(blocks).tolist():
        a, c = CELLS_PER_BLOCK * i - reach, CELLS_PER_BLOCK * j - reach
        a0, c0, b, d = max(a, 0), max(c, 0), min(a + side, gx), min(c + side, gy)
        if a0 < b and c0 < d:
            window = grid[a0:b, c0:d]
            np.minimum(window, _STAMP[a0 - a:b - a, c0 - c:d - c], out=window)
    return grid


def within_steps(clearance: np.ndarray, start: tuple[int, int], steps: int) -> np.ndarray:
    """The cells whose shortest way from cell ``start`` is at most ``steps`` grid steps (0.1 m
    each) through free cells (clearance above ``PATH_RADIUS``) joined by their four side
    neighbours: a breadth-first search, run as ``steps`` dilations of the start confined to
    the free cells (scipy's ``binary_dilation`` with a mask)."""
    free = clearance > PATH_RADIUS
    reached = np.zeros_like(free)
    if not free[start]:
        return reached
    reached[start] = True
    if steps < 1:  # binary_dilation reads iterations=0 as "until nothing changes"
        return reached
    return ndimage.binary_dilation(reached, structure=_CROSS, iterations=int(steps), mask=free)


class BlockIndex:
    """Constant-time 'does this rectangle overlap a block?' over the block lattice."""

    def __init__(self, blocks: np.ndarray, size: tuple[float, float]):
        nx, ny = blocks.shape
        table = np.zeros((nx + 1, ny + 1), dtype=np.int64)
        table[1:, 1:] = blocks.cumsum(0).cumsum(1)
        self._table = table.tolist()
        self._n = (nx, ny)
        self.size = size
        self.centers = (np.argwhere(blocks) * BLOCK + BLOCK_HALF).astype(np.float64)
        """(n, 2) centres of the blocks, in lattice order (x index, then y index)"""

    def overlaps(self, low: tuple[float, float], high: tuple[float, float]) -> bool:
        """Whether the open rectangle ``low``-``high`` (m) overlaps a block."""
        nx, ny = self._n
        i0, j0 = max(math.floor(low[0] / BLOCK), 0), max(math.floor(low[1] / BLOCK), 0)
        i1, j1 = min(math.ceil(high[0] / BLOCK), nx), min(math.ceil(high[1] / BLOCK), ny)
        if i0 >= i1 or j0 >= j1:
            return False
        t = self._table
        return t[i1][j1] - t[i0][j1] - t[i1][j0] + t[i0][j0] > 0

    def clear(self, low, high, margin: float) -> bool:
        """Whether the rectangle ``low``-``high`` grown by ``margin`` misses every block and
        stays ``margin`` inside the walls."""
        lo = (low[0] - margin, low[1] - margin)
        hi = (high[0] + margin, high[1] + margin)
        if lo[0] < 0 or lo[1] < 0 or hi[0] > self.size[0] or hi[1] > self.size[1]:
            return False
        return not self.overlaps(lo, hi)


def rects_apart(low_a, high_a, low_b, high_b, gap: float) -> bool:
    """Whether two rectangles are more than ``gap`` apart (m, Euclidean)."""
    dx = max(low_b[0] - high_a[0], low_a[0] - high_b[0], 0.0)
    dy = max(low_b[1] - high_a[1], low_a[1] - high_b[1], 0.0)
    return dx * dx + dy * dy > gap * gap


def marker_visible(block_centers: np.ndarray, camera: tuple[float, float], target: tuple[float, float]) -> bool:
    """Whether the line from a lens at ``camera`` to the top of a marker at ``target`` passes
    over every block (see the module docstring)."""
    if len(block_centers) == 0:
        return True
    p = np.asarray(camera, dtype=np.float64)
    d = (np.asarray(target, dtype=np.float64) - p) * SIGHT_FRACTION  # the part that can hit a block
    low, high = block_centers - BLOCK_HALF - p, block_centers + BLOCK_HALF - p
    t_in, t_out = np.zeros(len(block_centers)), np.ones(len(block_centers))
    for k in range(2):
        if d[k] == 0.0:
            inside = (low[:, k] < 0.0) & (high[:, k] > 0.0)
            t_out = np.where(inside, t_out, -1.0)
        else:
            a, b = low[:, k] / d[k], high[:, k] / d[k]
            t_in = np.maximum(t_in, np.minimum(a, b))
            t_out = np.minimum(t_out, np.maximum(a, b))
    return not bool(np.any(t_in < t_out))
