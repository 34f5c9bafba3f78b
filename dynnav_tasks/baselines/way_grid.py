"""The way to a target through a world's static layout, on an occupancy grid (for planners).

``WayGrid(world, clearance)`` lays a grid of ``cell`` (0.1 m) over the arena and marks a cell
free when its centre is at least ``clearance - cell / sqrt(2)`` from every wall and static
box: any point the robot's centre may occupy (``clearance`` from everything) lies in a free
cell, so the grid never shuts a way the robot has. ``to(target)`` runs Dijkstra from the
target's cell over the free cells and their eight neighbours and gives a ``WayField``: for
every point, the length of the way to the target (``distance``) and the direction in which
that way leaves (``aim``: towards the point ``AIM_AHEAD`` further along it). A field is
computed once per target cell and kept.

``StaticBuckets`` answers "which static boxes can come within ``clearance`` of this point?"
with the few boxes of a 0.5 m bucket, so that a collision check in a world of many blocks
looks at a handful of them instead of all.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

CELL = 0.1
"""side (m) of a grid cell"""
AIM_AHEAD = 5
"""cells along the way to the point ``WayField.aim`` points at (0.5 m, about three forward steps)"""
BUCKET = 0.5
"""side (m) of a ``StaticBuckets`` bucket"""


def static_boxes(world) -> list[tuple[float, float, float, float]]:
    """(lo_x, lo_y, hi_x, hi_y) of every static obstacle box of ``world``."""
    boxes = []
    for g in world.obstacles:
        if not g.moving:
            c, h = np.asarray(g.motion.at, float), np.asarray(g.half_size, float)
            boxes.append((*(c - h).tolist(), *(c + h).tolist()))
    return boxes


class StaticBuckets:
    """The static boxes near each 0.5 m bucket of the arena (see the module docstring)."""

    def __init__(self, boxes, x_range, y_range, clearance: float):
        self.x0, self.y0 = float(x_range[0]), float(y_range[0])
        self.nx = max(1, math.ceil((x_range[1] - x_range[0]) / BUCKET))
        self.ny = max(1, math.ceil((y_range[1] - y_range[0]) / BUCKET))
        self.buckets = [[[] for _ in range(self.ny)] for _ in range(self.nx)]
        for box in boxes:  # every bucket within ``clearance`` of the box
            lx, ly, hx, hy = box
            i0, i1 = self._index(lx - clearance, self.x0, self.nx), self._index(hx + clearance, self.x0, self.nx)
            j0, j1 = self._index(ly - clearance, self.y0, self.ny), self._index(hy + clearance, self.y0, self.ny)
            for i in range(i0, i1 + 1):
                for j in range(j0, j1 + 1):
                    self.buckets[i][j].append(box)

    @staticmethod
    def _index(v: float, origin: float, n: int) -> int:
        return min(max(int(math.floor((v - origin) / BUCKET)), 0), n - 1)

    def near(self, x: float, y: float) -> list:
        """The boxes that may come within the clearance of (x, y); every other box is farther."""
        return self.buckets[self._index(x, self.x0, self.nx)][self._index(y, self.y0, self.ny)]


class WayField:
    """Way lengths (m) to one target from every grid cell, and the direction each way leaves."""

    def __init__(self, grid: "WayGrid", target: tuple[float, float], distance: np.ndarray, aim_xy: np.ndarray):
        self._grid, self.target = grid, target
        finite = np.isfinite(distance)
        unreachable = (distance[finite].max() if finite.any() else 0.0) + grid.diagonal
        self._distance = np.where(finite, distance, unreachable)  # a closed-off cell: worse than any
        self._aim = aim_xy
        if grid.lists:  # [i][j] reads the same from lists and arrays; lists are faster per read
            self._distance, self._aim = self._distance.tolist(), self._aim.tolist()

    def distance(self, x: float, y: float) -> float:
        """Length (m) of the way from (x, y) to the target through the static layout: the
        cell's way, corrected by how far (x, y) lies from the cell centre along the way's
        direction (so that it changes smoothly within a cell)."""
        i, j = self._grid.cell_of(x, y)
        d = float(self._distance[i][j])
        ax, ay = self._aim[i][j]
        cx, cy = self._grid.center(i, j)
        dx, dy = ax - cx, ay - cy
        n = math.hypot(dx, dy)
        if n == 0.0:  # a cell no way leaves (closed off)
            return d
        return max(d - ((x - cx) * dx + (y - cy) * dy) / n, 0.0)

    def aim(self, x: float, y: float) -> tuple[float, float]:
        """The point (x, y) should head for: ``AIM_AHEAD`` cells further along its way (the
        target itself when the way ends sooner)."""
        i, j = self._grid.cell_of(x, y)
        return tuple(float(v) for v in self._aim[i][j])


class WayGrid:
    """The arena's occupancy grid of static boxes and walls, inflated by ``clearance``."""

    def __init__(self, world, clearance: float, cell: float = CELL, lists: bool = True):
        arena = world.arena
        self.cell = cell
        self.lists = lists
        """whether each ``WayField`` keeps its grids as Python lists (faster per lookup, for a search
        that makes thousands per step; building them costs a few milliseconds) or as numpy arrays"""
        self.x0, self.y0 = float(arena.x_range[0]), float(arena.y_range[0])
        self.nx = max(1, int(math.ceil((arena.x_range[1] - self.x0) / cell - 1e-9)))
        self.ny = max(1, int(math.ceil((arena.y_range[1] - self.y0) / cell - 1e-9)))
        self.diagonal = math.hypot(arena.x_range[1] - self.x0, arena.y_range[1] - self.y0)
        xs = self.x0 + (np.arange(self.nx) + 0.5) * cell
        ys = self.y0 + (np.arange(self.ny) + 0.5) * cell
        gap = np.minimum(np.minimum(xs - self.x0, arena.x_range[1] - xs)[:, None],
                         np.minimum(ys - self.y0, arena.y_range[1] - ys)[None, :])
        need = clearance - cell / math.sqrt(2)
        for lx, ly, hx, hy in static_boxes(world):
            # only cells nearer than ``need`` can change from free to occupied: look at the box's window
            i0, i1 = np.searchsorted(xs, lx - need), np.searchsorted(xs, hx + need, side="right")
            j0, j1 = np.searchsorted(ys, ly - need), np.searchsorted(ys, hy + need, side="right")
            if i0 >= i1 or j0 >= j1:
                continue
            wx, wy = xs[i0:i1], ys[j0:j1]
            dx = np.maximum(np.maximum(lx - wx, wx - hx), 0.0)
            dy = np.maximum(np.maximum(ly - wy, wy - hy), 0.0)
            np.minimum(gap[i0:i1, j0:j1], np.hypot(dx[:, None], dy[None, :]), out=gap[i0:i1, j0:j1])
        self.free = gap >= need
        """(nx, ny) cells the robot's centre may be in"""
        self._fields: dict[tuple[int, int], WayField] = {}

    def cell_of(self, x: float, y: float) -> tuple[int, int]:
        """Indices of the cell holding (x, y) (the nearest border cell for a point outside)."""
        i = min(max(int((x - self.x0) // self.cell), 0), self.nx - 1)
        j = min(max(int((y - self.y0) // self.cell), 0), self.ny - 1)
        return i, j

    def center(self, i: int, j: int) -> tuple[float, float]:
        """Centre (m) of cell (i, j)."""
        return self.x0 + (i + 0.5) * self.cell, self.y0 + (j + 0.5) * self.cell

    def line_free(self, a, b) -> bool:
        """Whether every point of the segment from ``a`` to ``b`` (x, y) lies in a free cell
        (tested every half cell, from ``a`` on, stopping at the first occupied cell)."""
        ax, ay = float(a[0]), float(a[1])
        dx, dy = float(b[0]) - ax, float(b[1]) - ay
        n = max(1, int(math.ceil(math.hypot(dx, dy) / (self.cell / 2))))
        step, x0, y0, cell = 1.0 / n, self.x0, self.y0, self.cell
        last_i, last_j, rows = self.nx - 1, self.ny - 1, self._free_rows
        for k in range(n + 1):
            t = k * step if k < n else 1.0  # the points of np.linspace(0, 1, n + 1)
            i = min(max(int((ax + dx * t - x0) // cell), 0), last_i)
            j = min(max(int((ay + dy * t - y0) // cell), 0), last_j)
            if not rows[i][j]:
                return False
        return True

    @cached_property
    def _free_rows(self) -> list[list[bool]]:
        """``free`` as lists (a read per point of a segment; lists are faster per read than arrays)."""
        return self.free.tolist()

    @cached_property
    def _graph(self):
        """The free cells' neighbour graph, built for the first way asked for."""
        return self._neighbour_graph()

    def _neighbour_graph(self):
        """Sparse graph of the free cells: edges to the eight neighbours, of their length; a
        diagonal only where both cells beside it are free (no cutting of a blocked corner)."""
        n, free, rows, cols, weights = self.nx * self.ny, self.free, [], [], []
        index = np.arange(n).reshape(self.nx, self.ny)
        for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
            a = (slice(0, self.nx - di), slice(max(-dj, 0), self.ny - max(dj, 0)))  # cell (i, j)
            b = (slice(di, self.nx), slice(max(dj, 0), self.ny - max(-dj, 0)))  # its neighbour (i + di, j + dj)
            ok = free[a] & free[b]
            if di and dj:
                ok &= free[b[0], a[1]] & free[a[0], b[1]]
            rows.append(index[a][ok])
            cols.append(index[b][ok])
            weights.append(np.full(int(ok.sum()), self.cell * math.hypot(di, dj)))
        r, c, w = np.concatenate(rows), np.concatenate(cols), np.concatenate(weights)
        return coo_matrix((np.concatenate([w, w]), (np.concatenate([r, c]), np.concatenate([c, r]))),
                          shape=(n, n)).tocsr()

    def to(self, target) -> WayField:
        """The ``WayField`` to ``target`` (x, y), computed on first use for its cell."""
        tx, ty = float(target[0]), float(target[1])
        key = self.cell_of(tx, ty)
        field = self._fields.get(key)
        if field is None:
            field = self._fields[key] = self._field(key, (tx, ty))
        return field

    def _field(self, key, target) -> WayField:
        start = self._nearest_free(key)
        distance, previous = dijkstra(self._graph, indices=start[0] * self.ny + start[1], return_predecessors=True)
        distance = distance.reshape(self.nx, self.ny) + math.hypot(*(np.subtract(self.center(*start), target)))
        ahead = np.arange(self.nx * self.ny)
        for _ in range(AIM_AHEAD):  # follow the way AIM_AHEAD cells towards the target
            ahead = np.where(previous[ahead] >= 0, previous[ahead], ahead)
        i, j = np.divmod(ahead, self.ny)
        aim = np.stack([self.x0 + (i + 0.5) * self.cell, self.y0 + (j + 0.5) * self.cell], axis=1)
        aim[ahead == start[0] * self.ny + start[1]] = target  # the way ends at the target
        return WayField(self, target, distance, aim.reshape(self.nx, self.ny, 2))

    def _nearest_free(self, key) -> tuple[int, int]:
        if self.free[key] or not self.free.any():
            return key
        cells = np.argwhere(self.free)
        return tuple(int(v) for v in cells[np.argmin(((cells - np.array(key)) ** 2).sum(1))])
