"""Draw assets/maps/office.pgm and office.yaml: a 16 m x 10 m office floor for DynNav-Map-v1.

    python scripts/draw_office_map.py

A corridor 1.6 m wide runs east-west through the middle; four rooms north of it and three south
(one of them a meeting room twice as wide), each with a 1 m door onto the corridor; desks and
cabinets stand in the rooms; the walls are 0.2 m thick. The north-east corner outside the
building is unknown (grey), as a SLAM map leaves what its lidar never saw. ``map_server``'s
conventions: 0.05 m per pixel, black occupied (0), white free (254), grey unknown (205),
``negate: 0``, thresholds 0.65 and 0.196; the origin puts the map's centre at (0, 0).
"""

from pathlib import Path

import numpy as np
from PIL import Image

RES = 0.05
W, H = 16.0, 10.0
FREE, WALL, UNKNOWN = 254, 0, 205
OUT = Path(__file__).resolve().parents[1] / "assets" / "maps"


def px(v: float) -> int:
    return int(round(v / RES))


def main() -> None:
    img = np.full((px(H), px(W)), FREE, dtype=np.uint8)  # rows from the top

    def box(x0, y0, x1, y1, value=WALL):  # metres from the map's lower-left corner
        img[px(H - y1):px(H - y0), px(x0):px(x1)] = value

    t = 0.2
    box(0, 0, W, t), box(0, H - t, W, H), box(0, 0, t, H), box(W - t, 0, W, H)  # outer walls
    c0, c1 = 4.2, 5.8  # the corridor between y = 4.2 and 5.8
    box(0, c0 - t, W, c0), box(0, c1, W, c1 + t)  # its walls
    for x in (4.0, 8.0, 12.0):  # north rooms' walls
        box(x - t / 2, c1, x + t / 2, H)
    for x in (5.0, 10.5):  # south rooms' walls (the middle one a meeting room)
        box(x - t / 2, 0, x + t / 2, c0)
    for x in (1.5, 5.5, 9.5, 13.5):  # north doors, 1 m wide
        box(x, c1, x + 1.0, c1 + t, FREE)
    for x in (2.0, 7.0, 13.0):  # south doors
        box(x, c0 - t, x + 1.0, c0, FREE)
    for x, y in ((1.0, 7.6), (5.0, 7.6), (9.0, 7.6), (13.0, 8.4)):  # desks in the north rooms
        box(x, y, x + 1.4, y + 0.7)
    box(6.8, 1.4, 8.8, 2.6)  # the meeting table
    box(0.4, 0.4, 1.0, 1.6), box(14.6, 0.4, 15.6, 1.0)  # cabinets
    box(12.4, 8.6, W, H, UNKNOWN)  # outside the building, never seen
    box(12.4, 8.6, 12.6, H - t), box(12.4, 8.6, W - t, 8.8)  # the walls round that corner
    OUT.mkdir(parents=True, exist_ok=True)
    Image.fromarray(img, mode="L").save(OUT / "office.pgm")
    (OUT / "office.yaml").write_text(
        "image: office.pgm\nresolution: 0.05\norigin: [-8.0, -5.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    print(f"wrote {OUT / 'office.pgm'} ({img.shape[1]} x {img.shape[0]} pixels) and office.yaml")


if __name__ == "__main__":
    main()
