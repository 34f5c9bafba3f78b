"""``Sensing``: what a dynnav task reads of its scene after a reset or a step.

It gathers the inputs of the step's ``StepSnapshot`` (``snapshot.py``):

* the robot's pose (x, y, yaw), read from its three planar joints;
* the laser readings (``lasers.LaserRing``: the study's 16 rays or the task's ``LaserConfig``);
* contact, the collision test of ``NavEnv``'s episode rules: a PhysX contact between the
  robot (chassis or wheels) and anything else that touches (separation at most
  ``collision_margin``) or that the solver pushed apart (non-zero impulse), or the robot's
  footprint overlapping a wall or an obstacle box at the end of the step;
* every obstacle box (static ones, then the moving ones at their current centres), for d2;
* the pedestrians (``set_pedestrians``): their centres and radii, and whether a contact was
  with one of them (a PhysX contact with a pedestrian's body, or the footprint overlapping
  its circle at the end of the step): a human collision.

The boxes are kept as Python floats, and what does not change within an episode (walls,
static boxes, half sizes) is computed once, when the scene is built or its world changes
(``Sensing.set_obstacles``). In a world of many static boxes (more than ``CULL_ABOVE``) a
snapshot finds the nearest one and those within the footprint's reach in one vectorised pass
and tests only those: the same contact and d2 as a test against every box.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from .lasers import LaserConfig, LaserRing
from .maniskill_adapter import sapien_object
from .robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT
from .snapshot import StepSnapshot, footprint_overlaps, footprint_touches_circles, snapshot_of

FOOTPRINT_HALF = (FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)
FOOTPRINT_RADIUS = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH) + 1e-9
"""no box the footprint overlaps is farther than this from the robot's centre (m)"""
CULL_ABOVE = 16
"""with more static boxes than this, a snapshot tests only those near the robot (same result)"""


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


class Sensing:
    """Reads the robot's pose, lasers and contacts in a PhysX CPU scene into snapshots.

    ``walls``: (centre xy, half size xy) of each wall; ``static_xy``: (n, 2) centres of the
    static obstacles; ``obstacle_half``: half sizes of all obstacles, static ones first;
    ``lasers``: the laser ring's rays, field of view and range.
    ``set_obstacles`` replaces them (a task whose world changes between episodes).
    """

    def __init__(
        self,
        px,
        robot,
        walls=(),
        static_xy: np.ndarray = np.zeros((0, 2)),
        obstacle_half: np.ndarray = np.zeros((0, 2)),
        collision_margin: float = 0.005,
        lasers: LaserConfig = LaserConfig(),
    ):
        self.px = px
        self.lasers = LaserRing(px, FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT, lasers)
        self.collision_margin = collision_margin
        self._art = sapien_object(robot)
        links = [sapien_object(link) for link in robot.links]
        self._robot_bodies = frozenset(link for link in links if link.collision_shapes)
        self.set_obstacles(walls, static_xy, obstacle_half)
        self.set_pedestrians((), ())

    def set_pedestrians(self, bodies, radii) -> None:
        """The pedestrians' PhysX bodies and radii (m) the next snapshots test against, in crowd order."""
        self._human_bodies = frozenset(bodies)
        self._human_radius = _read_only(np.array(radii, dtype=np.float64).reshape(-1))

    def set_obstacles(self, walls, static_xy: np.ndarray, obstacle_half: np.ndarray) -> None:
        """The walls and obstacle boxes the next snapshots test against (see the class docstring)."""
        half = np.array(obstacle_half, dtype=np.float64).reshape(-1, 2)
        static = np.array(static_xy, dtype=np.float64).reshape(-1, 2)
        n = len(static)
        self._static_xy = static
        self._obstacle_half = _read_only(half)  # shared by every snapshot: nothing writes to it
        self._moving_half = half[n:].tolist()
        self._static_boxes = [(*c, *h) for c, h in zip(static.tolist(), half[:n].tolist())]
        self._wall_boxes = [(float(c[0]), float(c[1]), float(h[0]), float(h[1])) for c, h in walls]
        self._fixed_boxes = self._wall_boxes + self._static_boxes
        self._still_xy = _read_only(static.copy()) if not self._moving_half else None
        self._culled = n > CULL_ABOVE
        if self._culled:
            self._static_half = half[:n]
            self._scratch = np.empty_like(static)

    def _nearby_static(self, x: float, y: float) -> tuple[list, list]:
        """Of many static boxes: (the nearest one, those the footprint can reach), as box rows.

        The distance from the robot's centre to a box its footprint overlaps is below the
        footprint's circumradius, and the nearest box gives d2, so the snapshot's values
        are those of a test against every box, found in one vectorised pass."""
        d = self._scratch
        np.subtract(self._static_xy, (x, y), out=d)
        np.abs(d, out=d)
        d -= self._static_half
        np.maximum(d, 0.0, out=d)
        dx, dy = d[:, 0], d[:, 1]
        dist = np.sqrt(dx * dx + dy * dy)  # as snapshot.nearest_box_distance computes it, bit for bit
        boxes = self._static_boxes
        near = [boxes[i] for i in np.flatnonzero(dist <= FOOTPRINT_RADIUS).tolist()]
        return [boxes[int(np.argmin(dist))]], near

    def pose(self) -> tuple[float, float, float]:
        """(x, y, yaw) of the robot, as Python floats."""
        x, y, yaw = self._art.get_qpos()[:3].tolist()
        return x, y, yaw

    def in_collision(self) -> bool:
        """Does a PhysX contact of the last step count as a collision of the robot?"""
        return self.collisions()[0]

    def collisions(self) -> tuple[bool, bool]:
        """(a PhysX contact of the last step counts as a collision of the robot, one of them was
        with a pedestrian)."""
        robot, humans, margin = self._robot_bodies, self._human_bodies, self.collision_margin
        hit = False
        for contact in self.px.get_contacts():
            a, b = contact.bodies
            if (a in robot) != (b in robot):  # robot against anything else
                for p in contact.points:
                    # touching, or the solver had to push them apart during the step
                    if p.separation <= margin or p.impulse.any():
                        if a in humans or b in humans:
                            return True, True
                        if not humans:
                            return True, False
                        hit = True
                        break
        return hit, False

    def take(
        self,
        step: int,
        target_xy,
        moving_xy: np.ndarray,
        contact: Optional[bool],
        previous: Optional[StepSnapshot],
        placed: bool = False,
        human_xy: Optional[np.ndarray] = None,
    ) -> StepSnapshot:
        """The snapshot of the scene now; ``contact=None``: after a step, from PhysX's contacts
        and the footprint's overlap; ``placed``: see ``snapshot.snapshot_of``; ``human_xy``: the
        pedestrians' centres (k, 2), in ``set_pedestrians``'s order."""
        x, y, yaw = pose = self.pose()
        moving = [(*p, *h) for p, h in zip(moving_xy.tolist(), self._moving_half)]
        if self._culled:
            nearest, near = self._nearby_static(x, y)
            fixed, boxes = self._wall_boxes + near, nearest + moving
        else:
            fixed, boxes = self._fixed_boxes, self._static_boxes + moving
        human = False
        humans = None
        if human_xy is not None and len(human_xy):
            humans = (_read_only(np.array(human_xy, dtype=np.float64).reshape(-1, 2)), self._human_radius)
        if contact is None and humans is None:
            contact = self.in_collision() or footprint_overlaps(pose, FOOTPRINT_HALF, fixed + moving)
        elif contact is None:
            contact, human = self.collisions()
            if not human:
                circles = [(cx, cy, r) for (cx, cy), r in zip(humans[0].tolist(), humans[1].tolist())]
                human = footprint_touches_circles(pose, FOOTPRINT_HALF, circles)
                contact = contact or human or footprint_overlaps(pose, FOOTPRINT_HALF, fixed + moving)
        if self._still_xy is not None:
            obstacle_xy = self._still_xy
        else:
            obstacle_xy = _read_only(np.concatenate([self._static_xy, moving_xy]))
        return snapshot_of(
            step=step,
            pose=pose,
            lasers=_read_only(self.lasers.read(x, y, yaw)),
            target_xy=_read_only(np.array(target_xy, dtype=np.float64)),
            obstacle_xy=obstacle_xy,
            obstacle_half=self._obstacle_half,
            moving_count=len(moving),
            boxes=boxes,
            contact=contact,
            previous=previous,
            placed=placed,
            humans=humans,
            human_contact=human,
        )
