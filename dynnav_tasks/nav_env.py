"""``NavEnv``: the navigation base task every dynnav world derives from.

A task subclass declares a ``World`` (arena, obstacles, targets, start area) and a docstring;
this class builds the SAPIEN scene from it, drives the robot, casts the lasers, detects
collisions from PhysX contacts, computes the reward and ends episodes.

Episode rules
    * success: the robot's centre comes within ``reach_radius`` (0.3 m) of the chosen
      target's centre; the episode terminates.
    * collision: a PhysX contact between the robot (chassis or wheels) and a wall or an
      obstacle that either pushed them apart (non-zero impulse) or has a separation of at
      most ``collision_margin`` (5 mm); the episode terminates.
    * timeout: ``max_episode_steps`` (200) steps without either; the episode is truncated,
      not terminated.

State observation (``obs_mode="state"``), float32, in this order (see ``state_layout()``):
    16 laser readings (m) | robot x, y | target x, y | x, y of each moving obstacle

Step
    One control step is 0.2 s (``control_freq`` 5 Hz) simulated as 4 PhysX steps of 50 ms.
    Moving obstacles are kinematic bodies moved to interpolated targets at every PhysX step.
    ``step()`` is a lean version of ``BaseEnv.step``: it drives the PhysX objects with numpy
    directly and hands ManiSkill batched torch tensors only at the end, which makes it several
    times faster than the default path while returning the same types.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import Any, ClassVar, Optional

import gymnasium as gym
import numpy as np
import sapien
import torch
from mani_skill.envs.sapien_env import BaseEnv
from mani_skill.sensors.camera import CameraConfig
from mani_skill.utils import sapien_utils
from mani_skill.utils.structs.types import SceneConfig, SimConfig

from . import rewards as R
from .camera import FRONT_CAMERA, CameraSpec
from .errors import check_choice
from .lasers import LaserRing
from .motion import wrap_angle
from .vulkan import explain, is_vulkan_error
from .robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT, DiffBot, DriveConfig
from .scene import HIDDEN_Z, add_lighting, build_world
from .world import World

OBS_MODES = ("state", "rgb", "rgb+state")


def box_distance(point: np.ndarray, centers: np.ndarray, half_sizes: np.ndarray) -> np.ndarray:
    """Distances from a 2D point to axis-aligned rectangles (0 inside)."""
    d = np.maximum(np.abs(point[None, :] - centers) - half_sizes, 0.0)
    return np.sqrt((d * d).sum(axis=1))


class NavEnv(BaseEnv):
    """Base class of the dynnav navigation tasks (not registered itself)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 5}
    SUPPORTED_ROBOTS = [DiffBot.uid]
    SUPPORTED_OBS_MODES = OBS_MODES
    SUPPORTED_REWARD_MODES = R.REWARD_MODES

    world: ClassVar[World]
    """the task's world; set by each task class"""
    max_episode_steps: ClassVar[int] = 200
    reach_radius: ClassVar[float] = 0.3
    collision_margin: ClassVar[float] = 0.005
    camera_world: ClassVar[bool] = False
    """a world of the thesis's camera experiments (5.5a-c); any task can use the camera"""
    default_reward_params: ClassVar[dict] = {}
    """per-task overrides of ``RewardParams`` defaults"""

    def __init__(
        self,
        *args,
        obs_mode: Optional[str] = None,
        reward_mode: Optional[str] = None,
        robot_uids: str = DiffBot.uid,
        reward_params: Optional[dict] = None,
        forward_step: float = DriveConfig.forward_step,
        turn_step: float = DriveConfig.turn_step,
        turn_forward_step: float = DriveConfig.turn_forward_step,
        camera_size: int = CameraSpec.size,
        camera_render_size: Optional[int] = None,
        num_envs: int = 1,
        sim_backend: str = "physx_cpu",
        render_backend: str = "cpu",
        **kwargs,
    ):
        obs_mode = check_choice(obs_mode or OBS_MODES[0], self.SUPPORTED_OBS_MODES, "obs_mode")
        reward_mode = check_choice(reward_mode or R.DEFAULT_REWARD_MODE, self.SUPPORTED_REWARD_MODES, "reward_mode")
        if num_envs != 1 or sim_backend not in ("physx_cpu", "cpu"):
            raise ValueError(
                "dynnav tasks run one environment per process on the CPU simulation "
                f"(got num_envs={num_envs}, sim_backend={sim_backend!r}); "
                "use gymnasium's vector environments for several."
            )
        self.reward_params = R.RewardParams.from_dict({**self.default_reward_params, **(reward_params or {})})
        self.drive_config = DriveConfig(
            forward_step=forward_step, turn_step=turn_step, turn_forward_step=turn_forward_step
        )
        self.drive_config.validate()
        self.camera_spec = CameraSpec(size=camera_size, render_size=camera_render_size)
        super().__init__(
            *args,
            obs_mode=obs_mode,
            reward_mode=reward_mode,
            robot_uids=robot_uids,
            num_envs=1,
            sim_backend="physx_cpu",
            render_backend=render_backend,
            **kwargs,
        )

    # ------------------------------------------------------------------ configuration
    @property
    def _default_sim_config(self):
        return SimConfig(
            sim_freq=20,
            control_freq=5,
            scene_config=SceneConfig(gravity=np.zeros(3), solver_position_iterations=4),
        )

    @property
    def _default_sensor_configs(self):
        """The front camera, created only when observations include images."""
        if "rgb" not in self._obs_mode:
            return []
        return [self.camera_spec.config(self.agent.robot.links_map["camera_link"])]

    TOP_DOWN_SIZE: ClassVar[int] = 512
    TOP_DOWN_HEIGHT: ClassVar[float] = 12.0

    def _top_down_half_extent(self) -> float:
        """Half the width of floor (m) the top-down picture covers."""
        arena = self.world.arena
        return float(max(arena.size)) / 2 + arena.wall_thickness + 0.3

    @property
    def _default_human_render_camera_configs(self):
        """A top-down camera over the whole arena (image right = +x, image up = +y)."""
        cx, cy = self.world.arena.center
        h = self.TOP_DOWN_HEIGHT
        pose = sapien_utils.look_at(eye=[cx, cy, h], target=[cx, cy, 0.0], up=[0, 1, 0])
        fov = 2 * math.atan(self._top_down_half_extent() / h)
        n = self.TOP_DOWN_SIZE
        return CameraConfig("top_down", pose=pose, width=n, height=n, fov=fov, near=0.1, far=2 * h)

    def top_down_pixel(self, x: float, y: float) -> tuple[float, float]:
        """(column, row) of the floor point (x, y) in the top-down picture."""
        cx, cy = self.world.arena.center
        half, n = self._top_down_half_extent(), self.TOP_DOWN_SIZE
        return n / 2 + (x - cx) / half * n / 2, n / 2 - (y - cy) / half * n / 2

    @cached_property
    def single_observation_space(self) -> gym.spaces.Space:
        """state: lasers in [0, range], positions within the walls; rgb: uint8 (H, W, 3)."""
        (x0, x1), (y0, y1) = self.world.arena.x_range, self.world.arena.y_range
        n_lasers, n_pos = len(self._lasers.angles), self.world.moving_obstacle_count + 2
        low = np.array([0.0] * n_lasers + [x0, y0] * n_pos, dtype=np.float32)
        high = np.array([self._lasers.max_range] * n_lasers + [x1, y1] * n_pos, dtype=np.float32)
        state = gym.spaces.Box(low, high, dtype=np.float32)
        n = self.camera_spec.size
        rgb = gym.spaces.Box(0, 255, (n, n, 3), dtype=np.uint8)
        return {"state": state, "rgb": rgb, "rgb+state": gym.spaces.Dict(rgb=rgb, state=state)}[self._obs_mode]

    def state_layout(self) -> list[tuple[str, int]]:
        """Names and sizes of the parts of the state vector, in order."""
        layout = [("lasers", len(self._lasers.angles)), ("robot_xy", 2), ("target_xy", 2)]
        layout += [(f"obstacle{i}_xy", 2) for i in range(self.world.moving_obstacle_count)]
        return layout

    # ------------------------------------------------------------------ scene
    def _setup_scene(self):
        try:
            super()._setup_scene()
        except RuntimeError as err:
            if is_vulkan_error(err):
                raise explain(err) from err
            raise

    def _load_agent(self, options: dict):
        super()._load_agent(options, sapien.Pose())
        self.agent.controller.configure(self.drive_config)

    def _load_lighting(self, options: dict):
        add_lighting(self.scene)  # even: every surface shows its palette colour

    def _load_scene(self, options: dict):
        built = build_world(self.scene, self.world)
        self._movers = built.movers
        self._moving_bodies, self._moving_z = built.moving_bodies, built.moving_z
        self._static_obstacle_xy, self._obstacle_half = built.static_obstacle_xy, built.obstacle_half
        self._targets = built.targets
        self._px = self.scene.px
        self._lasers = LaserRing(self._px, FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, LASER_HEIGHT)
        self._robot_bodies = {
            link._objs[0] for link in self.agent.robot.links if link._objs[0].collision_shapes
        }

    # ------------------------------------------------------------------ episodes
    def _initialize_episode(self, env_idx: torch.Tensor, options: dict):
        rng = self.np_random
        world = self.world
        self._target_index = int(rng.integers(len(world.targets)))
        self._target_xy = None
        for t, (mover, entity) in enumerate(self._targets):
            xy = mover.reset(rng)[0]
            if t == self._target_index:
                self._target_xy = xy
                entity.set_pose(sapien.Pose([xy[0], xy[1], 0.0]))
            else:
                entity.set_pose(sapien.Pose([xy[0], xy[1], HIDDEN_Z]))  # out of sight under the floor
        moving = []
        for mover, bodies in self._movers:
            xy = mover.reset(rng)
            for body, p in zip(bodies, xy):
                pose = sapien.Pose([p[0], p[1], body.entity.pose.p[2]])
                body.entity.set_pose(pose)
                body.set_kinematic_target(pose)
            moving.append(xy)
        self._moving_xy = np.concatenate(moving) if moving else np.zeros((0, 2))
        self.agent.set_pose2d(*world.start.sample(rng))
        self.agent.controller.reset()

        self._terminal = False
        self._path_length = 0.0
        self._reward = 0.0
        self._sense()

    # ------------------------------------------------------------------ step
    def step(self, action: Any):
        if self._terminal:
            raise RuntimeError("the episode has ended (success or collision): call reset() before step()")
        controller = self.agent.controller
        controller.set_action(action)
        # advance every mover one control step; interpolate kinematic targets per PhysX step
        old_xy, new_xy = self._moving_xy, self._advance_movers()
        n_sub = self._sim_steps_per_control
        bodies = self._moving_bodies
        for k in range(1, n_sub + 1):
            controller.before_simulation_step()
            if bodies:
                frac = k / n_sub
                xy = old_xy + (new_xy - old_xy) * frac
                for body, z, p in zip(bodies, self._moving_z, xy):
                    body.set_kinematic_target(sapien.Pose([p[0], p[1], z]))
            self._px.step()
        self._moving_xy = new_xy
        self._advance_targets()
        self._elapsed_steps += 1
        self._step_count += 1

        prev = self._sensed
        self._sense()
        info = self.get_info()  # evaluate() decides success and collision
        reached, collided = self._success, self._collided
        self._reward = R.compute_reward(
            self._reward_mode,
            R.RewardInputs(
                d1=self._d1, d1_prev=prev[0], d2=self._d2, d2_prev=prev[1],
                bearing=self._bearing, bearing_prev=prev[2], reached=reached, collided=collided,
            ),
            self.reward_params,
        )
        self._terminal = reached or collided
        obs = self.get_obs(info)
        self._last_obs = obs
        return (
            obs,
            torch.tensor([self._reward], dtype=torch.float32),
            torch.tensor([self._terminal]),
            torch.tensor([self._step_count >= self.max_episode_steps and not self._terminal]),
            info,
        )

    def _advance_movers(self) -> np.ndarray:
        rng = self.np_random
        if not self._movers:
            return self._moving_xy
        return np.concatenate([mover.advance(rng) for mover, _ in self._movers])

    def _advance_targets(self):
        mover, entity = self._targets[self._target_index]
        xy = mover.advance(self.np_random)[0]
        if xy[0] != self._target_xy[0] or xy[1] != self._target_xy[1]:
            entity.set_pose(sapien.Pose([xy[0], xy[1], 0.0]))
        self._target_xy = xy

    # ------------------------------------------------------------------ sensing
    def _sense(self):
        """Read the robot's pose, lasers, contacts and distances after a step or a reset."""
        x, y, yaw = self.agent.pose2d()
        if self._robot_xy is not None:
            self._path_length += math.hypot(x - self._robot_xy[0], y - self._robot_xy[1])
        self._robot_xy = np.array([x, y])
        self._robot_yaw = yaw
        self._laser = self._lasers.read(x, y, yaw)
        tx, ty = self._target_xy
        self._d1 = math.hypot(tx - x, ty - y)
        obstacle_xy = np.concatenate([self._static_obstacle_xy, self._moving_xy])
        self._d2 = float(box_distance(self._robot_xy, obstacle_xy, self._obstacle_half).min()) if len(obstacle_xy) else math.inf
        self._bearing = float(wrap_angle(math.atan2(ty - y, tx - x) - yaw))
        self._contact = self._in_collision()
        self._sensed = (self._d1, self._d2, self._bearing)

    def _in_collision(self) -> bool:
        robot = self._robot_bodies
        for contact in self._px.get_contacts():
            a, b = contact.bodies
            if (a in robot) != (b in robot):  # robot against anything else
                for p in contact.points:
                    # touching, or the solver had to push them apart during the step
                    if p.separation <= self.collision_margin or np.any(p.impulse):
                        return True
        return False

    # ------------------------------------------------------------------ ManiSkill API
    def reset(self, seed=None, options=None):
        """Reset; a seed makes the episode (start, target, motions) replay bit for bit.

        All of the task's randomness comes from gymnasium's ``self.np_random``, seeded here
        as ``gymnasium.Env.reset`` does (an unseeded reset continues the generator).
        """
        if isinstance(seed, (list, tuple, np.ndarray)):  # ManiSkill's batched form
            seed = int(seed[0])
        gym.Env.reset(self, seed=seed)
        self._step_count = 0
        self._robot_xy = None
        return super().reset(seed=seed, options=options)

    def evaluate(self) -> dict:
        """The single source of success and failure (decided here, read by ``step``)."""
        self._collided = self._contact
        self._success = self._d1 <= self.reach_radius and not self._collided
        timeout = self._step_count >= self.max_episode_steps and not (self._success or self._collided)
        return dict(
            success=torch.tensor([self._success]),
            fail=torch.tensor([self._collided]),
            collision=torch.tensor([self._collided]),
            timeout=torch.tensor([timeout]),
            distance_to_target=torch.tensor([self._d1], dtype=torch.float32),
            path_length=torch.tensor([self._path_length], dtype=torch.float32),
        )

    def get_obs(self, info: Optional[dict] = None, unflattened: bool = False):
        """Batched torch observation of the current step (see the module docstring)."""
        if self._obs_mode == "rgb":
            return torch.from_numpy(self.camera_image()[None])
        state = torch.from_numpy(self.state_vector()[None])
        if self._obs_mode == "state":
            return state
        return {"rgb": torch.from_numpy(self.camera_image()[None]), "state": state}

    def state_vector(self) -> np.ndarray:
        """lasers | robot xy | target xy | moving obstacles xy, float32."""
        return np.concatenate([self._laser, self._robot_xy, self._target_xy, self._moving_xy.reshape(-1)]).astype(np.float32)

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
    def target_index(self) -> int:
        """Which of the world's targets this episode's robot must reach (0-based)."""
        return self._target_index

    def get_reward(self, obs, action, info):
        return torch.tensor([self._reward], dtype=torch.float32)

    # ------------------------------------------------------------------ convenience
    def place_robot(self, x: float, y: float, yaw: float):
        """Teleport the robot (for tests and tools) and re-sense; returns the state vector."""
        self.agent.set_pose2d(x, y, yaw)
        self._robot_xy = None
        self._sense()
        return self.state_vector()

    def render_top_down(self, show_all_targets: bool = False) -> np.ndarray:
        """An RGB picture (H, W, 3) uint8 of the whole arena seen from above.

        With ``show_all_targets`` every candidate target's disc is drawn at its current
        position, not only the chosen one's.
        """
        hidden = []
        if show_all_targets:
            for t, (mover, entity) in enumerate(self._targets):
                if t != self._target_index:
                    p = entity.pose.p
                    hidden.append((entity, sapien.Pose(p)))
                    entity.set_pose(sapien.Pose([p[0], p[1], 0.0]))
        try:
            return self.render_rgb_array("top_down")[0].cpu().numpy()
        finally:
            for entity, pose in hidden:
                entity.set_pose(pose)
