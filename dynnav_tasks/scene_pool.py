"""``ScenePool``: one scene that shows a different ``World`` every episode, built once.

A task whose world changes between episodes (``tasks/procedural.py``) cannot rebuild its
SAPIEN scene on every reset: building hundreds of actors takes far longer than an episode's
reset budget. The pool builds, once, every body any world of its kind can need:

* a floor four times as wide as the largest arena (visual only), centred under each arena;
* four walls long enough for the largest arena, moved so that their inner faces lie on the
  episode's arena bounds (they run on past its corners, outside the arena);
* ``max_static`` static blocks and ``max_moving`` kinematic boxes, all of one size;
* two targets: a red disc, and a disc with the camera worlds' marker column;
* ``max_pedestrians`` pedestrians (kinematic upright cylinders), which the task's crowd places
  at each reset.

``place(world)`` moves the bodies the world uses into place and parks the ones it does not
use far under the floor (``PARK_Z``), each at its own spot, and switches them off: a
switched-off body is out of the PhysX scene (no laser ray and no contact reaches it, and it
costs a simulation step nothing: 600 idle blocks would otherwise double PhysX's step time)
and out of the render scene. Bodies that were parked and stay parked are not touched, so a
reset moves only what changed. It returns a ``scene.BuiltWorld``, the same handles
``build_world`` gives for a fixed world.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sapien

from .maniskill_adapter import physx_body, sapien_object
from .scene import HIDDEN_Z, BuiltWorld, add_box, add_pedestrian, add_target, material
from .world import FLOOR_COLOR, MOVING_OBSTACLE_COLOR, STATIC_OBSTACLE_COLOR, WALL_COLORS, Arena, World

PARK_Z = 2 * HIDDEN_Z
"""height of a parked block's centre (m): far under the floor"""
PARK_SPACING = 1.0
"""distance between two parked bodies' centres (m): more than a block's width"""


@dataclass(frozen=True)
class PoolSizes:
    """What a ``ScenePool`` holds: its capacity and the one size of its boxes."""

    max_static: int
    """static blocks (the most any world may use)"""
    max_moving: int
    """moving boxes (the most any world may use)"""
    box_half: float
    """half the side of every block and moving box (m)"""
    box_height: float = 0.5
    """height of every block and moving box (m)"""
    max_arena_side: float = 20.0
    """the longest side of an arena the walls and floor cover (m)"""
    max_pedestrians: int = 0
    """pedestrians (the most any world may have)"""
    pedestrian_radius: float = 0.3
    """radius of every pedestrian (m)"""
    pedestrian_height: float = 1.7
    """height of every pedestrian (m)"""


class ScenePool:
    """The pooled bodies of a scene whose world changes every episode (module docstring)."""

    def __init__(self, scene, sizes: PoolSizes):
        self.sizes = sizes
        self._arena = Arena(x_range=(0.0, sizes.max_arena_side), y_range=(0.0, sizes.max_arena_side))
        floor = scene.create_actor_builder()
        floor.initial_pose = sapien.Pose()
        side = 2 * sizes.max_arena_side  # wide enough to hide every parked body from every camera
        floor.add_box_visual(sapien.Pose([0.0, 0.0, -0.01]), half_size=[side, side, 0.01], material=material(FLOOR_COLOR))
        self._floor = sapien_object(floor.build_static("floor"))
        self._walls = {
            name: sapien_object(add_box(scene, f"wall_{name}", center, half, self._arena.wall_height, WALL_COLORS[name], False))
            for name, (center, half) in self._arena.walls().items()
        }
        half, height = (sizes.box_half, sizes.box_half), sizes.box_height
        self._static = [  # built parked: ManiSkill puts every body back where it was built
            sapien_object(add_box(scene, f"block{i}", _park_xy(i), half, height, STATIC_OBSTACLE_COLOR, False, PARK_Z))
            for i in range(sizes.max_static)
        ]
        moving_z = PARK_Z - 2 * height
        self._moving_z = moving_z
        moving = [add_box(scene, f"mover{i}", _park_xy(i), half, height, MOVING_OBSTACLE_COLOR, True, moving_z)
                  for i in range(sizes.max_moving)]
        self._moving = [physx_body(actor) for actor in moving]
        self._pedestrian_z = moving_z - 2 * sizes.pedestrian_height
        self._pedestrians = [
            physx_body(add_pedestrian(scene, f"walker{i}", sizes.pedestrian_radius, sizes.pedestrian_height, _park_xy(i),
                                      self._pedestrian_z))
            for i in range(sizes.max_pedestrians)
        ]
        self._targets = [add_target(scene, f"target{m}", marker, [0.0, 0.0, HIDDEN_Z]) for m, marker in enumerate((False, True))]
        self._static_parts = [tuple(entity.components) for entity in self._static]
        self._moving_parts = [tuple(body.entity.components) for body in self._moving]
        self._pedestrian_parts = [tuple(body.entity.components) for body in self._pedestrians]
        for parts in self._static_parts + self._moving_parts + self._pedestrian_parts:
            _switch(parts, False)
        self._static_used = self._moving_used = self._pedestrians_used = 0

    # ------------------------------------------------------------------ placing
    def check(self, world: World) -> None:
        """Raise ValueError, naming what is wrong, if ``world`` does not fit this pool."""
        s = self.sizes
        size = world.arena.size
        if max(size) > s.max_arena_side:
            raise ValueError(f"the world's arena is {size[0]:g} m x {size[1]:g} m; this task's scene covers arenas "
                             f"up to {s.max_arena_side:g} m a side")
        walls = (world.arena.wall_thickness, world.arena.wall_height)
        if walls != (self._arena.wall_thickness, self._arena.wall_height):
            raise ValueError(f"this task's walls are {self._arena.wall_thickness:g} m thick and "
                             f"{self._arena.wall_height:g} m high; the world's are {walls[0]:g} m and {walls[1]:g} m")
        if len(world.targets) != 1:
            raise ValueError(f"a world of this task has one target; got {len(world.targets)}")
        for group in world.obstacles:
            if tuple(group.half_size) != (s.box_half, s.box_half) or group.height != s.box_height:
                raise ValueError(f"every obstacle of this task is a {2 * s.box_half:g} m x {2 * s.box_half:g} m x "
                                 f"{s.box_height:g} m box; got half size {group.half_size} and height {group.height}")
        n_static = sum(g.count for g in world.obstacles if not g.moving)
        if n_static > s.max_static:
            raise ValueError(f"the world has {n_static} static blocks; this task holds at most {s.max_static}")
        if world.moving_obstacle_count > s.max_moving:
            raise ValueError(f"the world has {world.moving_obstacle_count} moving obstacles; this task holds at most "
                             f"{s.max_moving}")
        p = world.pedestrians
        if p is not None and p.count:
            if p.count > s.max_pedestrians:
                raise ValueError(f"the world has {p.count} pedestrians; this task holds at most {s.max_pedestrians}")
            if (p.radius, p.height) != (s.pedestrian_radius, s.pedestrian_height):
                raise ValueError(f"every pedestrian of this task has radius {s.pedestrian_radius:g} m and height "
                                 f"{s.pedestrian_height:g} m; got {p.radius:g} m and {p.height:g} m")

    def place(self, world: World) -> BuiltWorld:
        """Show ``world``: place its walls and floor, park what it does not use (see the module
        docstring) and return the handles of the bodies it uses."""
        self.check(world)
        wall_z = world.arena.wall_height / 2
        for name, (center, _) in world.arena.walls().items():  # a long wall on the world wall's line
            self._walls[name].set_pose(sapien.Pose([float(center[0]), float(center[1]), wall_z]))
        self._floor.set_pose(sapien.Pose([*world.arena.center, 0.0]))

        static_xy = [g.motion.at for g in world.obstacles if not g.moving for _ in range(g.count)]
        z = self.sizes.box_height / 2
        for entity, (x, y) in zip(self._static, static_xy):
            entity.set_pose(sapien.Pose([float(x), float(y), z]))
        self._static_used = self._use(self._static, self._static_parts, len(static_xy), self._static_used, PARK_Z)

        movers, bodies_used = [], 0
        for group in world.obstacles:
            if group.moving:
                bodies = self._moving[bodies_used:bodies_used + group.count]
                movers.append((group.motion.mover(), bodies))
                bodies_used += group.count
        entities = [body.entity for body in self._moving]
        self._moving_used = self._use(entities, self._moving_parts, bodies_used, self._moving_used, self._moving_z)

        walkers = world.pedestrians.count if world.pedestrians is not None else 0
        entities = [body.entity for body in self._pedestrians]
        self._pedestrians_used = self._use(entities, self._pedestrian_parts, walkers, self._pedestrians_used,
                                           self._pedestrian_z)

        target = self._targets[int(world.target_marker)]
        self._targets[1 - int(world.target_marker)].set_pose(sapien.Pose([0.0, 0.0, HIDDEN_Z]))
        half = [tuple(float(v) for v in g.half_size) for g in world.obstacles if not g.moving for _ in range(g.count)]
        half += [tuple(float(v) for v in g.half_size) for g in world.obstacles if g.moving for _ in range(g.count)]
        return BuiltWorld(
            movers=movers,
            moving_bodies=self._moving[:bodies_used],
            moving_z=[z] * bodies_used,
            static_obstacle_xy=np.array(static_xy, dtype=np.float64).reshape(-1, 2),
            obstacle_half=np.array(half, dtype=np.float64).reshape(-1, 2),
            targets=[(world.targets[0].mover(), target)],
            pedestrian_bodies=self._pedestrians[:walkers],
        )

    # ------------------------------------------------------------------ parking
    @staticmethod
    def _use(entities, parts, used: int, was_used: int, park_z: float) -> int:
        """Switch on bodies ``[was_used, used)``, park and switch off ``[used, was_used)``;
        return ``used``. A switched-off body is out of the PhysX scene (no contact, no ray, no
        cost in a step) and of the render scene."""
        for i in range(was_used, used):
            _switch(parts[i], True)
        for i in range(used, was_used):
            entities[i].set_pose(sapien.Pose([*_park_xy(i), park_z]))
            _switch(parts[i], False)
        return used


def _switch(components, on: bool) -> None:
    """Enable or disable a body's components (its PhysX body and its render body)."""
    for component in components:
        if on:
            component.enable()
        else:
            component.disable()


def _park_xy(i: int) -> tuple[float, float]:
    """Parked body ``i``'s own spot under the floor, on a grid of ``PARK_SPACING``."""
    return (i % 25) * PARK_SPACING, (i // 25) * PARK_SPACING
