"""The dynnav wheeled robot ("diffbot") and its discrete differential-drive controller.

The robot is a ManiSkill agent (``diffbot.DiffBot``) loaded from ``assets/diffbot/diffbot.urdf``:
a Pioneer-like chassis (footprint 0.45 m x 0.38 m) whose base moves in the plane through three
virtual joints (world x, world y, yaw), driven by joint velocity targets as ManiSkill's Fetch
base is. This module holds its geometry, the discrete drive's step lengths and controller.

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

This is the default control mode, ``"discrete_drive"``; ``control_mode="diff_drive_vel"``
drives the robot by linear and angular velocity instead (``drive.py``).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from gymnasium import spaces
from mani_skill.agents.controllers.base_controller import BaseController, ControllerConfig

from .maniskill_adapter import sapien_object

ASSET_DIR = Path(__file__).resolve().parent.parent / "assets" / "diffbot"
BASE_JOINTS = ["root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint"]
ACTION_NAMES = ("forward", "left", "right")

# Footprint of everything that collides (chassis box and both wheels), in the chassis frame.
FOOTPRINT_HALF_LENGTH = 0.225  # m, along x (forward)
FOOTPRINT_HALF_WIDTH = 0.19  # m, along y (wheel outer faces)
LASER_HEIGHT = 0.30  # m above the floor (the laser_ring link)
CAMERA_OFFSET = (0.19, 0.0, 0.36)  # camera_link position in the chassis frame

MAX_FORWARD_STEP = 0.5
"""Longest forward step (m). Collisions are checked at each of a control step's 4 PhysX
sub-steps, so a sub-step moves the robot at most 0.125 m, plus at most 0.125 m of the fastest
obstacle (0.5 m per step): far less than the 0.55 m it would take to pass through the thinnest
thing in a world (a 0.1 m wall) with the robot's 0.45 m length."""
MAX_TURN_STEP = math.pi / 2
"""Largest turn (rad) of one step: a sub-step turns at most pi/8, the default turn of a whole
step, so the footprint's corners (0.29 m from its centre) move at most 0.12 m between checks."""


def parse_action(action) -> int:
    """The action index of ``action``: an integer in {0, 1, 2}.

    Python and numpy integers, and 0-d or 1-element integer arrays or tensors, are accepted;
    anything else (floats such as 1.5, booleans, strings, several values) is a ValueError.
    """
    if isinstance(action, (int, np.integer)) and not isinstance(action, (bool, np.bool_)):
        index = int(action)
    else:
        if hasattr(action, "detach"):  # a torch tensor
            action = action.detach().cpu().numpy()
        array = action if isinstance(action, np.ndarray) else None
        if array is None or array.size != 1 or array.dtype.kind not in "iu":
            raise ValueError(
                f"action must be an integer in [0, {len(ACTION_NAMES)}) ({', '.join(ACTION_NAMES)}), "
                f"given as an int, a numpy integer or a one-element integer array; got {action!r}"
            )
        index = int(array.reshape(-1)[0])
    if not 0 <= index < len(ACTION_NAMES):
        raise ValueError(f"action must be an integer in [0, {len(ACTION_NAMES)}) ({', '.join(ACTION_NAMES)}), got {index}")
    return index


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
        """Raise ValueError unless every step length is a finite number within its bounds."""
        for name, low, high, unit in (
            ("forward_step", 0.0, MAX_FORWARD_STEP, "m"),
            ("turn_step", 0.0, MAX_TURN_STEP, "rad"),
            ("turn_forward_step", None, MAX_FORWARD_STEP, "m"),
        ):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"DriveConfig.{name} must be a finite number, got {value!r}")
            above = value > low if low is not None else value >= 0
            if not (above and value <= high):
                lower = f"> {low}" if low is not None else ">= 0"
                raise ValueError(
                    f"DriveConfig.{name} must be {lower} and <= {high:.4g} {unit}, got {value!r}: a longer step "
                    "could carry the robot through a wall or an obstacle between two collision checks"
                )


class DiscreteDriveController(BaseController):
    """Maps a discrete action to velocity targets of the planar base joints.

    Works on the CPU simulation with numpy only (one environment), which keeps the step lean.
    """

    config: DriveConfig
    sets_target_qpos = False
    sets_target_qvel = True

    def _initialize_action_space(self):
        self.single_action_space = spaces.Discrete(len(ACTION_NAMES))
        self._px_art = sapien_object(self.articulation)
        self._px_joints = [sapien_object(joint) for joint in self.joints]  # ManiSkill resolved the names
        self._dof_index = [int(i) for i in self.active_joint_indices]
        self._dof = self._px_art.dof
        self._qvel = np.zeros(self._dof, dtype=np.float32)
        self._yaw_index = self._dof_index[2]
        self._commanded = None
        self.configure(self.config)

    def configure(self, config: DriveConfig) -> None:
        """Use the step lengths of ``config`` from now on."""
        self.config = config
        rate = float(self._control_freq)
        c = config
        # (linear velocity m/s, angular velocity rad/s) per action, as Python floats
        self._twists = (
            (float(c.forward_step * rate), 0.0),
            (float(c.turn_forward_step * rate), float(c.turn_step * rate)),
            (float(c.turn_forward_step * rate), float(-c.turn_step * rate)),
        )
        self._twist = (0.0, 0.0)

    def set_drive_property(self):
        for joint in self._px_joints:
            joint.set_drive_properties(0.0, self.config.damping, self.config.force_limit, "force")
            joint.set_friction(0.0)

    def reset(self):
        self._twist = (0.0, 0.0)
        self._commanded = None

    def parse_action(self, action) -> int:
        """The action index of ``action`` (module function ``parse_action``)."""
        return parse_action(action)

    def set_action(self, action) -> None:
        self._twist = self._twists[parse_action(action)]

    def before_simulation_step(self):
        """Turn the body-frame twist into world-frame joint velocities at the current heading.

        Every sub-step starts at the commanded velocity, so steps have exact lengths and no
        lag; PhysX is only told again when the command changes (it does not change within a
        straight move or a turn in place).
        """
        v, w = self._twist
        if v != 0.0:
            yaw = self._px_art.get_qpos().item(self._yaw_index)
            target = (v * math.cos(yaw), v * math.sin(yaw), w)
        else:
            target = (0.0, 0.0, w)
        if target != self._commanded:
            qvel = self._qvel
            for joint, i, t in zip(self._px_joints, self._dof_index, target):
                joint.set_drive_velocity_target(t)
                qvel[i] = t
            self._commanded = target
        self._px_art.set_qvel(self._qvel)


DriveConfig.controller_cls = DiscreteDriveController
