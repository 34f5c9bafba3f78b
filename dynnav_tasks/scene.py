"""Turn a ``World`` into SAPIEN actors: floor, coloured walls, obstacles, target discs and markers.

Lighting is even: ambient light only, no directional lights, so every surface shows its
palette colour (``world.py``) exactly, from every side and at every distance. A camera then
tells things apart by colour alone, and a shaded face never takes another object's colour.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sapien

from .maniskill_adapter import physx_body, sapien_object
from .motion import Mover
from .world import (FLOOR_COLOR, MOVING_OBSTACLE_COLOR, PEDESTRIAN_COLOR, STATIC_OBSTACLE_COLOR, TARGET_COLOR,
                    WALL_COLORS, World)

TARGET_DISC_RADIUS = 0.25
HIDDEN_Z = -10.0
"""height at which a target (disc and marker) is out of sight, under the floor"""


@dataclass(frozen=True)
class TargetMarker:
    """The red column that stands on the chosen target in the camera worlds.

    Visual only: it has no collision shape, so the robot drives into it and the lasers do not
    see it. Its radius is the success radius (0.3 m): the robot succeeds when its centre is
    inside the column. Its height puts it above the 0.5 m obstacles and walls, so the front
    camera sees it over them from most of the arena (see the camera tasks' docstrings for the
    pixel counts this gives).
    """

    radius: float = 0.3
    height: float = 1.2


TARGET_MARKER = TargetMarker()


def add_lighting(scene) -> None:
    """Even lighting: ambient only, so rendered colours are the palette's sRGB colours."""
    scene.set_ambient_light([1.0, 1.0, 1.0])


@dataclass
class BuiltWorld:
    """Handles to what ``build_world`` created, for the environment to move and query."""

    movers: list[tuple[Mover, list]]
    """(mover, kinematic bodies it moves) per moving obstacle group"""
    moving_bodies: list
    """every moving obstacle's PhysxRigidDynamicComponent, in state-vector order"""
    moving_z: list[float]
    """centre height of each moving obstacle"""
    static_obstacle_xy: np.ndarray
    """(n, 2) centres of the static obstacles"""
    obstacle_half: np.ndarray
    """(m, 2) half sizes of all obstacles: static ones first, then moving ones"""
    targets: list[tuple[Mover, sapien.Entity]]
    """(mover, disc entity) per candidate target"""
    pedestrian_bodies: list = field(default_factory=list)
    """every pedestrian's PhysxRigidDynamicComponent (kinematic upright cylinders), in crowd order"""


def material(rgba) -> sapien.render.RenderMaterial:
    """A material that renders as the sRGB colour ``rgba`` under ``add_lighting``."""
    linear = [float(c) ** 2.2 for c in rgba[:3]]  # the shader outputs colour ** (1 / 2.2)
    return sapien.render.RenderMaterial(base_color=[*linear, float(rgba[3])])


def add_box(scene, name, center, half_size, height, color, moving, z=None):
    """A box standing on the floor at ``center`` (x, y) (or with its centre at height ``z``):
    static, or kinematic when ``moving``. ManiSkill puts it back there when the scene is set up."""
    b = scene.create_actor_builder()
    half = [float(half_size[0]), float(half_size[1]), height / 2]
    b.add_box_collision(half_size=half)
    b.add_box_visual(half_size=half, material=material(color))
    b.initial_pose = sapien.Pose([float(center[0]), float(center[1]), height / 2 if z is None else float(z)])
    return b.build_kinematic(name) if moving else b.build_static(name)


UPRIGHT = [0.7071068, 0, 0.7071068, 0]
"""SAPIEN's cylinder axis (x) turned to the world's z"""


def add_pedestrian(scene, name: str, radius: float, height: float, position, z=None):
    """A pedestrian: an upright kinematic cylinder standing on the floor at ``position`` (x, y)
    (or with its centre at height ``z``), with a collision shape (the lasers and the robot meet
    it) and the pedestrians' colour."""
    b = scene.create_actor_builder()
    pose = sapien.Pose([0, 0, 0], UPRIGHT)
    b.add_cylinder_collision(pose, radius=radius, half_length=height / 2)
    b.add_cylinder_visual(pose, radius=radius, half_length=height / 2, material=material(PEDESTRIAN_COLOR))
    b.initial_pose = sapien.Pose([float(position[0]), float(position[1]), height / 2 if z is None else float(z)])
    return b.build_kinematic(name)


def add_target(scene, name: str, marker: bool, position) -> sapien.Entity:
    """A target: a red disc on the floor and, with ``marker``, the red column standing on it
    (``TargetMarker``); visual only (no collision shape), kinematic, at ``position`` (x, y, z)."""
    b = scene.create_actor_builder()
    upright = UPRIGHT
    b.add_cylinder_visual(
        sapien.Pose([0, 0, 0.002], upright),
        radius=TARGET_DISC_RADIUS,
        half_length=0.002,
        material=material(TARGET_COLOR),
    )
    if marker:
        m = TARGET_MARKER
        b.add_cylinder_visual(
            sapien.Pose([0, 0, m.height / 2], upright),
            radius=m.radius,
            half_length=m.height / 2,
            material=material(TARGET_COLOR),
        )
    b.initial_pose = sapien.Pose(position)
    return sapien_object(b.build_kinematic(name))


def build_world(scene, world: World) -> BuiltWorld:
    """Add ``world``'s actors to a ManiSkill scene."""
    arena = world.arena
    # floor: visual only (nothing rests on it, so it needs no collision shape)
    b = scene.create_actor_builder()
    b.initial_pose = sapien.Pose()
    b.add_box_visual(
        sapien.Pose([*arena.center, -0.01]),
        half_size=[*(arena.size / 2 + arena.wall_thickness), 0.01],
        material=material(FLOOR_COLOR),
    )
    b.build_static("floor")
    for side, (center, half) in arena.walls().items():
        add_box(scene, f"wall_{side}", center, half, arena.wall_height, WALL_COLORS[side], moving=False)

    # obstacles: static boxes, or kinematic boxes moved by their motion's mover
    movers, moving_bodies, moving_z, static_xy, static_half, moving_half = [], [], [], [], [], []
    for g, group in enumerate(world.obstacles):
        mover = group.motion.mover()
        color = MOVING_OBSTACLE_COLOR if group.moving else STATIC_OBSTACLE_COLOR
        start = mover.reset(np.random.default_rng(0))
        bodies = []
        for i in range(group.count):
            actor = add_box(scene, f"obstacle{g}_{i}", start[i], group.half_size, group.height, color, group.moving)
            if group.moving:
                bodies.append(physx_body(actor))
                moving_z.append(group.height / 2)
                moving_half.append(group.half_size)
            else:
                static_xy.append(start[i])
                static_half.append(group.half_size)
        if group.moving:
            movers.append((mover, bodies))
            moving_bodies.extend(bodies)

    # targets: red discs (and, in camera worlds, red columns) with no collision shape
    targets = []
    for t, spec in enumerate(world.targets):
        entity = add_target(scene, f"target{t}", world.target_marker, [*spec.extent()[0], HIDDEN_Z])
        targets.append((spec.mover(), entity))

    # pedestrians: upright cylinders, placed by the crowd at every reset (here: out of the way)
    pedestrians = []
    if world.pedestrians is not None:
        p = world.pedestrians
        for i in range(p.count):
            actor = add_pedestrian(scene, f"pedestrian{i}", p.radius, p.height, (arena.center[0], arena.center[1]))
            pedestrians.append(physx_body(actor))

    return BuiltWorld(
        pedestrian_bodies=pedestrians,
        movers=movers,
        moving_bodies=moving_bodies,
        moving_z=moving_z,
        static_obstacle_xy=np.array(static_xy, dtype=np.float64).reshape(-1, 2),
        obstacle_half=np.array(static_half + moving_half, dtype=np.float64).reshape(-1, 2),
        targets=targets,
    )
