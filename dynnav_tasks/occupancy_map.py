"""Occupancy maps in ROS's ``map_server`` format, read as a grid and merged into boxes.

A map is a YAML file and an image (PGM or PNG) beside it, as ``map_server`` and Nav2's
``map_io`` read them:

``image``
    the image's path, relative to the YAML file (or absolute).
``resolution``
    metres per pixel, > 0.
``origin``
    ``[x, y, yaw]``: the world pose of the image's lower-left pixel's corner; yaw must be 0
    (dynnav's boxes are axis-aligned; ``map_server`` itself ignores it in most places).
``occupied_thresh``, ``free_thresh``
    a pixel whose occupancy probability p exceeds ``occupied_thresh`` is occupied, one below
    ``free_thresh`` is free, anything between is unknown.
``negate``
    0: p = (255 - v) / 255 for a pixel of value v (black is occupied); 1: p = v / 255.

Colour pixels count by the mean of their channels, as ``map_server`` does; an alpha channel is
ignored. Unknown cells count as occupied here (the robot may not drive where the map does not
know the floor). ``merge_boxes`` covers the occupied cells with few axis-aligned rectangles:
each is grown from its first cell to the right as far as the row stays occupied, then up as
long as every cell of the next row's span is occupied and not yet covered; every occupied cell
lies in exactly one rectangle and no free cell in any.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml


class MapError(ValueError):
    """An occupancy map that cannot be read: the message names the file and the field."""


@dataclass(frozen=True)
class OccupancyMap:
    """A map's cells: ``occupied[i, j]`` for column i (x) and row j (y, from the bottom)."""

    occupied: np.ndarray
    """(width, height) bool: occupied or unknown"""
    resolution: float
    """m per cell"""
    origin: tuple[float, float]
    """world (x, y) of cell (0, 0)'s lower-left corner"""
    source: str = ""
    """the YAML file it was read from"""

    @property
    def size(self) -> tuple[float, float]:
        """(x, y) extent in metres."""
        return self.occupied.shape[0] * self.resolution, self.occupied.shape[1] * self.resolution

    def box_of(self, rect: tuple[int, int, int, int]) -> tuple[tuple[float, float], tuple[float, float]]:
        """((centre x, y), (half x, y)) in metres of the cell rectangle (i0, j0, i1, j1), ends exclusive."""
        i0, j0, i1, j1 = rect
        r, (x0, y0) = self.resolution, self.origin
        return ((x0 + (i0 + i1) * r / 2, y0 + (j0 + j1) * r / 2), ((i1 - i0) * r / 2, (j1 - j0) * r / 2))


def _field(data: dict, name: str, path: Path):
    if name not in data:
        raise MapError(f"{path}: field {name!r} is missing (map_server's YAML needs image, resolution, origin, "
                       "occupied_thresh, free_thresh and negate)")
    return data[name]


def _number(data: dict, name: str, path: Path) -> float:
    value = _field(data, name, path)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise MapError(f"{path}: field {name!r} must be a number, got {value!r}")
    return float(value)


def read_map(path: str | Path) -> OccupancyMap:
    """The occupancy map of the ``map_server`` YAML file ``path`` (module docstring); ``MapError``
    naming the file and the field for anything it cannot use."""
    from PIL import Image

    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise MapError(f"{path}: cannot read the map's YAML file ({err.strerror or err})") from err
    except yaml.YAMLError as err:
        raise MapError(f"{path}: not YAML ({err})") from err
    if not isinstance(data, dict):
        raise MapError(f"{path}: a map_server YAML file is a mapping of fields, got {type(data).__name__}")
    resolution = _number(data, "resolution", path)
    if resolution <= 0:
        raise MapError(f"{path}: field 'resolution' must be > 0 (metres per pixel), got {resolution!r}")
    origin = _field(data, "origin", path)
    if not (isinstance(origin, (list, tuple)) and len(origin) in (2, 3)
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in origin)):
        raise MapError(f"{path}: field 'origin' must be [x, y, yaw] in metres and radians, got {origin!r}")
    if len(origin) == 3 and origin[2] != 0:
        raise MapError(f"{path}: field 'origin' has yaw {origin[2]!r}: only maps with yaw 0 are supported "
                       "(rotate the image instead)")
    occupied_thresh, free_thresh = _number(data, "occupied_thresh", path), _number(data, "free_thresh", path)
    if not 0.0 <= free_thresh <= occupied_thresh <= 1.0:
        raise MapError(f"{path}: fields 'free_thresh' ({free_thresh}) and 'occupied_thresh' ({occupied_thresh}) "
                       "must satisfy 0 <= free_thresh <= occupied_thresh <= 1")
    negate = _field(data, "negate", path)
    if negate not in (0, 1, True, False):
        raise MapError(f"{path}: field 'negate' must be 0 or 1, got {negate!r}")
    image_name = _field(data, "image", path)
    if not isinstance(image_name, str) or not image_name:
        raise MapError(f"{path}: field 'image' must name the map's image file, got {image_name!r}")
    image_path = Path(image_name) if Path(image_name).is_absolute() else path.parent / image_name
    try:
        with Image.open(image_path) as image:
            pixels = np.asarray(image.convert("RGB"), dtype=np.float64).mean(axis=-1)  # gray, or colour's mean
    except FileNotFoundError as err:
        raise MapError(f"{path}: field 'image': {image_path} does not exist") from err
    except OSError as err:
        raise MapError(f"{path}: field 'image': {image_path} is not an image PIL can read ({err})") from err
    p = pixels / 255.0 if negate else (255.0 - pixels) / 255.0
    free = p < free_thresh
    occupied_rows = ~free  # occupied and unknown alike
    # image row 0 is the top of the map: flip to rows from the bottom, then index [column, row]
    return OccupancyMap(np.ascontiguousarray(occupied_rows[::-1].T), resolution, (float(origin[0]), float(origin[1])),
                        str(path))


def merge_boxes(occupied: np.ndarray) -> list[tuple[int, int, int, int]]:
    """Cell rectangles (i0, j0, i1, j1), ends exclusive, covering exactly the ``occupied`` cells
    (module docstring); in the order grown (by row j, then column i)."""
    occupied = np.asarray(occupied, bool)
    covered = np.zeros_like(occupied)
    nx, ny = occupied.shape
    rects = []
    for j in range(ny):
        i = 0
        while i < nx:
            if not occupied[i, j] or covered[i, j]:
                i += 1
                continue
            i1 = i
            while i1 < nx and occupied[i1, j] and not covered[i1, j]:
                i1 += 1
            j1 = j + 1
            while j1 < ny and occupied[i:i1, j1].all() and not covered[i:i1, j1].any():
                j1 += 1
            covered[i:i1, j:j1] = True
            rects.append((i, j, i1, j1))
            i = i1
    return rects
