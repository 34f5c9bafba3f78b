"""``Sensing``: what a dynnav task reads of its scene after a reset or a step.

It gathers the inputs of the step's ``StepSnapshot`` (``snapshot.py``):

* the robot's pose (x, y, yaw), read from its three planar joints;
* the 16 laser readings (``lasers.LaserRing``);
* contact, the collision test of ``NavEnv``'s episode rules: a PhysX contact between the
  robot (chassis or wheels) and anything else that touches (separation at most
  ``collision_margin``) or that the solver pushed apart (non-zero impulse), or the robot's
  footprint overlapping a wall or an obstacle box at the end of the step;
* every obstacle box (static ones, then the moving ones at their current centres), for d2.

The boxes are kept as Python floats, and what does not change within an episode (walls,
static boxes, half sizes) is computed once, when the scene is built.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .lasers import LaserRing
from .maniskill_adapter import sapien_object
from .robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT
from .snapshot import StepSnapshot, footprint_overlaps, snapshot_of

FOOTPRINT_HALF = (FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


class Sensing:
    """Reads the robot's pose, lasers and contacts in a PhysX CPU scene into snapshots.

    ``walls``: (centre xy, half size xy) of each wall; ``static_xy``: (n, 2) centres of the
    static obstacles; ``obstacle_half``: half sizes of all obstacles, static ones first.
    """

    def __init__(
        self,
        px,
        robot,
        walls,
        static_xy: np.ndarray,
        obstacle_half: np.ndarray,
        collision_margin: float,
    ):
        self.px = px
        self.lasers = LaserRing(px, FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT)
        self.collision_margin = collision_margin
        self._art = sapien_object(robot)
        links = [sapien_object(link) for link in robot.links]
        self._robot_bodies = frozenset(link for link in links if link.collision_shapes)
        half = np.array(obstacle_half, dtype=np.float64).reshape(-1, 2)
        static = np.array(static_xy, dtype=np.float64).reshape(-1, 2)
        n = len(static)
        self._static_xy = static
        self._obstacle_half = _read_only(half)  # shared by every snapshot: nothing writes to it
        self._moving_half = half[n:].tolist()
        self._static_boxes = [(*c, *h) for c, h in zip(static.tolist(), half[:n].tolist())]
        self._fixed_boxes = [(float(c[0]), float(c[1]), float(h[0]), float(h[1])) for c, h in walls]
        self._fixed_boxes += self._static_boxes
        self._still_xy = _read_only(static.copy()) if not self._moving_half else None

    def pose(self) -> tuple[float, float, float]:
        """(x, y, yaw) of the robot, as Python floats."""
        x, y, yaw = self._art.get_qpos()[:3].tolist()
        return x, y, yaw

    def in_collision(self) -> bool:
        """Does a PhysX contact of the last step count as a collision of the robot?"""
        robot, margin = self._robot_bodies, self.collision_margin
        for contact in self.px.get_contacts():
            a, b = contact.bodies
            if (a in robot) != (b in robot):  # robot against anything else
                for p in contact.points:
                    # touching, or the solver had to push them apart during the step
                    if p.separation <= margin or p.impulse.any():
                        return True
        return False

    def take(
        self,
        step: int,
        target_xy,
        moving_xy: np.ndarray,
        contact: Optional[bool],
        previous: Optional[StepSnapshot],
        placed: bool = False,
    ) -> StepSnapshot:
        """The snapshot of the scene now; ``contact=None``: after a step, from PhysX's contacts
        and the footprint's overlap; ``placed``: see ``snapshot.snapshot_of``."""
        x, y, yaw = pose = self.pose()
        moving = [(*p, *h) for p, h in zip(moving_xy.tolist(), self._moving_half)]
        if contact is None:
            contact = self.in_collision() or footprint_overlaps(pose, FOOTPRINT_HALF, self._fixed_boxes + moving)
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
            boxes=self._static_boxes + moving,
            contact=contact,
            previous=previous,
            placed=placed,
        )
