"""Seeded noise and per-episode randomization of a task: all off by default.

``NoiseConfig`` holds the options, given to any task as flat keyword arguments (they fit a
training config's ``task_kwargs``) or as one ``noise=`` dict or ``NoiseConfig``::

    gym.make("DynNav-MovingObstacles-v1", laser_noise_std=0.02, laser_dropout=0.01,
             odometry_drift_std=0.005, action_noise=0.05,
             robot_speed_scale_min=0.8, robot_speed_scale_max=1.2,
             obstacle_speed_scale_min=0.5, obstacle_speed_scale_max=1.5)

=============================  =========  ==================================================
option                         default    what it does
=============================  =========  ==================================================
``laser_noise_std``            0          Gaussian noise added to every laser reading (m)
``laser_dropout``              0          probability that a ray's reading is lost; a lost
                                          ray reads the laser's range (as if it met nothing)
``odometry_drift_std``         0          odometry drift: the position the agent observes is
                                          the true one plus a random walk that starts at 0
                                          at every reset and takes one Gaussian step of this
                                          std (m, on x and y) per control step
``action_noise``               0          probability that the executed action is one drawn
                                          uniformly from all three (it may be the one asked
                                          for: the asked one runs with probability 1 - 2p/3);
                                          with ``control_mode="diff_drive_vel"``: the std of
                                          Gaussian noise added to (v, w), as a fraction of
                                          each limit, the result clipped to the action box
``robot_speed_scale_min/max``  1, 1       every episode, the robot's forward, turn and
                                          turn-forward steps are scaled by one factor drawn
                                          uniformly from [min, max]; with the velocity drive,
                                          its executed velocities and accelerations
``obstacle_speed_scale_min/max`` 1, 1     every episode, every moving obstacle's speed (m
                                          per step) is scaled by one factor drawn uniformly
                                          from [min, max] (targets keep their speed)
=============================  =========  ==================================================

Laser readings, noisy or dropped, are clipped to [0, range]. The observed position is
clipped to the arena's bounds (the observation space's); the drift itself walks on.

Only what the agent observes and what the robot executes change: the physics, the reward,
the outcome and ``env.unwrapped.snapshot`` use the true pose and the true laser readings;
``env.unwrapped.observed_snapshot`` is the snapshot as the agent perceives it (the state
vector is read from it). In the egocentric state (``egocentric.py``) the target's distance and
bearing and the obstacles' relative positions are computed from the observed position.

Seeds: every draw comes from generators of this module, one per option (laser noise,
dropout, drift, action, the episode's factors), seeded from the reset's seed and never from
the world's generator: a seed replays the noise bit for bit, and turning noise on leaves the
world's own draws (start, target, obstacles' speeds and routes) as they were. An unseeded
reset continues the generators (the first one seeds them from fresh entropy).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .drive import VelocityDriveConfig
from .robot import ACTION_NAMES, DriveConfig
from .snapshot import StepSnapshot, perceived_snapshot

MAX_LASER_NOISE_STD = 1.0
"""metres: the largest ``laser_noise_std``"""
MAX_ODOMETRY_DRIFT_STD = 0.5
"""metres per control step: the largest ``odometry_drift_std``"""
MAX_SPEED_SCALE = 2.0
"""the largest speed factor (robot and obstacles); the scaled robot steps must also stay
within ``DriveConfig``'s bounds"""
NOISE_SEED_KEY = 0x6E6F6973
"""the spawn key that keeps the noise generators apart from every other seeded generator"""
STREAMS = ("laser_noise", "laser_dropout", "odometry_drift", "action", "episode")
"""one generator each, in this order of spawn keys"""


@dataclass(frozen=True)
class NoiseConfig:
    """The noise and randomization options of a task (module docstring); all off by default.
    Made with bad values, it raises a ValueError naming the option."""

    laser_noise_std: float = 0.0
    """std of the Gaussian noise on every laser reading (m)"""
    laser_dropout: float = 0.0
    """probability per ray and reading that it is lost (reads the range)"""
    odometry_drift_std: float = 0.0
    """std of the observed position's random walk, per control step (m)"""
    action_noise: float = 0.0
    """probability that the executed action is drawn uniformly from all three (the velocity
    drive: std of the Gaussian noise on (v, w), as a fraction of each limit)"""
    robot_speed_scale_min: float = 1.0
    """lowest factor of the robot's step lengths, drawn per episode"""
    robot_speed_scale_max: float = 1.0
    """highest factor of the robot's step lengths, drawn per episode"""
    obstacle_speed_scale_min: float = 1.0
    """lowest factor of the moving obstacles' speeds, drawn per episode"""
    obstacle_speed_scale_max: float = 1.0
    """highest factor of the moving obstacles' speeds, drawn per episode"""

    def __post_init__(self):
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"{f.name} must be a finite number, got {value!r}")
            object.__setattr__(self, f.name, float(value))
        for name, high, unit in (
            ("laser_noise_std", MAX_LASER_NOISE_STD, " m"),
            ("laser_dropout", 1.0, ""),
            ("odometry_drift_std", MAX_ODOMETRY_DRIFT_STD, " m"),
            ("action_noise", 1.0, ""),
        ):
            if not 0.0 <= getattr(self, name) <= high:
                raise ValueError(f"{name} must be from 0 to {high}{unit}, got {getattr(self, name)!r}")
        for what in ("robot", "obstacle"):
            low, high = f"{what}_speed_scale_min", f"{what}_speed_scale_max"
            lo, hi = getattr(self, low), getattr(self, high)
            if not 0.0 < lo <= MAX_SPEED_SCALE:
                raise ValueError(f"{low} must be > 0 and <= {MAX_SPEED_SCALE}, got {lo!r}")
            if not lo <= hi <= MAX_SPEED_SCALE:
                raise ValueError(f"{high} must be >= {low} ({lo!r}) and <= {MAX_SPEED_SCALE}, got {hi!r}")

    @classmethod
    def options(cls) -> tuple[str, ...]:
        """The task options' names (the fields)."""
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def from_task_options(cls, noise=None, options: Optional[dict] = None) -> "NoiseConfig":
        """The config of a task's ``noise=`` (a ``NoiseConfig``, a dict or None) or of its flat
        options, which are taken out of ``options`` (a task's other keyword arguments)."""
        flat = {name: options.pop(name) for name in cls.options() if options is not None and name in options}
        if noise is not None and flat:
            raise ValueError(f"give the noise options either as noise= or as keyword arguments, not both "
                             f"(got noise= and {', '.join(sorted(flat))})")
        if isinstance(noise, NoiseConfig):
            return noise
        if noise is not None and not isinstance(noise, dict):
            raise ValueError(f"noise must be a dynnav_tasks.noise.NoiseConfig or a dict of its options, got {noise!r}")
        given = dict(noise or flat)
        unknown = sorted(set(given) - set(cls.options()))
        if unknown:
            raise ValueError(f"unknown noise option(s) {', '.join(unknown)}; valid: {', '.join(cls.options())}")
        return cls(**given)

    @property
    def enabled(self) -> bool:
        """Is any option away from its default (off)?"""
        return self != NoiseConfig()


def scaled_drive(drive: DriveConfig | VelocityDriveConfig, factor: float) -> DriveConfig | VelocityDriveConfig:
    """``drive`` with its three step lengths (or, a ``VelocityDriveConfig``, its executed
    velocities and accelerations) multiplied by ``factor``."""
    if isinstance(drive, VelocityDriveConfig):
        return drive.scaled(factor)
    return dataclasses.replace(
        drive,
        forward_step=drive.forward_step * factor,
        turn_step=drive.turn_step * factor,
        turn_forward_step=drive.turn_forward_step * factor,
    )


class EpisodeNoise:
    """A task's noise at work (``NavEnv.episode_noise``) for its nominal ``drive`` (a
    ``DriveConfig`` or a ``VelocityDriveConfig``: the task's control mode) and its lasers'
    range: its generators, this episode's factors and drift. Public and read-only:
    ``config``, ``robot_speed_factor`` and
    ``obstacle_speed_factor`` (this episode's), ``drift`` (the observed position's offset
    now, m) and ``executed_action`` (the action the robot ran in the last step)."""

    def __init__(self, config: NoiseConfig, drive: DriveConfig | VelocityDriveConfig, laser_range: float):
        self.config = config
        self.drive = drive
        self.laser_range = float(laser_range)
        try:
            scaled_drive(drive, config.robot_speed_scale_max).validate()
        except ValueError as err:
            raise ValueError(f"robot_speed_scale_max {config.robot_speed_scale_max!r} makes the robot too fast: {err}") from None
        self._rngs: Optional[dict[str, np.random.Generator]] = None
        self.robot_speed_factor = 1.0
        self.obstacle_speed_factor = 1.0
        self.drift = (0.0, 0.0)
        self.executed_action: Optional[int | tuple[float, float]] = None

    def seed(self, seed: Optional[int]) -> None:
        """Seed the generators from a reset's seed; ``None`` continues them (the first time:
        fresh entropy)."""
        if seed is None and self._rngs is not None:
            return
        entropy = np.random.SeedSequence(None if seed is None else int(seed)).entropy
        self._rngs = {
            name: np.random.default_rng(np.random.SeedSequence(entropy, spawn_key=(NOISE_SEED_KEY, k)))
            for k, name in enumerate(STREAMS)
        }

    def start_episode(self, controller, movers) -> None:
        """Draw the episode's speed factors and apply them: the robot's ``controller`` (a
        ``DiscreteDriveController`` or ``VelocityDriveController``) drives ``drive_config()``,
        each obstacle ``Mover`` of
        ``movers`` (just reset) scales its speed; the drift starts at 0."""
        if self._rngs is None:
            self.seed(None)
        c, rng = self.config, self._rngs["episode"]
        self.robot_speed_factor = float(rng.uniform(c.robot_speed_scale_min, c.robot_speed_scale_max))
        self.obstacle_speed_factor = float(rng.uniform(c.obstacle_speed_scale_min, c.obstacle_speed_scale_max))
        self.drift = (0.0, 0.0)
        self.executed_action = None
        controller.configure(self.drive_config())
        for mover in movers:
            mover.scale_speed(self.obstacle_speed_factor)

    def drive_config(self) -> DriveConfig | VelocityDriveConfig:
        """The robot's drive this episode (scaled by ``robot_speed_factor``)."""
        return scaled_drive(self.drive, self.robot_speed_factor)

    def execute(self, action: int | tuple[float, float]) -> int | tuple[float, float]:
        """The action the robot runs when the agent asks for ``action``: an index, or the
        velocity drive's ``(v, w)`` (already clipped to the box)."""
        p = self.config.action_noise
        if p > 0.0:
            rng = self._rngs["action"]
            if isinstance(action, tuple):
                d = self.drive
                dv, dw = rng.normal(0.0, p, 2).tolist()
                action = d.clip(action[0] + dv * d.max_linear_speed, action[1] + dw * d.max_angular_speed)
            elif rng.random() < p:
                action = int(rng.integers(len(ACTION_NAMES)))
        self.executed_action = action
        return action

    def perceive(self, snapshot: StepSnapshot, stepped: bool, arena) -> StepSnapshot:
        """``snapshot`` as the agent perceives it: noisy, dropped and clipped laser readings
        and the drifted position (clipped to the ``arena``'s x and y ranges). ``stepped``: the
        snapshot follows a simulated step, so the drift takes a step first."""
        c, rngs, laser_range = self.config, self._rngs, self.laser_range
        lasers = snapshot.lasers
        if c.laser_noise_std > 0.0 or c.laser_dropout > 0.0:
            readings = lasers.astype(np.float64)
            if c.laser_noise_std > 0.0:
                readings += rngs["laser_noise"].normal(0.0, c.laser_noise_std, len(readings))
            if c.laser_dropout > 0.0:
                readings[rngs["laser_dropout"].random(len(readings)) < c.laser_dropout] = laser_range
            lasers = np.clip(readings, 0.0, laser_range).astype(np.float32)
            lasers.setflags(write=False)
        x, y, _ = snapshot.pose
        if c.odometry_drift_std > 0.0:
            if stepped:
                dx, dy = rngs["odometry_drift"].normal(0.0, c.odometry_drift_std, 2).tolist()
                self.drift = (self.drift[0] + dx, self.drift[1] + dy)
            (x0, x1), (y0, y1) = arena.x_range, arena.y_range
            x = min(max(x + self.drift[0], x0), x1)
            y = min(max(y + self.drift[1], y0), y1)
        if lasers is snapshot.lasers and (x, y) == snapshot.pose[:2]:
            return snapshot
        return perceived_snapshot(snapshot, lasers, (x, y))
