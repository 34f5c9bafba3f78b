"""What a dynnav task observes: its observation space and its observation, in numpy and torch.

``obs_mode`` selects the observation:

=============  ===================================================================
``state``      float32 vector: the laser readings (m; 16 unless ``laser_rays`` says
               otherwise) | robot x, y | target x, y | x, y of each moving obstacle;
               with the continuous drive also the robot's heading (sin, cos) and
               the velocity it drives (see ``state_layout()``)
``rgb``        the front camera's frame, uint8 (size, size, 3)
``rgb+state``  ``{"rgb": frame, "state": vector}``
=============  ===================================================================

The state vector is read from the step's ``StepSnapshot``; the frame is rendered when the
observation is made. A task with more moving obstacles than its state vector has places for
(``state_obstacle_slots``, e.g. world 5.3 with ``obstacle_count=4``) lists the nearest ones to the
robot, in the world's order, so a navigator trained in the original world reads the same vector. A task may observe another state vector by overriding ``task_state_vector``,
``task_state_space`` and ``task_state_layout`` (the procedural task's egocentric state, ``egocentric.py``).

The continuous drive (``control_mode="diff_drive_vel"``, ``drive.py``) adds what a real robot's
odometry reads and the three discrete actions make needless: the study's state gains
``robot_heading`` (sin and cos of the yaw; the velocity drive steers relative to the heading)
after the positions, and every state vector ends with ``robot_velocity``, the ``(v, w)`` the
robot drives (m/s, rad/s; the acceleration limits make it part of the state: the same action
moves the robot differently at rest and at full speed). The discrete drive's vectors are the study's.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import Optional

import gymnasium as gym
import numpy as np
import torch

from .camera import FRONT_CAMERA
from .drive import VelocityDriveConfig
from .noise import EpisodeNoise
from .snapshot import StepSnapshot

OBS_MODES = ("state", "rgb", "rgb+state")


class Observations:
    """Mixed into ``NavEnv``: its observation space, state layout and observations.

    Uses the task's ``world``, ``camera_spec``, ``observed_snapshot`` and laser ring (``_sensing.lasers``).
    """

    state_obstacle_slots: Optional[int] = None
    """moving obstacles the state vector lists (the nearest to the robot when the world has more);
    None: every moving obstacle of the world"""

    @property
    def _obstacle_slots(self) -> int:
        count = self.world.moving_obstacle_count
        return count if self.state_obstacle_slots is None else min(self.state_obstacle_slots, count)

    @property
    def _default_sensor_configs(self):
        """The front camera, created only when observations include images."""
        if "rgb" not in self._obs_mode:
            return []
        return [self.camera_spec.config(self.agent.robot.links_map["camera_link"])]

    @cached_property
    def single_observation_space(self) -> gym.spaces.Space:
        """state: ``state_space()``; rgb: uint8 (H, W, 3)."""
        state = self.state_space()
        n = self.camera_spec.size
        rgb = gym.spaces.Box(0, 255, (n, n, 3), dtype=np.uint8)
        return {"state": state, "rgb": rgb, "rgb+state": gym.spaces.Dict(rgb=rgb, state=state)}[self._obs_mode]

    @property
    def velocity_drive(self) -> bool:
        """Whether the robot drives by velocity (``control_mode="diff_drive_vel"``)."""
        return isinstance(self.controller_config, VelocityDriveConfig)

    def state_space(self) -> gym.spaces.Box:
        """The state vector's space: the task's (``task_state_space``), then with the continuous
        drive the velocity, within the action box times the largest speed scale."""
        space = self.task_state_space()
        if not self.velocity_drive:
            return space
        scale = self.noise_config.robot_speed_scale_max
        high = np.float32(self.controller_config.box_high()) * np.float32(scale)
        return gym.spaces.Box(np.concatenate([space.low, -high]), np.concatenate([space.high, high]), dtype=np.float32)

    def state_layout(self) -> list[tuple[str, int]]:
        """Names and sizes of the parts of the state vector, in order."""
        return self.task_state_layout() + ([("robot_velocity", 2)] if self.velocity_drive else [])

    def state_vector(self) -> np.ndarray:
        """The task's state vector (``task_state_vector``), then with the continuous drive the
        ``(v, w)`` the robot drives."""
        state = self.task_state_vector()
        if not self.velocity_drive:
            return state
        return np.concatenate([state, np.float32(self.agent.controller.command)], dtype=np.float32)

    def task_state_space(self) -> gym.spaces.Box:
        """The study's state vector's space: lasers in [0, range], positions within the walls,
        the heading's sin and cos in [-1, 1] with the continuous drive."""
        (x0, x1), (y0, y1) = self.world.arena.x_range, self.world.arena.y_range
        n_lasers, n_pos = len(self._sensing.lasers.angles), self._obstacle_slots + 2
        n_heading = 2 if self.velocity_drive else 0
        low = np.array([0.0] * n_lasers + [x0, y0] * n_pos + [-1.0] * n_heading, dtype=np.float32)
        high = np.array([self._sensing.lasers.max_range] * n_lasers + [x1, y1] * n_pos + [1.0] * n_heading,
                        dtype=np.float32)
        return gym.spaces.Box(low, high, dtype=np.float32)

    def task_state_layout(self) -> list[tuple[str, int]]:
        """Names and sizes of the parts of the study's state vector, in order."""
        layout = [("lasers", len(self._sensing.lasers.angles)), ("robot_xy", 2), ("target_xy", 2)]
        layout += [(f"obstacle{i}_xy", 2) for i in range(self._obstacle_slots)]
        return layout + ([("robot_heading", 2)] if self.velocity_drive else [])

    @property
    def numpy_observation(self):
        """The observation of the latest reset or step, unbatched numpy (as ``step_numpy`` gives)."""
        return self._obs_numpy

    def get_obs(self, info: Optional[dict] = None, unflattened: bool = False):
        """Batched torch observation of the current step (see the module docstring)."""
        obs = self._obs_numpy = self.observation_numpy()
        if isinstance(obs, dict):
            return {k: torch.from_numpy(v[None]) for k, v in obs.items()}
        return torch.from_numpy(obs[None])

    def observation_numpy(self):
        """The current observation, unbatched numpy: the state vector, the camera image, or both."""
        if self._obs_mode == "state":
            return self.state_vector()
        if self._obs_mode == "rgb":
            return self.camera_image()
        return {"rgb": self.camera_image(), "state": self.state_vector()}

    @property
    def observed_snapshot(self) -> StepSnapshot:
        """The snapshot as the agent perceives it (the state vector's source): ``snapshot``
        itself unless the task has sensor or odometry noise (``noise.py``)."""
        self.snapshot  # noqa: B018  (raises before the first reset)
        return self._observed

    @property
    def episode_noise(self) -> Optional[EpisodeNoise]:
        """The noise at work (this episode's speed factors, drift, executed action); None
        when every noise option is off (``noise.py``)."""
        return self._noise

    def task_state_vector(self) -> np.ndarray:
        """lasers | robot xy | target xy | moving obstacles xy (| heading sin, cos with the
        continuous drive), float32, as the agent perceives them (``observed_snapshot``: with the
        task's sensor and odometry noise, if any)."""
        snapshot = self.observed_snapshot
        slots = self._obstacle_slots
        heading = [np.float32([math.sin(snapshot.pose[2]), math.cos(snapshot.pose[2])])] if self.velocity_drive else []
        if slots == snapshot.moving_count and not heading:
            return snapshot.state_vector()
        moving = snapshot.moving_obstacle_xy
        nearest = np.sort(np.argsort(np.linalg.norm(moving - snapshot.pose[:2], axis=1), kind="stable")[:slots])
        return np.concatenate([snapshot.lasers, snapshot.pose[:2], snapshot.target_xy, moving[nearest].reshape(-1),
                               *heading], dtype=np.float32)

    def camera_image(self) -> np.ndarray:
        """What the front camera sees now: uint8 (size, size, 3)."""
        self.scene.update_render(update_sensors=True, update_human_render_cameras=False)
        sensor = self._sensors[FRONT_CAMERA]
        sensor.capture()
        rgb = sensor.get_obs(rgb=True, depth=False, position=False, segmentation=False)["rgb"][0].numpy()
        self._camera_frame = self.camera_spec.shrink(rgb)
        return self._camera_frame

    @property
    def last_camera_frame(self) -> Optional[np.ndarray]:
        """The frame of the latest observation (None when the task renders no images)."""
        return getattr(self, "_camera_frame", None)

    @property
    def laser_angles(self) -> np.ndarray:
        """Direction of each laser ray relative to the robot's heading (rad)."""
        return self._sensing.lasers.angles.copy()

    @property
    def laser_range(self) -> float:
        """Reading of a ray that meets nothing (m)."""
        return self._sensing.lasers.max_range
