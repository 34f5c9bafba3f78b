"""Static layouts as boolean block lattices: open, clutter, corridors, rooms.

A layout is drawn on the lattice of 0.5 m cells that starts at the arena's corner (0, 0):
``blocks[i, j]`` is a 0.5 m block on the cell [0.5 i, 0.5 i + 0.5] x [0.5 j, 0.5 j + 0.5].
Besides the blocks each builder returns ``keep_clear``, the cells clutter must leave empty
(doorways and the cells beside them), so scattered blocks never close a doorway.

* ``open``: no blocks.
* ``clutter``: single blocks and 1x2, 2x1 and 2x2 clusters at random cells until the given
  fraction of the cells is covered.
* ``corridors``: parallel walls (along x or along y, drawn) across the arena, 1.5-2.5 m
  apart, each with one or two doorways 1.0-1.5 m wide; then half the density as clutter.
* ``rooms``: walls across the arena every 3-5 m in both directions (at least one wall),
  making a grid of rooms; every wall between two neighbouring rooms has one doorway 1.0-1.5 m
  wide (so every room is reachable); then half the density as clutter.

Every draw comes from the given numpy ``Generator``; the number of draws depends only on the
lattice size and the values drawn, so a seed replays the layout exactly.
"""

from __future__ import annotations

import numpy as np

from .spec import MAX_STATIC_BLOCKS

CORRIDOR_WIDTH_CELLS = (3, 5)
"""free cells between two corridor walls (1.5-2.5 m)"""
ROOM_CELLS = (6, 10)
"""cells between two room walls (3-5 m)"""
DOOR_CELLS = (2, 3)
"""width of a doorway in cells (1.0-1.5 m)"""
_PIECES = ((1, 1), (1, 2), (2, 1), (2, 2))


def build_layout(name: str, shape: tuple[int, int], density: float, rng: np.random.Generator):
    """(blocks, keep_clear): boolean lattices of ``shape`` for layout ``name`` (see the module
    docstring); clutter covers ``density`` of the cells ("clutter") or half of it
    ("corridors", "rooms"); never more than ``MAX_STATIC_BLOCKS`` blocks."""
    blocks = np.zeros(shape, dtype=bool)
    keep = np.zeros(shape, dtype=bool)
    if name == "open":
        return blocks, keep
    if name == "corridors":
        _corridors(blocks, keep, rng)
        density /= 2
    elif name == "rooms":
        _rooms(blocks, keep, rng)
        density /= 2
    elif name != "clutter":
        raise ValueError(f"unknown layout {name!r}")
    _clutter(blocks, keep, density, rng)
    return blocks, keep


def _door(lo: int, hi: int, rng: np.random.Generator) -> tuple[int, int]:
    """A doorway (start, width) in cells lo..hi-1 of a wall, a cell away from both ends when
    it fits."""
    width = min(DOOR_CELLS[0] + int(rng.integers(DOOR_CELLS[1] - DOOR_CELLS[0] + 1)), hi - lo)
    first, last = (lo + 1, hi - 1 - width) if hi - lo >= width + 2 else (lo, hi - width)
    return first + int(rng.integers(last - first + 1)), width


def _corridors(blocks: np.ndarray, keep: np.ndarray, rng: np.random.Generator) -> None:
    """Parallel walls with doorways (see the module docstring), drawn into the lattices."""
    along_y = bool(rng.integers(2))  # walls along y (constant x) or along x (constant y)
    b, k = (blocks, keep) if along_y else (blocks.T, keep.T)  # b[wall position, cell along the wall]
    n_across, n_along = b.shape
    low, high = CORRIDOR_WIDTH_CELLS
    pos = low + int(rng.integers(high - low + 1))
    while pos <= n_across - 1 - low:
        b[pos, :] = True
        for _ in range(1 + int(rng.integers(2))):
            start, width = _door(0, n_along, rng)
            b[pos, start:start + width] = False
            k[max(pos - 1, 0):pos + 2, max(start - 1, 0):start + width + 1] = True
        pos += 1 + low + int(rng.integers(high - low + 1))


def _wall_positions(n: int, rng: np.random.Generator) -> list[int]:
    """Cells of the room walls across one axis of ``n`` cells: rooms of 6-10 cells between."""
    low, high = ROOM_CELLS
    walls, pos = [], low + int(rng.integers(high - low + 1))
    while pos <= n - 1 - low:
        walls.append(pos)
        pos += 1 + low + int(rng.integers(high - low + 1))
    return walls


def _rooms(blocks: np.ndarray, keep: np.ndarray, rng: np.random.Generator) -> None:
    """A grid of rooms with a doorway in every shared wall (see the module docstring)."""
    nx, ny = blocks.shape
    xs, ys = _wall_positions(nx, rng), _wall_positions(ny, rng)
    if not xs and not ys:
        xs = [nx // 2] if nx >= ny else []
        ys = [] if xs else [ny // 2]
    for x in xs:
        blocks[x, :] = True
    for y in ys:
        blocks[:, y] = True
    for walls, crossing, b, k in ((xs, ys, blocks, keep), (ys, xs, blocks.T, keep.T)):
        n_along = b.shape[1]
        bounds = [-1] + crossing + [n_along]
        for w in walls:
            for lo, hi in zip(bounds[:-1], bounds[1:]):
                start, width = _door(lo + 1, hi, rng)
                b[w, start:start + width] = False
                k[max(w - 1, 0):w + 2, max(start - 1, 0):start + width + 1] = True


def _clutter(blocks: np.ndarray, keep: np.ndarray, density: float, rng: np.random.Generator) -> None:
    """Scatter single blocks and small clusters on free cells outside ``keep`` until
    ``density`` of all cells (at most ``MAX_STATIC_BLOCKS`` blocks in all) are covered."""
    nx, ny = blocks.shape
    existing = int(blocks.sum())
    wanted = min(int(round(density * nx * ny)), MAX_STATIC_BLOCKS - existing)
    if wanted <= 0:
        return
    tries = 4 * wanted
    kinds = rng.integers(len(_PIECES), size=tries).tolist()
    spots = rng.random((tries, 2)).tolist()
    added = 0
    for kind, (u, v) in zip(kinds, spots):
        sx, sy = _PIECES[kind]
        if added + sx * sy > wanted:
            sx = sy = 1
        i, j = int(u * (nx - sx + 1)), int(v * (ny - sy + 1))
        if keep[i:i + sx, j:j + sy].any():
            continue
        window = blocks[i:i + sx, j:j + sy]
        added += int(window.size - window.sum())
        window[...] = True
        if added >= wanted:
            return
