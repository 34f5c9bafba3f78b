"""``NavEnv``: the navigation base task every dynnav world derives from.

A task subclass declares a ``World`` (arena, obstacles, targets, start area) and a docstring;
this class builds the SAPIEN scene from it, drives the robot, casts the lasers, detects
collisions from PhysX contacts, computes the reward and ends episodes.

Episode rules
    * success: the robot's centre comes within ``reach_radius`` (0.3 m) of the chosen
      target's centre; the episode terminates.
    * collision: a PhysX contact between the robot (chassis or wheels) and a wall or an
      obstacle that either pushed them apart (non-zero impulse) or has a separation of at
      most ``collision_margin`` (5 mm), at any PhysX sub-step; or the robot's footprint
      overlapping a wall or an obstacle at the end of the step (PhysX finds contacts at the
      start of a sub-step, so an overlap made during the last one would otherwise be seen a
      step late); the episode terminates.
    * timeout: ``max_episode_steps`` (200) steps without either; the episode is truncated,
      not terminated.

Pedestrians (``World.pedestrians``, ``crowd/``)
    Upright kinematic cylinders placed at every reset (after the robot: clear of its start and
    the target) and moved every control step by their crowd's model, which sees the robot or
    not (``Pedestrians.see_robot``); their kinematic targets are interpolated over the sub-steps
    as the boxes' are. A collision with one is a collision, and ``info["human_collision"]`` says
    so (False in every other world). The info of an episode's last step also holds its social
    metrics (``crowd/metrics.py``: minimum distance, personal-space compliance, discomfort
    frequency, time to goal, path length, SPL, path irregularity, jerk).

Reward
    ``reward_mode`` picks one of ``rewards.SUPPORTED_REWARD_MODES``: the study's (default
    ``distance_orientation_always``, Eq. 4.6) and ManiSkill's ``dense`` (the same),
    ``normalized_dense`` (it divided by ``reward_bound``, within [-1, 1]) and ``none``.

State observation (``obs_mode="state"``), float32, in this order (see ``state_layout()``
and ``observations.py`` for the camera's):
    16 laser readings (m) | robot x, y | target x, y | x, y of each moving obstacle
(the procedural task observes the egocentric state instead, ``egocentric.py``).

Sensors and noise (``docs/sensors.md``)
    ``laser_rays`` (16), ``laser_fov_deg`` (360) and ``laser_range`` (5 m) set the laser
    ring (``lasers.LaserConfig``); the state vector has one reading per ray. Sensor, odometry
    and action noise and per-episode speed randomization (``noise.NoiseConfig``, all off by
    default) are flat options such as ``laser_noise_std=0.02`` or one ``noise=`` dict.

Control modes (``drive.py``)
    ``control_mode="discrete_drive"`` (the default): the study's three actions;
    ``"diff_drive_vel"``: ``Box(2)``, linear and angular velocity with a Pioneer 3-DX's limits.

Step
    One control step is 0.2 s (``control_freq`` 5 Hz) simulated as 4 PhysX steps of 50 ms.
    Moving obstacles are kinematic bodies moved to interpolated targets at every PhysX step.
    After it the task takes one ``StepSnapshot`` (``snapshot.py``) from what its ``Sensing``
    (``sensing.py``) reads; ``evaluate()``, the reward and the observation are read from it.
    ``step_numpy`` returns the plain gymnasium values (numpy, no torch at all); ``step``
    (ManiSkill's batched torch API) wraps them.
"""

from __future__ import annotations

import copy
from typing import Any, ClassVar, Optional

import gymnasium as gym
import numpy as np
import sapien
import torch
from mani_skill.envs.sapien_env import BaseEnv
from mani_skill.utils.structs.types import SceneConfig, SimConfig

from . import rewards as R
from .camera import CameraSpec
from .crowd.crowd import Crowd
from .crowd.metrics import SocialMetrics
from .drive import CONTROL_MODES, DISCRETE_DRIVE, VelocityDriveConfig
from .errors import check_choice
from .lasers import LASER_RANGE, NUM_LASERS, LaserConfig
from .motion import EpisodeMotion
from .noise import EpisodeNoise, NoiseConfig
from .observations import OBS_MODES, Observations
from .diffbot import DiffBot
from .robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH, DriveConfig
from .scene import HIDDEN_Z, BuiltWorld, add_lighting, build_world
from .sensing import Sensing
from .snapshot import StepSnapshot
from .viz.top_down import TopDownView
from .vulkan import explain, is_vulkan_error, keep_render_pipelines
from .world import World

ROBOT_RADIUS = float(np.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH))
"""m: the circle around the robot's footprint, as pedestrians that see it avoid it"""


class NavEnv(Observations, TopDownView, BaseEnv):
    """Base class of the dynnav navigation tasks (not registered itself)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 5}
    SUPPORTED_ROBOTS = [DiffBot.uid]
    SUPPORTED_OBS_MODES = OBS_MODES
    SUPPORTED_REWARD_MODES = R.SUPPORTED_REWARD_MODES

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
        control_mode: Optional[str] = None,
        reward_params: Optional[dict] = None,
        forward_step: float = DriveConfig.forward_step,
        turn_step: float = DriveConfig.turn_step,
        turn_forward_step: float = DriveConfig.turn_forward_step,
        camera_size: int = CameraSpec.size,
        camera_render_size: Optional[int] = None,
        laser_rays: int = NUM_LASERS,
        laser_fov_deg: float = 360.0,
        laser_range: float = LASER_RANGE,
        noise: Optional[NoiseConfig | dict] = None,
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
        self.reward_bound = self.reward_bound_of(self.world)
        """the largest |reward| of reward_mode "dense"; "normalized_dense" divides by it (``rewards.py``)"""
        self.drive_config = DriveConfig(
            forward_step=forward_step, turn_step=turn_step, turn_forward_step=turn_forward_step
        )
        self.drive_config.validate()
        control_mode = check_choice(control_mode or CONTROL_MODES[0], CONTROL_MODES, "control_mode")
        self.velocity_drive_config = VelocityDriveConfig.from_task_options(control_mode, kwargs)
        """the limits of control_mode "diff_drive_vel" (``drive.py``; its flat options come out of kwargs)"""
        self.controller_config = self.drive_config if control_mode == DISCRETE_DRIVE else self.velocity_drive_config
        """the config of the robot's controller in this task's control mode (before any noise)"""
        self.camera_spec = CameraSpec(size=camera_size, render_size=camera_render_size)
        self.laser_config = LaserConfig.of(laser_rays, laser_fov_deg, laser_range)
        """the laser ring's rays, field of view and range (``lasers.py``)"""
        self.noise_config = NoiseConfig.from_task_options(noise, kwargs)  # takes its flat options out of kwargs
        """the noise and randomization options (``noise.py``; all off by default)"""
        enabled = self.noise_config.enabled
        self._noise = EpisodeNoise(self.noise_config, self.controller_config, self.laser_config.max_range) if enabled else None
        self._snapshot: Optional[StepSnapshot] = None
        self._outcome_of: Optional[StepSnapshot] = None  # outcome() of this snapshot is cached
        super().__init__(
            *args,
            obs_mode=obs_mode,
            reward_mode=reward_mode,
            robot_uids=robot_uids,
            control_mode=control_mode,
            num_envs=1,
            sim_backend="physx_cpu",
            render_backend=render_backend,
            **kwargs,
        )

    def reward_bound_of(self, world: World) -> float:
        """The largest |reward| of reward_mode "dense" in ``world`` with this task's reward
        parameters (``rewards.dense_bound``)."""
        return R.dense_bound(self.reward_params, world.span(), min(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH))

    # ------------------------------------------------------------------ configuration
    @property
    def _default_sim_config(self):
        return SimConfig(
            sim_freq=20,
            control_freq=5,
            scene_config=SceneConfig(gravity=np.zeros(3), solver_position_iterations=4),
        )

    # ------------------------------------------------------------------ scene
    def _setup_scene(self):
        try:
            super()._setup_scene()
            keep_render_pipelines(self._render_device)
        except RuntimeError as err:
            if is_vulkan_error(err):
                raise explain(err) from err
            raise

    def _load_agent(self, options: dict):
        super()._load_agent(options, sapien.Pose())
        self.agent.controller.configure(self.controller_config)

    def _load_lighting(self, options: dict):
        add_lighting(self.scene)  # even: every surface shows its palette colour

    def _load_scene(self, options: dict):
        self._px = self.scene.px
        self._sensing = Sensing(self._px, self.agent.robot, collision_margin=self.collision_margin, lasers=self.laser_config)
        self._use_world(self._build_world())

    def _build_world(self) -> BuiltWorld:
        """Add the bodies of ``self.world`` to the scene, once (``scene.build_world``)."""
        return build_world(self.scene, self.world)

    def _use_world(self, built: BuiltWorld):
        """Move, sense and draw the bodies of ``built``, the scene's bodies of ``self.world``,
        from the next reset on (a task whose world changes between episodes calls it again)."""
        self._movers = built.movers
        self._moving_bodies, self._moving_z = built.moving_bodies, built.moving_z
        n_sub, n_moving = self._sim_steps_per_control, len(self._moving_bodies)
        self._sub_step_fractions = (np.arange(1, n_sub + 1) / n_sub).reshape(-1, 1, 1)  # k / n_sub
        kinematic = np.empty((n_sub, n_moving, 3), dtype=np.float32)
        kinematic[:, :, 2] = self._moving_z
        self._kinematic_xy = kinematic[:, :, :2]
        self._kinematic_rows = [list(rows) for rows in kinematic]
        self._kinematic_pose = sapien.Pose()
        self._targets = built.targets
        self._sensing.set_obstacles(self.world.arena.walls().values(), built.static_obstacle_xy, built.obstacle_half)
        self._use_pedestrians(built)

    def _use_pedestrians(self, built: BuiltWorld):
        """The crowd of ``self.world.pedestrians`` (``crowd.crowd.Crowd``) and the bodies it moves."""
        spec, bodies = self.world.pedestrians, built.pedestrian_bodies
        self._crowd = Crowd(spec) if spec is not None and spec.count else None
        self._social = SocialMetrics(ROBOT_RADIUS, 1.0 / self._control_freq) if self._crowd is not None else None
        self._human_bodies = bodies
        self._sensing.set_pedestrians(bodies, [spec.radius] * len(bodies) if spec is not None else [])
        if self._crowd is None:
            return
        kinematic = np.empty((self._sim_steps_per_control, len(bodies), 3), dtype=np.float32)
        kinematic[:, :, 2] = spec.height / 2
        self._human_kinematic_xy = kinematic[:, :, :2]
        self._human_rows = [list(rows) for rows in kinematic]
        walls = [(c[0] - h[0], c[1] - h[1], c[0] + h[0], c[1] + h[1]) for c, h in self.world.arena.walls().values()]
        static = [(c[0] - h[0], c[1] - h[1], c[0] + h[0], c[1] + h[1])
                  for c, h in zip(built.static_obstacle_xy, built.obstacle_half)]
        self._crowd_boxes = np.array(walls + static, dtype=np.float64).reshape(-1, 4)
        self._moving_half = np.asarray(built.obstacle_half, dtype=np.float64)[len(built.static_obstacle_xy):]

    # ------------------------------------------------------------------ episodes
    def _initialize_episode(self, env_idx: torch.Tensor, options: dict):
        rng = self.np_random
        world = self.world
        self._target_index = int(rng.integers(len(world.targets)))
        self._target_xy = None
        for t, (mover, entity) in enumerate(self._targets):
            xy = mover.reset(rng)[0]
            if t == self._target_index:
                self._target_xy = tuple(xy.tolist())
                entity.set_pose(sapien.Pose([xy[0], xy[1], 0.0]))
            else:
                entity.set_pose(sapien.Pose([xy[0], xy[1], HIDDEN_Z]))  # out of sight under the floor
        moving = []
        moving_z = iter(self._moving_z)
        for mover, bodies in self._movers:
            xy = mover.reset(rng)
            for body, p in zip(bodies, xy):
                pose = sapien.Pose([p[0], p[1], next(moving_z)])
                body.entity.set_pose(pose)
                body.set_kinematic_target(pose)
            moving.append(xy)
        self._moving_xy = np.concatenate(moving) if moving else np.zeros((0, 2))
        if self._noise is not None:  # this episode's speed factors, from the noise's own generators
            self._noise.start_episode(self.agent.controller, [mover for mover, _ in self._movers])
        start = world.start.sample(rng)
        self.agent.set_pose2d(*start)
        if self._crowd is not None:  # the crowd last: the box worlds' draws stay what they were
            self._crowd.reset(rng, keep_clear=[start[:2], self._target_xy, *self._moving_xy], boxes=self._crowd_boxes)
            pose = self._kinematic_pose
            for body, (x, y) in zip(self._human_bodies, self._crowd.positions.tolist()):
                pose.p = [x, y, self.world.pedestrians.height / 2]
                body.entity.set_pose(pose)
                body.set_kinematic_target(pose)
        self._robot_velocity = (0.0, 0.0)
        if self._crowd is not None:  # the episode's social metrics (``crowd.metrics``), from the start
            self._social.start(*start, self._target_xy)
            self._shortest = max(float(np.hypot(*np.subtract(self._target_xy, start[:2]))) - self.reach_radius, 0.0)
        self.agent.controller.reset()
        # nothing has been simulated since the placement: PhysX's contacts are the last episode's
        self._snapshot = self._take_snapshot(step=0, contact=False, previous=None)
        self._reward = 0.0

    # ------------------------------------------------------------------ step
    def step(self, action: Any):
        """ManiSkill's step: batched torch tensors (see ``step_numpy`` for the same in numpy)."""
        obs, reward, terminated, truncated, _ = self.step_numpy(action, numpy_obs=False)
        return (
            obs,
            torch.tensor([reward], dtype=torch.float32),
            torch.tensor([terminated]),
            torch.tensor([truncated]),
            self.get_info(),
        )

    def step_numpy(self, action: Any, numpy_obs: bool = True):
        """One step in the plain gymnasium form: (observation as numpy, reward as float,
        terminated, truncated, info of Python scalars). ``NumpyWrapper`` calls this."""
        if self._snapshot is None:
            raise RuntimeError("call reset() before step()")
        if self._terminal():
            raise RuntimeError("the episode has ended (success or collision): call reset() before step()")
        if self._noise is not None:
            action = self._noise.execute(self.agent.controller.parse_action(action))
        self.agent.controller.set_action(action)
        prev = self._snapshot
        self._simulate()
        self._snapshot = self._take_snapshot(step=prev.step + 1, contact=None, previous=prev)
        rate = float(self._control_freq)
        self._robot_velocity = ((self._snapshot.pose[0] - prev.pose[0]) * rate, (self._snapshot.pose[1] - prev.pose[1]) * rate)
        result = self.outcome()  # evaluate()'s decision, as Python values
        self._reward = R.compute_reward(
            self._reward_mode, prev, self._snapshot, self.reward_params,
            reached=result["success"], collided=result["collision"], bound=self.reward_bound,
        )
        if self._social is not None:
            s = self._snapshot
            self._social.step(*s.pose, s.human_xy, s.human_radius)
            if result["success"] or result["collision"] or result["timeout"]:  # the episode's end: its metrics
                result.update(self._social.result(result["success"], self._shortest))
        if numpy_obs:
            obs = self._obs_numpy = self.observation_numpy()
        else:
            obs = self._last_obs = self.get_obs()  # also keeps the numpy one in self._obs_numpy
        return obs, self._reward, result["success"] or result["collision"], result["timeout"], result

    def _simulate(self):
        """One control step: the robot's drive and every mover, over the PhysX sub-steps."""
        before_sub_step, px_step = self.agent.controller.before_simulation_step, self._px.step
        old_xy, new_xy = self._moving_xy, self._advance_movers()
        bodies, pose = self._moving_bodies, self._kinematic_pose  # PhysX copies a target's pose
        if bodies:  # kinematic targets, interpolated, in float32 (a Pose's precision)
            np.add(old_xy, (new_xy - old_xy) * self._sub_step_fractions, out=self._kinematic_xy, casting="same_kind")
        humans, human_rows = self._advance_crowd()
        for k, rows in enumerate(self._kinematic_rows):  # one list of (x, y, z) rows per sub-step
            before_sub_step()
            for body, p in zip(bodies, rows):
                pose.p = p
                body.set_kinematic_target(pose)
            if humans:
                for body, p in zip(humans, human_rows[k]):
                    pose.p = p
                    body.set_kinematic_target(pose)
            px_step()
        self._moving_xy = new_xy
        self._advance_targets()

    def _advance_crowd(self):
        """Move the crowd one control step; (its bodies, their (x, y, z) rows per sub-step) or
        ((), None) without one."""
        crowd = self._crowd
        if crowd is None:
            return (), None
        old = crowd.positions.copy()
        s = self._snapshot
        robot = ((s.pose[0], s.pose[1]), self._robot_velocity, ROBOT_RADIUS) if crowd.spec.see_robot else None
        new = crowd.step(1.0 / self._control_freq, self.np_random, robot=robot, boxes=self._crowd_obstacles())
        np.add(old, (new - old) * self._sub_step_fractions, out=self._human_kinematic_xy, casting="same_kind")
        return self._human_bodies, self._human_rows

    def _crowd_obstacles(self) -> np.ndarray:
        """(k, 4) boxes the crowd walks round: the walls, the static boxes and the moving boxes
        where they are now (as resting ones)."""
        if not len(self._moving_xy):
            return self._crowd_boxes
        return np.vstack([self._crowd_boxes,
                          np.hstack([self._moving_xy - self._moving_half, self._moving_xy + self._moving_half])])

    def _advance_movers(self) -> np.ndarray:
        movers = self._movers
        if not movers:
            return self._moving_xy
        rng = self.np_random
        return np.array([p for mover, _ in movers for p in mover.advance_points(rng)])

    def _advance_targets(self):
        mover, entity = self._targets[self._target_index]
        xy = mover.advance_points(self.np_random)[0]
        if xy != self._target_xy:
            pose = self._kinematic_pose  # the entity copies it
            pose.p = [xy[0], xy[1], 0.0]
            entity.set_pose(pose)
        self._target_xy = xy

    # ------------------------------------------------------------------ sensing
    def _take_snapshot(
        self, step: int, contact: Optional[bool], previous: Optional[StepSnapshot], placed: bool = False
    ) -> StepSnapshot:
        """``contact=None``: after a step, from PhysX's contacts and the footprint's overlap.
        Also makes the step's ``observed_snapshot``."""
        humans = self._crowd.positions if self._crowd is not None else None
        snapshot = self._sensing.take(step, self._target_xy, self._moving_xy, contact, previous, placed, humans)
        noise = self._noise
        self._observed = snapshot if noise is None else noise.perceive(snapshot, contact is None, self.world.arena)
        return snapshot

    @property
    def snapshot(self) -> StepSnapshot:
        """The frozen ``StepSnapshot`` of the latest reset, step or ``place_robot``."""
        if self._snapshot is None:
            raise RuntimeError("no snapshot yet: call reset() first")
        return self._snapshot

    # ------------------------------------------------------------------ ManiSkill API
    def reset(self, seed=None, options=None):
        """Reset; a seed makes the episode (start, target, motions) replay bit for bit.

        All of the task's randomness comes from gymnasium's ``self.np_random``, seeded here
        as ``gymnasium.Env.reset`` does (an unseeded reset continues the generator).
        """
        if isinstance(seed, (list, tuple, np.ndarray)):  # ManiSkill's batched form
            seed = int(seed[0])
        gym.Env.reset(self, seed=seed)
        if self._noise is not None:
            self._noise.seed(seed)  # its own generators, from the same seed
        options = options or {}
        reconfigure = options.get("reconfigure", False) or (
            self._reconfig_counter == 0 and self.reconfiguration_freq != 0
        )
        if seed is not None and not (reconfigure or self._enhanced_determinism or "env_idx" in options):
            # ManiSkill's seeded reset: its generators seeded as below, then _initialize_episode
            # run with torch seeded and its state restored afterwards (about 1 ms: torch seeds
            # every device type). The task draws nothing from torch, so the same reset without
            # a seed, after seeding ManiSkill's generators here, is the same reset.
            self._set_main_rng(seed)
            self._set_episode_rng(seed, np.arange(self.num_envs))
            seed = None
        return super().reset(seed=seed, options=options)

    def outcome(self) -> dict:
        """Success and failure of the current snapshot, as Python values (read-only).

        success: the robot's centre within ``reach_radius`` of the target, without contact;
        collision (also ``fail``): the robot touched a wall or an obstacle; timeout: the step
        limit came first. ``evaluate`` returns the same as batched tensors.
        """
        s = self.snapshot
        if self._outcome_of is s:
            return dict(self._outcome)
        collision = s.contact
        success = s.d1 <= self.reach_radius and not collision
        self._outcome_of, self._outcome = s, dict(
            elapsed_steps=s.step,
            success=success,
            fail=collision,
            collision=collision,
            timeout=s.step >= self.max_episode_steps and not (success or collision),
            human_collision=s.human_contact,
            distance_to_target=s.d1,
            path_length=s.path_length,
        )
        return dict(self._outcome)

    def evaluate(self) -> dict:
        """The single source of success and failure, read from the snapshot; changes nothing."""
        result = self.outcome()
        del result["elapsed_steps"]
        return {
            k: torch.tensor([v], dtype=torch.float32 if isinstance(v, float) else torch.bool)
            for k, v in result.items()
        }

    @property
    def elapsed_steps(self) -> torch.Tensor:
        """Steps since the reset, batched (ManiSkill's API)."""
        steps = self._snapshot.step if self._snapshot is not None else 0
        return torch.tensor([steps], dtype=torch.int32)

    def _terminal(self) -> bool:
        if self._outcome_of is not self.snapshot:
            self.outcome()  # caches it
        return self._outcome["success"] or self._outcome["collision"]

    @property
    def obstacle_motions(self) -> tuple[EpisodeMotion, ...]:
        """The moving obstacle groups of this episode, in state-vector order: each one's motion
        spec, body count and the speed it drew at the reset (read-only copies)."""
        return tuple(EpisodeMotion.of(mover) for mover, _ in self._movers)

    @property
    def pedestrian_goals(self) -> np.ndarray:
        """(k, 2) where each pedestrian is heading now, in crowd order (a copy; (0, 2) without a crowd)."""
        return self._crowd.goals.copy() if self._crowd is not None else np.zeros((0, 2))

    @property
    def target_index(self) -> int:
        """Which of the world's targets this episode's robot must reach (0-based)."""
        return self._target_index

    def get_reward(self, obs, action, info):
        """The latest step's reward under the task's ``reward_mode``, batched (ManiSkill's API)."""
        return torch.tensor([self._reward], dtype=torch.float32)

    def close(self):
        """Release the scene at once, so nothing of SAPIEN's lingers for a forked child."""
        for name in ("_px", "_sensing", "_movers", "_moving_bodies", "_targets", "segmentation_id_map"):
            self.__dict__.pop(name, None)
        super().close()

    # ------------------------------------------------------------------ convenience
    def place_pedestrians(self, xy, goals=None):
        """Put the crowd's pedestrians at ``xy`` (k, 2), at rest, heading for ``goals`` (k, 2;
        default: where they stand), for tests and tools; takes a new snapshot (same step)."""
        crowd = self._crowd
        if crowd is None:
            raise ValueError("this task's world has no pedestrians (World.pedestrians)")
        xy = np.array(xy, dtype=np.float64).reshape(-1, 2)
        if len(xy) != crowd.spec.count:
            raise ValueError(f"the world has {crowd.spec.count} pedestrians; got {len(xy)} places")
        crowd.positions = xy.copy()
        crowd.velocities = np.zeros_like(xy)
        crowd.goals = xy.copy() if goals is None else np.array(goals, dtype=np.float64).reshape(-1, 2)
        crowd.starts = crowd.positions.copy()
        pose = self._kinematic_pose
        for body, (x, y) in zip(self._human_bodies, xy.tolist()):
            pose.p = [x, y, self.world.pedestrians.height / 2]
            body.entity.set_pose(pose)
            body.set_kinematic_target(pose)
        prev = self.snapshot
        self._snapshot = self._take_snapshot(step=prev.step, contact=False, previous=prev, placed=True)

    def pedestrian_forecast(self, steps: int) -> np.ndarray:
        """(steps + 1, n, 2): where the pedestrians are now and after each of the next ``steps``
        control steps if the robot were not there: their motion model stepped forward on a copy
        of the crowd (and of the random generator). Exact for pedestrians blind to the robot that
        stop at their goals; a goal drawn on the way may differ from the one the episode draws.
        (0, 0, 2)-shaped slices without pedestrians."""
        crowd = self._crowd
        if crowd is None:
            return np.zeros((steps + 1, 0, 2))
        ghost, rng = copy.deepcopy(crowd), copy.deepcopy(self.np_random)
        out = np.empty((steps + 1, crowd.spec.count, 2))
        out[0] = crowd.positions
        boxes = self._crowd_obstacles()
        for k in range(1, steps + 1):
            out[k] = ghost.step(1.0 / self._control_freq, rng, robot=None, boxes=boxes)
        return out

    def place_robot(self, x: float, y: float, yaw: float):
        """Teleport the robot (for tests and tools) and take a new snapshot (same step, same
        path length, no contact: nothing was simulated); returns the state vector."""
        self.agent.set_pose2d(x, y, yaw)
        prev = self.snapshot
        self._snapshot = self._take_snapshot(step=prev.step, contact=False, previous=prev, placed=True)
        return self.state_vector()
