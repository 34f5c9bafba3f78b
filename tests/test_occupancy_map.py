"""Occupancy maps in map_server's format: a map drawn here, read back cell by cell (origin, negate,
unknown cells), merged into boxes that cover exactly its occupied cells, and every bad input refused."""

import numpy as np
import pytest
from PIL import Image

from dynnav_tasks.occupancy_map import MapError, merge_boxes, read_map

# the map as drawn, top row first (as in the image): # occupied, . free, ? unknown
DRAWING = [
    "##########",
    "#....#...#",
    "#....#...#",
    "#..?.....#",
    "#....#...#",
    "##########",
]
FREE, OCCUPIED, UNKNOWN = 254, 0, 205  # map_saver's pixel values


def write_map(folder, negate=0, origin=(-1.0, 2.0, 0.0), resolution=0.05, suffix="pgm", **fields):
    values = {"#": OCCUPIED, ".": FREE, "?": UNKNOWN}
    pixels = np.array([[values[c] for c in row] for row in DRAWING], np.uint8)
    if negate:
        pixels = 255 - pixels
    Image.fromarray(pixels, mode="L").save(folder / f"office.{suffix}")
    text = {"image": f"office.{suffix}", "resolution": resolution, "origin": list(origin), "negate": negate,
            "occupied_thresh": 0.65, "free_thresh": 0.196, **fields}
    path = folder / "office.yaml"
    path.write_text("\n".join(f"{k}: {v}" for k, v in text.items() if v is not None) + "\n")
    return path


@pytest.mark.parametrize("negate, suffix", [(0, "pgm"), (1, "pgm"), (0, "png")])
def test_a_drawn_map_reads_back_cell_by_cell(tmp_path, negate, suffix):
    m = read_map(write_map(tmp_path, negate=negate, suffix=suffix))
    assert m.occupied.shape == (10, 6) and m.resolution == 0.05 and m.origin == (-1.0, 2.0)
    for row, line in enumerate(DRAWING):
        j = len(DRAWING) - 1 - row  # the image's top row is the map's last
        for i, c in enumerate(line):
            assert m.occupied[i, j] == (c != "."), (i, j, c)  # unknown counts as occupied
    # the unknown cell "?" is column 3 of the image's row 3, i.e. map row 2: its box lies at
    # x = -1 + 3 * 0.05 .. -1 + 4 * 0.05, y = 2 + 2 * 0.05 .. 2 + 3 * 0.05
    (cx, cy), (hx, hy) = m.box_of((3, 2, 4, 3))
    assert (cx, cy, hx, hy) == pytest.approx((-0.825, 2.125, 0.025, 0.025))


def test_boxes_cover_exactly_the_occupied_cells(tmp_path):
    m = read_map(write_map(tmp_path))
    rects = merge_boxes(m.occupied)
    count = np.zeros(m.occupied.shape, int)
    for i0, j0, i1, j1 in rects:
        count[i0:i1, j0:j1] += 1
    np.testing.assert_array_equal(count, m.occupied.astype(int))
    assert len(rects) <= 8  # two walls' rows, two side walls, the inner wall's two pieces, the unknown cell
    rng = np.random.default_rng(0)
    for _ in range(50):  # and any grid at all
        grid = rng.random(tuple(rng.integers(1, 25, 2))) < rng.uniform(0.1, 0.9)
        count = np.zeros(grid.shape, int)
        for i0, j0, i1, j1 in merge_boxes(grid):
            count[i0:i1, j0:j1] += 1
        np.testing.assert_array_equal(count, grid.astype(int))


@pytest.mark.parametrize("change, message", [
    (dict(image="missing.pgm"), r"office.yaml: field 'image': .*missing.pgm does not exist"),
    (dict(resolution=0), r"office.yaml: field 'resolution' must be > 0"),
    (dict(resolution=-0.05), r"office.yaml: field 'resolution' must be > 0"),
    (dict(resolution=None), r"office.yaml: field 'resolution' is missing"),
    (dict(origin=[0.0, 0.0, 0.5]), r"office.yaml: field 'origin' has yaw 0.5"),
    (dict(origin="[a, b]"), r"office.yaml: field 'origin' must be \[x, y, yaw\]"),
    (dict(negate=2), r"office.yaml: field 'negate' must be 0 or 1"),
    (dict(free_thresh=0.9), r"office.yaml: fields 'free_thresh' \(0.9\) and 'occupied_thresh' \(0.65\)"),
])
def test_bad_maps_are_refused_naming_the_file_and_the_field(tmp_path, change, message):
    path = write_map(tmp_path)
    text = path.read_text()
    for key, value in change.items():
        lines = [line for line in text.splitlines() if not line.startswith(f"{key}:")]
        text = "\n".join(lines + ([f"{key}: {value}"] if value is not None else [])) + "\n"
    path.write_text(text)
    with pytest.raises(MapError, match=message):
        read_map(path)
    with pytest.raises(MapError, match=r"nowhere.yaml: cannot read the map's YAML file"):
        read_map(tmp_path / "nowhere.yaml")
