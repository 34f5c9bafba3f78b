"""Rerun recordings of dynnav episodes: the world, the lasers, the camera and the agent.

A ``Recorder`` writes a ``.rrd`` file (no viewer needed) and/or streams to a viewer it
spawns. Per environment step it logs, on the ``step`` timeline (global across episodes)
with the ``episode`` timeline set alongside:

===============================  ==========================================================
entity                           what
===============================  ==========================================================
``world``                        right-handed, z up (static)
``world/walls``                  the four walls as boxes, coloured by side (when the world changes)
``world/blocks``                 the static blocks (when the world changes; cleared if none)
``world/obstacles``              every moving box at its current position
``world/target``                 the chosen target's disc
``world/robot``                  the robot's transform (x, y, yaw); ``body`` is its footprint
``world/robot/lasers``           16 line strips from the laser ring to the readings
``world/robot/laser_hits``       points where a ray met a surface (within range)
``world/robot/camera``           the front camera: transform + pinhole (FLU axes)
``world/robot/camera/image``     the camera frame (when the task renders images)
``agent/reconstruction``         an auto-encoder's reconstruction of the frame (if given)
``agent/latent``                 the latent vector, as a bar chart (if given)
``agent/q_values``               Q-value per action, as a bar chart (if given)
``agent/action``, ``reward``     chosen action index and the step's reward (scalars)
``episode/outcome``              "success", "collision" or "timeout" at the episode's end
``training/*``                   return, loss, epsilon, success rate on the ``episode``
                                 timeline (``log_training``)
===============================  ==========================================================

The world's walls and blocks are logged on the timelines at the first step of every episode
whose world differs from the last one logged (all of a fixed-world task's episodes share the
first episode's; ``DynNav-Procedural-v1`` changes its world every episode), so that the viewer
shows, at any step, the walls and blocks of that step's world. The robot's body and camera
are the same in every world and logged once, static.

The default blueprint puts the 3D view on the left, the camera frame above its
reconstruction in the middle, and the time series on the right.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path
from typing import Optional

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from dynnav_tasks.outcomes import outcome_of
from dynnav_tasks.robot import CAMERA_OFFSET, FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT
from dynnav_tasks.scene import TARGET_DISC_RADIUS
from dynnav_tasks.world import (MOVING_OBSTACLE_COLOR, PEDESTRIAN_COLOR, STATIC_OBSTACLE_COLOR, TARGET_COLOR, WALL_COLORS,
                                 World)

MOVING_BOX_HALF_HEIGHT = 0.25
"""half the height (m) of a moving box as drawn (``world.Obstacles.height`` is 0.5 m)"""


def _rgb255(rgba) -> list[int]:
    return [int(round(255 * c)) for c in rgba[:3]]


def check_output_path(path: str | os.PathLike) -> Path:
    """Fail early, with a clear message, if a recording cannot be written to ``path``."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise ValueError(f"recording path {str(path)!r} is a folder; give a file name such as {str(path / 'run.rrd')!r}")
    if not folder.is_dir():
        raise ValueError(f"cannot write recording {str(path)!r}: folder {str(folder)!r} does not exist (create it first)")
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".dynnav-write-test-"):
            pass
    except OSError as err:
        raise ValueError(f"cannot write recording {str(path)!r}: folder {str(folder)!r} is not writable ({err.strerror})") from err
    return path


def default_blueprint() -> rrb.Blueprint:
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(name="world", origin="/world"),
            rrb.Vertical(
                rrb.Spatial2DView(name="camera", origin="/world/robot/camera/image"),
                rrb.Spatial2DView(name="reconstruction", origin="/agent/reconstruction"),
                rrb.BarChartView(name="Q-values", origin="/agent/q_values"),
            ),
            rrb.Vertical(
                rrb.TimeSeriesView(name="reward", origin="/agent/reward"),
                rrb.TimeSeriesView(name="training", origin="/training"),
                rrb.TextLogView(name="outcomes", origin="/episode"),
            ),
            column_shares=[3, 2, 2],
        ),
        collapse_panels=True,
    )


class Recorder:
    """Log dynnav episodes to Rerun. Use as a context manager, or call ``close()``.

    ``path``: a ``.rrd`` file to write (checked before anything else happens);
    ``spawn``: also open a Rerun viewer (needs a display).
    """

    def __init__(self, path: Optional[str | os.PathLike] = None, spawn: bool = False, application_id: str = "dynnav"):
        if path is None and not spawn:
            raise ValueError("a Recorder needs a path to write, spawn=True, or both")
        self.path = check_output_path(path) if path is not None else None
        self.rec = rr.RecordingStream(application_id)
        blueprint = default_blueprint()
        if self.path is not None:
            self.rec.save(self.path, default_blueprint=blueprint)
        if spawn:
            self.rec.spawn(connect=self.path is None, default_blueprint=blueprint)
        self.rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        self.step = -1
        self.episode = -1
        self._robot_logged = False
        self._world_logged: Optional[World] = None

    # ------------------------------------------------------------------ episodes
    def start_episode(self, env, episode: Optional[int] = None) -> None:
        """Log the state right after ``env.reset()``."""
        base = env.unwrapped
        self.episode = self.episode + 1 if episode is None else episode
        self.step += 1
        self._set_time()
        if not self._robot_logged:
            self._log_robot_parts(base)
            self._robot_logged = True
        world = base.world
        if world is not self._world_logged and world != self._world_logged:
            self._log_world(world)
            self._world_logged = world
        self._log_state(base)

    def log_step(self, env, action: Optional[int] = None, reward: Optional[float] = None,
                 q_values=None, latent=None, reconstruction=None) -> None:
        """Log the state after one ``env.step(action)`` and what the agent thought."""
        self.step += 1
        self._set_time()
        base = env.unwrapped
        self._log_state(base)
        rec = self.rec
        if action is not None:
            rec.log("agent/action", rr.Scalars(float(action)))
        if reward is not None:
            rec.log("agent/reward", rr.Scalars(float(reward)))
        if q_values is not None:
            rec.log("agent/q_values", rr.BarChart(np.asarray(q_values, dtype=np.float32).reshape(-1)))
        if latent is not None:
            rec.log("agent/latent", rr.BarChart(np.asarray(latent, dtype=np.float32).reshape(-1)))
        if reconstruction is not None:
            rec.log("agent/reconstruction", rr.Image(np.asarray(reconstruction)))

    def end_episode(self, info: dict) -> str:
        """Log the episode's outcome (``outcomes.outcome_of`` the last step's ``info``) and return it."""
        outcome = outcome_of(info)
        level = rr.TextLogLevel.INFO if outcome == "success" else rr.TextLogLevel.WARN
        self.rec.log("episode/outcome", rr.TextLog(f"episode {self.episode}: {outcome}", level=level))
        return outcome

    def log_training(self, episode: int, **scalars: float) -> None:
        """Training curves (return, loss, epsilon, success_rate, ...) on the episode timeline."""
        self.rec.set_time("episode", sequence=episode)
        for name, value in scalars.items():
            if value is not None and np.isfinite(value):
                self.rec.log(f"training/{name}", rr.Scalars(float(value)))

    def close(self) -> None:
        self.rec.flush()
        self.rec.disconnect()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ------------------------------------------------------------------ logging
    def _set_time(self):
        self.rec.set_time("step", sequence=self.step)
        self.rec.set_time("episode", sequence=max(self.episode, 0))

    def _log_world(self, world: World) -> None:
        """The walls and static blocks of ``world``, at the current step; clears the moving
        boxes of the previous world (``_log_state`` logs this world's)."""
        rec, arena = self.rec, world.arena
        walls = arena.walls()
        rec.log("world/walls", rr.Boxes3D(
            centers=[[c[0], c[1], arena.wall_height / 2] for c, _ in walls.values()],
            half_sizes=[[h[0], h[1], arena.wall_height / 2] for _, h in walls.values()],
            colors=[_rgb255(WALL_COLORS[side]) for side in walls],
            fill_mode="solid",
        ))
        blocks = [group for group in world.obstacles if not group.moving]
        if blocks:
            rec.log("world/blocks", rr.Boxes3D(
                centers=[[g.motion.at[0], g.motion.at[1], g.height / 2] for g in blocks],
                half_sizes=[[g.half_size[0], g.half_size[1], g.height / 2] for g in blocks],
                colors=[_rgb255(STATIC_OBSTACLE_COLOR)], fill_mode="solid",
            ))
        else:
            rec.log("world/blocks", rr.Clear(recursive=False))
        rec.log("world/obstacles", rr.Clear(recursive=False))

    def _log_robot_parts(self, base) -> None:
        """The robot's footprint and front camera (the same in every world), static."""
        rec = self.rec
        rec.log("world/robot/body", rr.Boxes3D(
            centers=[[0, 0, 0.16]], half_sizes=[[FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, 0.1]],
            colors=[[80, 82, 97]], fill_mode="solid",
        ), static=True)
        spec = base.camera_spec
        focal = (spec.size / 2) / math.tan(spec.fov / 2)
        half = spec.pitch / 2
        rec.log("world/robot/camera", rr.Transform3D(
            translation=list(CAMERA_OFFSET), quaternion=[0.0, math.sin(half), 0.0, math.cos(half)],
        ), static=True)
        rec.log("world/robot/camera", rr.Pinhole(
            focal_length=focal, width=spec.size, height=spec.size, camera_xyz=rr.ViewCoordinates.FLU,
            image_plane_distance=0.3,
        ), static=True)

    def _log_state(self, base) -> None:
        rec, snap = self.rec, base.snapshot
        x, y, yaw = snap.pose
        rec.log("world/robot", rr.Transform3D(
            translation=[x, y, 0.0], rotation=rr.RotationAxisAngle(axis=[0, 0, 1], radians=yaw),
        ))
        # lasers, in the robot's frame
        readings = snap.lasers.astype(np.float64)
        angles = base.laser_angles
        ends = np.stack([readings * np.cos(angles), readings * np.sin(angles), np.full_like(readings, LASER_HEIGHT)], axis=1)
        start = np.array([0.0, 0.0, LASER_HEIGHT])
        rec.log("world/robot/lasers", rr.LineStrips3D([[start, e] for e in ends], colors=[[255, 60, 60]], radii=0.005))
        hit = readings < base.laser_range - 1e-6
        rec.log("world/robot/laser_hits", rr.Points3D(ends[hit], colors=[[255, 200, 0]], radii=0.03))
        # moving boxes and target, in the world frame (the blocks are logged with the world)
        if snap.moving_count:
            centers, half = snap.moving_obstacle_xy, snap.obstacle_half[-snap.moving_count:]
            rec.log("world/obstacles", rr.Boxes3D(
                centers=[[c[0], c[1], MOVING_BOX_HALF_HEIGHT] for c in centers],
                half_sizes=[[h[0], h[1], MOVING_BOX_HALF_HEIGHT] for h in half],
                colors=[_rgb255(MOVING_OBSTACLE_COLOR)], fill_mode="solid",
            ))
        if len(snap.human_xy):  # the pedestrians, and a line to the goal each heads for
            goals = base.pedestrian_goals
            height = base.world.pedestrians.height
            rec.log("world/pedestrians", rr.Cylinders3D(
                centers=[[p[0], p[1], height / 2] for p in snap.human_xy.tolist()], lengths=[height],
                radii=snap.human_radius.tolist(), colors=[_rgb255(PEDESTRIAN_COLOR)], fill_mode="solid",
            ))
            rec.log("world/pedestrian_goals", rr.LineStrips3D(
                [[[p[0], p[1], 0.01], [g[0], g[1], 0.01]] for p, g in zip(snap.human_xy.tolist(), goals.tolist())],
                colors=[_rgb255(PEDESTRIAN_COLOR)], radii=0.01,
            ))
        tx, ty = (float(v) for v in snap.target_xy)
        rec.log("world/target", rr.Cylinders3D(
            centers=[[tx, ty, 0.002]], lengths=[0.004], radii=[TARGET_DISC_RADIUS],
            colors=[_rgb255(TARGET_COLOR)], fill_mode="solid",
        ))
        frame = base.last_camera_frame
        if frame is not None:
            rec.log("world/robot/camera/image", rr.Image(frame))
