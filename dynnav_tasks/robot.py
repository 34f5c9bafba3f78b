"""The dynnav wheeled robot ("diffbot") and its discrete differential-drive controller.

The robot is a ManiSkill agent loaded from ``assets/diffbot/diffbot.urdf``: a Pioneer-like
chassis (footprint 0.45 m x 0.38 m) whose base moves in the plane through three virtual
joints (world x, world y, yaw), driven by joint velocity targets as ManiSkill's Fetch base is.

Actions are ``Discrete(3)``:

=====  ========  =====================================================================
index  name      motion during one control step (defaults, see ``DriveConfig``)
=====  ========  =====================================================================
0      forward   ``forward_step`` = 0.15 m straight ahead
1      left      turn ``turn_step`` = pi/8 rad (22.5 deg) counter-clockwise, advancing
                 ``turn_forward_step`` = 0 m (in place)
2      right     as ``left``, clockwise
=====  ========  =====================================================================

The per-step distances are converted to velocities with the control frequency, so changing
``control_freq`` does not change how far an action moves the robot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from gymnasium import spaces
from mani_skill.agents.base_agent import BaseAgent
from mani_skill.agents.controllers.base_controller import BaseController, ControllerConfig
from mani_skill.agents.registration import register_agent

ASSET_DIR = Path(__file__).resolve().parent.parent / "assets" / "diffbot"
BASE_JOINTS = ["root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint"]
ACTION_NAMES = ("forward", "left", "right")

# Footprint of everything that collides (chassis box and both wheels), in the chassis frame.
FOOTPRINT_HALF_LENGTH = 0.225  # m, along x (forward)
FOOTPRINT_HALF_WIDTH = 0.19  # m, along y (wheel outer faces)
LASER_HEIGHT = 0.30  # m above the floor (the laser_ring link)
CAMERA_OFFSET = (0.19, 0.0, 0.36)  # camera_link position in the chassis frame


@dataclass
class DriveConfig(ControllerConfig):
    """Discrete drive: how far each of the three actions moves the robot in one step."""

    joint_names: list[str] = field(default_factory=lambda: list(BASE_JOINTS))
    forward_step: float = 0.15
    """metres travelled by the forward action in one control step"""
    turn_step: float = math.pi / 8
    """radians turned by the left / right actions in one control step"""
    turn_forward_step: float = 0.0
    """metres travelled forward while turning (0: turn in place)"""
    damping: float = 1e4
    """velocity-drive damping of the planar joints (N s/m); high, so targets are met at once"""
    force_limit: float = 1e4
    """drive force limit of the planar joints"""
    controller_cls = None  # set below

    def validate(self):
        for name in ("forward_step", "turn_step"):
            if not getattr(self, name) > 0:
                raise ValueError(f"DriveConfig.{name} must be > 0, got {getattr(self, name)!r}")
        if self.turn_forward_step < 0:
            raise ValueError(f"DriveConfig.turn_forward_step must be >= 0, got {self.turn_forward_step!r}")


class DiscreteDriveController(BaseController):
    """Maps a discrete action to velocity targets of the planar base joints.

    Works on the CPU simulation with numpy only (one environment), which keeps the step lean.
    """

    config: DriveConfig
    sets_target_qpos = False
    sets_target_qvel = True

    def _initialize_action_space(self):
        self.single_action_space = spaces.Discrete(len(ACTION_NAMES))
        self._px_art = self.articulation._objs[0]
        self._px_joints = [joint._objs[0] for joint in self.joints]  # ManiSkill resolved the names
        self._dof_index = [int(i) for i in self.active_joint_indices]
        self._dof = self._px_art.dof
        self.configure(self.config)

    def configure(self, config: DriveConfig) -> None:
        """Use the step lengths of ``config`` from now on."""
        self.config = config
        rate = float(self._control_freq)
        c = config
        # (linear velocity m/s, angular velocity rad/s) per action
        self._twists = np.array(
            [
                [c.forward_step * rate, 0.0],
                [c.turn_forward_step * rate, c.turn_step * rate],
                [c.turn_forward_step * rate, -c.turn_step * rate],
            ]
        )
        self._twist = np.zeros(2)

    def set_drive_property(self):
        for joint in self._px_joints:
            joint.set_drive_properties(0.0, self.config.damping, self.config.force_limit, "force")
            joint.set_friction(0.0)

    def reset(self):
        self._twist = np.zeros(2)

    def set_action(self, action) -> None:
        index = int(np.asarray(action).reshape(-1)[0]) if not isinstance(action, (int, np.integer)) else int(action)
        if not 0 <= index < len(ACTION_NAMES):
            raise ValueError(f"action must be an integer in [0, {len(ACTION_NAMES)}) ({', '.join(ACTION_NAMES)}), got {action!r}")
        self._twist = self._twists[index]

    def before_simulation_step(self):
        """Turn the body-frame twist into world-frame joint velocities at the current heading."""
        qpos = self._px_art.get_qpos()
        yaw = qpos[self._dof_index[2]]
        v, w = self._twist
        target = (v * math.cos(yaw), v * math.sin(yaw), w)
        qvel = np.zeros(self._dof, dtype=np.float32)
        for joint, i, t in zip(self._px_joints, self._dof_index, target):
            joint.set_drive_velocity_target(t)
            qvel[i] = t
        # start every sub-step at the commanded velocity: steps have exact lengths and no lag
        self._px_art.set_qvel(qvel)


DriveConfig.controller_cls = DiscreteDriveController


@register_agent()
class DiffBot(BaseAgent):
    """A Pioneer-like differential-drive robot with a 16-laser ring and a front camera."""

    uid = "dynnav_diffbot"
    urdf_path = str(ASSET_DIR / "diffbot.urdf")
    fix_root_link = True
    disable_self_collisions = True
    drive_config: DriveConfig = DriveConfig()

    @property
    def _controller_configs(self):
        return dict(discrete_drive=self.drive_config)

    def pose2d(self) -> np.ndarray:
        """(x, y, yaw) of the chassis in the world, as numpy."""
        return np.asarray(self.robot._objs[0].get_qpos()[:3], dtype=np.float64)

    def set_pose2d(self, x: float, y: float, yaw: float) -> None:
        """Place the robot at (x, y) facing ``yaw`` (radians), at rest."""
        art = self.robot._objs[0]
        art.set_qpos(np.array([x, y, yaw], dtype=np.float32))
        art.set_qvel(np.zeros(3, dtype=np.float32))
