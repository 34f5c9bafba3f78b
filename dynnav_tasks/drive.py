"""The robot's control modes: the study's discrete drive and a continuous velocity drive.

Every task takes ManiSkill's ``control_mode``::

    gym.make("DynNav-MovingObstacles-v1")                                # "discrete_drive"
    gym.make("DynNav-MovingObstacles-v1", control_mode="diff_drive_vel")

=====================  ==============================================================
control mode           action
=====================  ==============================================================
``"discrete_drive"``   ``Discrete(3)``: forward, left, right (the study's; the default,
                       ``robot.DriveConfig``)
``"diff_drive_vel"``   ``Box(2)``, float32: ``(v, w)``, the linear velocity (m/s, forward
                       positive) and the angular velocity (rad/s, counter-clockwise
                       positive) of a differential drive (``VelocityDriveConfig``)
=====================  ==============================================================

The velocity drive's limits are a Pioneer 3-DX's (the thesis's robot; the manufacturer gives
1.2 m/s and 300 deg/s), and the box is ``[-1.2, 1.2] x [-5.236, 5.236]``: the robot drives
backwards as fast as forwards, as the Pioneer does. Each control step (0.2 s) the command
moves from the previous one towards the asked ``(v, w)`` by at most
``max_linear_accel`` x 0.2 s = 0.2 m/s and ``max_angular_accel`` x 0.2 s = 0.873 rad/s
(1.0 m/s^2 and 250 deg/s^2: the top speed and the top turn rate are reached in 6 steps,
1.2 s, from standstill), and is then held for the step's 4 PhysX sub-steps, the world-frame
velocity following the heading at each sub-step. The command is 0 at every reset.

Actions outside the box are clipped to it (each component on its own); an action with a NaN
or an infinity, or that is not two numbers, is refused with a ValueError.

No tunnelling, at top speed
    Collisions are checked at each PhysX sub-step (``robot.MAX_FORWARD_STEP``): a sub-step
    may move the robot at most ``MAX_FORWARD_STEP / 4`` = 0.125 m and turn it at most
    ``MAX_TURN_STEP / 4`` = pi/8, the bounds the discrete drive's longest steps keep. At the
    tasks' 20 Hz physics that is ``MAX_LINEAR_SPEED`` = 0.125 m x 20 /s = 2.5 m/s and
    ``MAX_ANGULAR_SPEED`` = pi/8 x 20 /s = 7.85 rad/s, and ``VelocityDriveConfig.validate``
    refuses limits beyond them (a different physics rate scales them:
    ``limits_at(sim_freq)``). The Pioneer's limits are within them: 1.2 m/s is 0.06 m a
    sub-step and 300 deg/s is 0.26 rad (15 deg); together, a corner of the footprint (0.295 m
    from the centre) moves at most 0.06 + 0.26 x 0.295 = 0.137 m a sub-step. With the fastest
    box's 0.125 m (0.5 m a step) the two close in by at most 0.26 m a sub-step, far less than
    the 0.55 m it would take to pass through the thinnest thing in a world (a 0.1 m wall) with
    the robot's 0.45 m length.

Noise (``noise.py``) in this mode
    ``action_noise`` is the std of Gaussian noise added to the command, as a fraction of each
    limit (0.05: 0.06 m/s and 0.26 rad/s), the noisy command clipped to the box; the robot
    speed scale multiplies the executed velocities and both accelerations (the action box
    stays the same; a scale of 1.5 makes the top speed 1.8 m/s).

What it can reach: straight ahead, 0.84 m in the first 6 steps (1.2 s) from standstill, then
0.24 m per step (the discrete forward step is 0.15 m); a full turn in place in 9 steps (1.8 s)
from standstill (the discrete drive: 16 steps); arcs of any radius down to turning in place;
backwards as fast as forwards. The
full-state planner and the camera pilot (``baselines/``) plan in the discrete actions and
drive ``"discrete_drive"`` only.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field, replace

import numpy as np
from gymnasium import spaces
from mani_skill.agents.controllers.base_controller import ControllerConfig

from .robot import BASE_JOINTS, MAX_FORWARD_STEP, MAX_TURN_STEP, DiscreteDriveController

DISCRETE_DRIVE = "discrete_drive"
"""the study's three actions (the default control mode)"""
VELOCITY_DRIVE = "diff_drive_vel"
"""linear and angular velocity, ``Box(2)``"""
CONTROL_MODES = (DISCRETE_DRIVE, VELOCITY_DRIVE)
"""every task's control modes; the first is the default"""

SIM_FREQ = 20
"""the tasks' PhysX rate (Hz): 4 sub-steps of a 5 Hz control step"""
MAX_SUB_STEP_MOVE = MAX_FORWARD_STEP / 4
"""longest move of one PhysX sub-step (m): the discrete drive's longest step over its 4 sub-steps"""
MAX_SUB_STEP_TURN = MAX_TURN_STEP / 4
"""largest turn of one PhysX sub-step (rad)"""


def limits_at(sim_freq: float) -> tuple[float, float]:
    """(top linear speed m/s, top angular speed rad/s) that keep every sub-step of a
    ``sim_freq`` Hz physics within ``MAX_SUB_STEP_MOVE`` and ``MAX_SUB_STEP_TURN``."""
    return MAX_SUB_STEP_MOVE * sim_freq, MAX_SUB_STEP_TURN * sim_freq


MAX_LINEAR_SPEED, MAX_ANGULAR_SPEED = limits_at(SIM_FREQ)
"""the fastest limits the collision check allows at the tasks' 20 Hz: 2.5 m/s, 7.85 rad/s"""

PIONEER_LINEAR_SPEED = 1.2
"""m/s: a Pioneer 3-DX's top speed, forwards and backwards (the manufacturer's figure)"""
PIONEER_ANGULAR_SPEED = math.radians(300.0)
"""rad/s: a Pioneer 3-DX's top turn rate, 300 deg/s"""


@dataclass
class VelocityDriveConfig(ControllerConfig):
    """Continuous differential drive: the limits of ``(v, w)`` (module docstring).

    As task options (flat keyword arguments of ``gym.make``, with
    ``control_mode="diff_drive_vel"``): ``max_linear_speed``, ``max_angular_speed``,
    ``max_linear_accel``, ``max_angular_accel``."""

    joint_names: list[str] = field(default_factory=lambda: list(BASE_JOINTS))
    max_linear_speed: float = PIONEER_LINEAR_SPEED
    """m/s: the action box's linear bound, forwards and backwards"""
    max_angular_speed: float = PIONEER_ANGULAR_SPEED
    """rad/s: the action box's angular bound, both ways"""
    max_linear_accel: float = 1.0
    """m/s^2: how fast the linear command may change, applied once per control step"""
    max_angular_accel: float = math.radians(250.0)
    """rad/s^2: how fast the angular command may change, applied once per control step"""
    speed_scale: float = 1.0
    """factor of the executed velocities and accelerations (the noise's per-episode robot speed
    scale; the action box keeps the nominal limits)"""
    damping: float = 1e4
    """velocity-drive damping of the planar joints (N s/m); high, so targets are met at once"""
    force_limit: float = 1e4
    """drive force limit of the planar joints"""
    controller_cls = None  # set below

    OPTIONS = ("max_linear_speed", "max_angular_speed", "max_linear_accel", "max_angular_accel")
    """the fields a task takes as flat options"""

    @classmethod
    def from_task_options(cls, control_mode: str, options: dict) -> "VelocityDriveConfig":
        """The config of a task's flat options, which are taken out of ``options`` (its other
        keyword arguments); they are refused unless ``control_mode`` is the velocity drive."""
        given = {name: options.pop(name) for name in cls.OPTIONS if name in options}
        if given and control_mode != VELOCITY_DRIVE:
            raise ValueError(f"{', '.join(sorted(given))} set(s) the velocity drive's limits: make the task with "
                             f"control_mode={VELOCITY_DRIVE!r} (got control_mode={control_mode!r})")
        config = cls(**given)
        config.validate()
        return config

    def validate(self, sim_freq: float = SIM_FREQ) -> None:
        """Raise ValueError unless every limit is a finite positive number and the scaled top
        speeds keep a ``sim_freq`` Hz sub-step within the collision check's bounds."""
        for name in (*self.OPTIONS, "speed_scale"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
                raise ValueError(f"VelocityDriveConfig.{name} must be a finite number > 0, got {value!r}")
        top_v, top_w = limits_at(sim_freq)
        for name, top, unit in (("max_linear_speed", top_v, "m/s"), ("max_angular_speed", top_w, "rad/s")):
            value = getattr(self, name) * self.speed_scale
            if value > top * (1 + 1e-12):
                scaled = f" x speed scale {self.speed_scale:.4g}" if self.speed_scale != 1.0 else ""
                raise ValueError(
                    f"VelocityDriveConfig.{name}{scaled} must be <= {top:.4g} {unit} at {sim_freq:g} Hz physics, got "
                    f"{value!r}: a faster robot could pass through a wall or an obstacle between two collision checks"
                )

    def scaled(self, factor: float) -> "VelocityDriveConfig":
        """This drive with its executed velocities and accelerations multiplied by ``factor``."""
        return replace(self, speed_scale=self.speed_scale * float(factor))

    def box_high(self) -> tuple[float, float]:
        """The action box's upper bounds ``(v, w)``, as the float32 box holds them."""
        return float(np.float32(self.max_linear_speed)), float(np.float32(self.max_angular_speed))

    def action_space(self) -> spaces.Box:
        """``Box([-v, -w], [v, w])``, float32, of the nominal limits."""
        high = np.array(self.box_high(), dtype=np.float32)
        return spaces.Box(low=-high, high=high, dtype=np.float32)

    def clip(self, v: float, w: float) -> tuple[float, float]:
        """``(v, w)`` clipped to the action box."""
        return clip_to(v, w, self.box_high())


def clip_to(v: float, w: float, high: tuple[float, float]) -> tuple[float, float]:
    """``(v, w)`` clipped to ``[-high, high]``, each component on its own."""
    hv, hw = high
    return min(max(v, -hv), hv), min(max(w, -hw), hw)


def parse_velocity_action(action, high: tuple[float, float]) -> tuple[float, float]:
    """``(v, w)`` of ``action``, clipped to the box ``[-high, high]``, as Python floats.

    Accepted: two real numbers in any form (a list or tuple, a numpy array or torch tensor of
    shape (2,), (1, 2) or the like); NaN or infinity, booleans, strings or another count of
    values are a ValueError."""
    if type(action) is np.ndarray and action.size == 2 and action.dtype.kind == "f":
        array = action  # the common case, checked first: a float array from a policy
    else:
        if hasattr(action, "detach"):  # a torch tensor
            action = action.detach().cpu().numpy()
        try:
            array = np.asarray(action)
        except (TypeError, ValueError):
            array = None
        if array is None or array.size != 2 or array.dtype.kind not in "iuf":
            raise ValueError(
                f"control_mode {VELOCITY_DRIVE!r} takes an action of two numbers, (linear m/s, angular rad/s) "
                f"within +-({high[0]:.4g}, {high[1]:.4g}); got {action!r}"
            )
    v, w = array.reshape(-1).tolist()
    v, w = float(v), float(w)
    if not (math.isfinite(v) and math.isfinite(w)):
        raise ValueError(f"action must be finite, got {action!r}: NaN and infinite velocities are refused")
    return clip_to(v, w, high)


class VelocityDriveController(DiscreteDriveController):
    """Maps ``(v, w)`` to velocity targets of the planar base joints, within the acceleration
    limits (module docstring); numpy only, one environment, as its base class."""

    config: VelocityDriveConfig

    def configure(self, config: VelocityDriveConfig) -> None:
        """Use the limits of ``config`` from now on (checked at this controller's physics rate)."""
        sim_freq = float(self._control_freq * self._sim_steps)
        config.validate(sim_freq)
        self.config = config
        self.single_action_space = self.action_space = config.action_space()
        self._high = config.box_high()
        dt = 1.0 / float(self._control_freq)
        scale = config.speed_scale
        self._scale = scale
        self._dv = config.max_linear_accel * scale * dt  # largest change of v in one control step
        self._dw = config.max_angular_accel * scale * dt
        self._twist = (0.0, 0.0)

    def parse_action(self, action) -> tuple[float, float]:
        """``(v, w)`` of ``action``, clipped to the box (``parse_velocity_action``)."""
        return parse_velocity_action(action, self._high)

    def set_action(self, action) -> None:
        """Command ``action`` (clipped, scaled), within the acceleration limits of the last command."""
        v, w = self.parse_action(action)
        v0, w0 = self._twist
        v, w, dv, dw = v * self._scale, w * self._scale, self._dv, self._dw
        self._twist = (min(max(v, v0 - dv), v0 + dv), min(max(w, w0 - dw), w0 + dw))

    def before_simulation_step(self):
        """Turn the twist into world-frame joint velocities at the current heading (as the
        discrete drive does); only the joint targets that changed are sent to PhysX (the
        heading changes the x and y targets at every sub-step of an arc, w within a step never)."""
        v, w = self._twist
        old = self._commanded or (None, None, None)
        qvel, (jx, jy, jw), (ix, iy, iw) = self._qvel, self._px_joints, self._dof_index
        if v != 0.0:
            yaw = self._px_art.get_qpos().item(self._yaw_index)
            vx, vy = v * math.cos(yaw), v * math.sin(yaw)
        else:
            vx = vy = 0.0
        if vx != old[0]:
            jx.set_drive_velocity_target(vx)
            qvel[ix] = vx
        if vy != old[1]:
            jy.set_drive_velocity_target(vy)
            qvel[iy] = vy
        if w != old[2]:
            jw.set_drive_velocity_target(w)
            qvel[iw] = w
        self._commanded = (vx, vy, w)
        self._px_art.set_qvel(qvel)

    @property
    def command(self) -> tuple[float, float]:
        """The ``(v, w)`` the robot drives this step (m/s, rad/s): after the acceleration
        limits and the speed scale; (0, 0) after a reset."""
        return self._twist


VelocityDriveConfig.controller_cls = VelocityDriveController


def require_discrete_drive(env, who: str) -> None:
    """Raise ValueError unless the task ``env`` (``env.unwrapped``) drives the discrete
    actions: ``who`` (a planner, a pilot) chooses among them."""
    mode = env.control_mode
    if mode != DISCRETE_DRIVE:
        raise ValueError(f"{who} chooses among the three discrete actions: make the task with "
                         f"control_mode={DISCRETE_DRIVE!r} (the default), not {mode!r}")


def controller_configs(discrete) -> dict:
    """The robot's controller configs by control mode, ``discrete`` (a ``DriveConfig``) first."""
    return {DISCRETE_DRIVE: discrete, VELOCITY_DRIVE: VelocityDriveConfig()}
