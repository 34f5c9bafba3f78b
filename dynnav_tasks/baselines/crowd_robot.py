"""The robot driven by a pedestrian model: CrowdNav's classical baselines (an ORCA robot and a
social-force robot), on the continuous drive.

    python -m dynnav_tasks.baselines.crowd_robot --model orca --episodes 500 \
        --options humans=5,scenario=circle_crossing,on_arrival=stop --out docs/results/baselines.json

``CrowdRobot`` plans as one more pedestrian would: from the pedestrians' places and velocities
(the full state, as CrowdNav's baselines read it; the velocities from their last step) and the
walls and static boxes, the model gives the velocity the robot would take at its place heading
for the target at ``preferred_speed`` (by default the pedestrians' 0.75 m/s). With ORCA the robot
takes the whole avoidance of a pedestrian that does not see it and half of one that does. The
velocity, a direction the robot may not face, becomes the drive's command: forward speed its
length times the cosine of the heading error (0 when the error exceeds a right angle: turn
first), turn rate the heading error over one control step; both clipped to the drive's limits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import tyro

from dynnav_tasks.baselines.cli import ControllerArgs, drive_controller
from dynnav_tasks.baselines.episodes import ROBOT_RADIUS, EpisodeResults, run_episodes
from dynnav_tasks.baselines.way_grid import static_boxes
from dynnav_tasks.crowd import orca, social_force
from dynnav_tasks.crowd.crowd import MODELS
from dynnav_tasks.drive import VELOCITY_DRIVE
from dynnav_tasks.errors import check_choice


class CrowdRobot:
    """The robot as a pedestrian of ``model`` would walk (a ``run_episodes`` controller; module docstring)."""

    control_mode = VELOCITY_DRIVE

    def __init__(self, model: str = "orca", preferred_speed: Optional[float] = None):
        self.model = check_choice(model, MODELS, "model")
        self.preferred_speed = preferred_speed

    def start(self, env) -> None:
        """A new episode: the drive's limits, the world's walls and boxes, no pedestrian velocity yet."""
        drive, spec = env.controller_config, env.world.pedestrians
        self._dt = 1.0 / float(env.control_freq)
        self._v_max, self._w_max = drive.max_linear_speed, drive.max_angular_speed
        self._speed = self.preferred_speed or (spec.preferred_speed if spec is not None else 0.75)
        self._share = 0.5 if spec is not None and spec.see_robot else 1.0
        arena = env.world.arena
        walls = [(c[0] - h[0], c[1] - h[1], c[0] + h[0], c[1] + h[1]) for c, h in arena.walls().values()]
        self._boxes = np.array(walls + static_boxes(env.world), dtype=np.float64).reshape(-1, 4)
        self._previous = None

    def act(self, env) -> np.ndarray:
        """The model's velocity for the robot, as a ``(v, w)`` command."""
        s = env.snapshot
        x, y, yaw = s.pose
        humans = np.asarray(s.human_xy, dtype=np.float64).reshape(-1, 2)
        velocities = np.zeros_like(humans) if self._previous is None else (humans - self._previous) / self._dt
        self._previous = humans.copy()
        v_now, _ = env.agent.controller.command
        here, now = np.array([[x, y]]), np.array([[v_now * math.cos(yaw), v_now * math.sin(yaw)]])
        target = np.asarray(s.target_xy, dtype=np.float64)[None]
        speed = np.array([self._speed])
        if self.model == "orca":
            to_target = target - here
            distance = float(np.hypot(*to_target[0]))
            preferred = to_target / max(distance, 1e-9) * min(self._speed, distance / self._dt)
            others = [(tuple(p), tuple(v), float(r), self._share)
                      for p, v, r in zip(humans.tolist(), velocities.tolist(), np.asarray(s.human_radius).tolist())]
            wish = orca.orca_velocities(here, now, np.array([ROBOT_RADIUS]), preferred, speed, self._dt,
                                        others=tuple(others), boxes=self._boxes)[0]
        else:
            a = social_force.accelerations(here, now, np.array([ROBOT_RADIUS]), target, speed,
                                           bodies=(humans, np.asarray(s.human_radius, dtype=np.float64)),
                                           boxes=self._boxes)
            wish = social_force.step_velocities(now, a, speed, self._dt)[0]
        return self.command(float(wish[0]), float(wish[1]), yaw)

    def command(self, vx: float, vy: float, yaw: float) -> np.ndarray:
        """``(v, w)`` that follows the world-frame velocity ``(vx, vy)`` from heading ``yaw`` (module docstring)."""
        speed = math.hypot(vx, vy)
        if speed < 1e-9:
            return np.zeros(2, dtype=np.float32)
        error = (math.atan2(vy, vx) - yaw + math.pi) % (2.0 * math.pi) - math.pi
        v = min(speed * max(math.cos(error), 0.0), self._v_max)
        w = min(max(error / self._dt, -self._w_max), self._w_max)
        return np.array([v, w], dtype=np.float32)


def run_crowd_robot(task_id: str, seeds, model: str = "orca", progress: bool = False, label: Optional[str] = None,
                    task_kwargs=None) -> EpisodeResults:
    """One episode per seed of ``task_id`` (made with ``task_kwargs`` on the continuous drive) driven by ``CrowdRobot``."""
    kwargs = dict(task_kwargs or {}, control_mode=VELOCITY_DRIVE)
    return run_episodes(label or f"{model} robot", task_id, seeds, CrowdRobot(model), progress=progress, **kwargs)


@dataclass
class Args(ControllerArgs):
    model: str = "orca"
    """the pedestrian model that drives the robot: "orca" or "social_force\""""
    task: str = "DynNav-Crowd-v1"
    """a task with pedestrians (its scenario and crowd go in --options, e.g. humans=10,scenario=corridor)"""
    episodes: int = 500
    """episodes (seeds first_seed .. first_seed + episodes - 1)"""


def main(args: Args) -> None:
    """Drive the episodes ``args`` names and print (and with ``--out`` record, as
    ``{model}_robot/<task> [options]``) the rates and the social metrics."""
    from dynnav_tasks import CROWD_TASK_IDS

    try:
        check_choice(args.model, MODELS, "model")
    except ValueError as err:
        raise SystemExit(f"error: --model: {err}")
    drive_controller(args, lambda task, seeds, label, kwargs: run_crowd_robot(task, seeds, args.model, progress=True,
                                                                             label=label, task_kwargs=kwargs),
                     f"{args.model}_robot", CROWD_TASK_IDS)


if __name__ == "__main__":
    main(tyro.cli(Args))
