"""The dynamic window approach (Fox, Burgard and Thrun, IEEE RA Magazine 4(1), 1997) on the laser
scan: the classical local planner (Nav2's DWB descends from it), on the continuous drive.

    python -m dynnav_tasks.baselines.dwa --task DynNav-MovingObstacles-v1 --episodes 200

``DWA`` knows what a robot's local planner knows and nothing more: the laser scan (its
readings as points around the robot, every reading below the range an obstacle point), the
target's distance and bearing, and its own velocity command. Each control step it

1. takes the dynamic window: every ``(v, w)`` the drive can reach within one control step from
   its current command (``max_linear_accel``, ``max_angular_accel``), ``v`` from 0 (no backing
   up, as Nav2's default) to the top speed, sampled on a ``linear_samples`` x
   ``angular_samples`` grid;
2. rolls each out as an arc for ``horizon`` seconds from the robot's pose and measures its
   clearance: the least distance from the arc to a scan point, less the robot's radius (the
   circle around its footprint) and ``safety``;
3. drops the arcs that touch (clearance <= 0 before the horizon) or that could not stop before
   the first contact at the drive's deceleration (admissible velocities);
4. scores the others ``heading_weight * heading + clearance_weight * clearance +
   speed_weight * speed``, each term divided by its largest value over the admissible arcs:
   heading = pi - |the target's bearing seen from the arc's end|, clearance capped at
   ``clearance_cap``, speed = v; and commands the best arc.

A local planner alone stalls in front of a wall between it and the target (the local minimum
every potential-field and window method has). Nav2 therefore hands its local planner a global
path through the static map; ``follow_way`` (the default) does the same: where the straight
line to the target is blocked on the static map, the heading term follows the way through it
instead (``way_sense.WaySense``, the map the procedural task's ``way`` reading comes from: walls
and static boxes only, no moving box). In the study's worlds, open arenas, the two are the same.

With no admissible arc it turns in place towards the target at the largest turn the window
allows (a rotate recovery), stopping first. The scan is all it sees of the world, static or
moving: it treats every moving box as standing where the scan found it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import tyro

from dynnav_tasks.baselines.cli import ControllerArgs, drive_controller
from dynnav_tasks.baselines.episodes import ROBOT_RADIUS, EpisodeResults, run_episodes
from dynnav_tasks.drive import VELOCITY_DRIVE
from dynnav_tasks.way_sense import WaySense


@dataclass(frozen=True)
class DWAConfig:
    """The planner's settings (defaults: Fox et al.'s weights 2 : 0.2 : 0.2, Nav2 DWB's horizon)."""

    horizon: float = 1.7
    """s: how far ahead each arc is rolled out (DWB's ``sim_time``)"""
    rollout_dt: float = 0.1
    """s between the points of a rolled-out arc"""
    linear_samples: int = 11
    """linear velocities sampled across the window"""
    angular_samples: int = 21
    """angular velocities sampled across the window"""
    heading_weight: float = 2.0
    """alpha: facing the target from the arc's end"""
    clearance_weight: float = 0.2
    """beta: the arc's distance to the nearest scan point"""
    speed_weight: float = 0.2
    """gamma: forward speed"""
    clearance_cap: float = 1.0
    """m: clearance beyond this scores the same (an open arc is as good as another)"""
    safety: float = 0.05
    """m kept between the robot's circle and every scan point"""
    follow_way: bool = True
    """head along the way through the static map where the straight line is blocked (Nav2's global path)"""


class DWA:
    """The dynamic window approach on the laser scan (a ``run_episodes`` controller; module docstring)."""

    control_mode = VELOCITY_DRIVE

    def __init__(self, config: DWAConfig = DWAConfig()):
        self.config = config
        c = config
        self._times = np.arange(1, int(round(c.horizon / c.rollout_dt)) + 1) * c.rollout_dt  # (T,)

    def start(self, env) -> None:
        """A new episode: read the drive's limits and the laser ring's ray directions."""
        drive = env.controller_config
        self._v_max, self._w_max = drive.max_linear_speed, drive.max_angular_speed
        self._dt = 1.0 / float(env.control_freq)
        self._dv, self._dw = drive.max_linear_accel * self._dt, drive.max_angular_accel * self._dt
        self._brake = drive.max_linear_accel
        self._angles = env.laser_config.angles()
        self._range = env.laser_config.max_range
        self._way = WaySense(env.world) if self.config.follow_way else None

    def window(self, v: float, w: float) -> tuple[np.ndarray, np.ndarray]:
        """The sampled ``(v, w)`` pairs, flattened, reachable in one control step from ``(v, w)``."""
        c = self.config
        vs = np.linspace(max(0.0, v - self._dv), min(self._v_max, v + self._dv), c.linear_samples)
        ws = np.linspace(max(-self._w_max, w - self._dw), min(self._w_max, w + self._dw), c.angular_samples)
        vv, ww = np.meshgrid(vs, ws, indexing="ij")
        return vv.ravel(), ww.ravel()

    def arcs(self, vs: np.ndarray, ws: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """x, y, heading (N, T) of each arc's points in the robot's frame (exact circular arcs)."""
        t = self._times[None, :]
        v, w = vs[:, None], ws[:, None]
        theta = w * t
        straight = np.abs(w) < 1e-9
        safe_w = np.where(straight, 1.0, w)
        x = np.where(straight, v * t, v / safe_w * np.sin(theta))
        y = np.where(straight, 0.0, v / safe_w * (1.0 - np.cos(theta)))
        return x, y, theta

    def act(self, env) -> np.ndarray:
        """The best admissible ``(v, w)`` for the task's current scan and target (module docstring)."""
        c, s = self.config, env.snapshot
        v0, w0 = env.agent.controller.command
        vs, ws = self.window(v0, w0)
        x, y, theta = self.arcs(vs, ws)
        seen = s.lasers < self._range - 1e-3
        px, py = (s.lasers * np.cos(self._angles))[seen], (s.lasers * np.sin(self._angles))[seen]
        radius = ROBOT_RADIUS + c.safety
        if len(px):
            gaps = np.hypot(x[..., None] - px, y[..., None] - py).min(axis=-1) - radius  # (N, T)
        else:
            gaps = np.full(x.shape, np.inf)
        touching = gaps <= 0.0
        free = ~touching.any(axis=1)
        # admissible: it can stop before its first contact (none within the horizon: always)
        contact_time = self._times[touching.argmax(axis=1)]
        admissible = free | (vs ** 2 <= 2.0 * self._brake * vs * contact_time)
        if not admissible.any():  # rotate recovery: stop and turn towards the target
            turn = math.copysign(min(self._w_max, abs(w0) + self._dw), s.bearing)
            return np.array([max(0.0, v0 - self._dv), turn], dtype=np.float32)
        tx, ty = s.d1 * math.cos(s.bearing), s.d1 * math.sin(s.bearing)
        bearing_end = np.arctan2(ty - y[:, -1], tx - x[:, -1]) - theta[:, -1]
        if self._way is not None:
            length, sin_b, cos_b = self._way.read(*s.pose, *s.target_xy)
            if length > s.d1 + 1e-6:  # the straight line is blocked: follow the way's direction
                bearing_end = math.atan2(sin_b, cos_b) - theta[:, -1]
        heading = math.pi - np.abs((bearing_end + math.pi) % (2.0 * math.pi) - math.pi)
        clearance = np.minimum(gaps.min(axis=1), c.clearance_cap)
        terms = [(c.heading_weight, heading), (c.clearance_weight, clearance), (c.speed_weight, vs)]
        score = np.zeros(len(vs))
        for weight, term in terms:
            top = term[admissible].max()
            score += weight * (term / top if top > 0 else term)
        best = int(np.argmax(np.where(admissible, score, -np.inf)))
        return np.array([vs[best], ws[best]], dtype=np.float32)


def run_dwa(task_id: str, seeds, progress: bool = False, label: Optional[str] = None, task_kwargs=None,
            config: DWAConfig = DWAConfig()) -> EpisodeResults:
    """One episode per seed of ``task_id`` (made with ``task_kwargs`` on the continuous drive) driven by ``DWA``."""
    kwargs = dict(task_kwargs or {}, control_mode=VELOCITY_DRIVE)
    return run_episodes(label or task_id, task_id, seeds, DWA(config), progress=progress, **kwargs)


@dataclass
class Args(ControllerArgs):
    task: str = "DynNav-MovingObstacles-v1"
    """task to drive in: a study task, a crowd task or a procedural one (which runs its difficulties and splits)"""


def main(args: Args) -> None:
    """Drive the episodes ``args`` names and print (and with ``--out`` record) the rates."""
    from dynnav_tasks import CROWD_TASK_IDS, TASK_IDS

    drive_controller(args, lambda task, seeds, label, kwargs: run_dwa(task, seeds, progress=True, label=label,
                                                                 task_kwargs=kwargs),
                     "dwa", TASK_IDS + CROWD_TASK_IDS)


if __name__ == "__main__":
    main(tyro.cli(Args))
