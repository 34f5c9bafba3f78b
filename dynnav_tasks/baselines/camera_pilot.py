"""A scripted controller that sees only the front camera's frame: proof that the camera
worlds can be solved from the camera alone.

    python -m dynnav_tasks.baselines.camera_pilot --task DynNav-VisualStaticTarget-v1 --episodes 100

``CameraPilot.act(frame)`` reads one 32x32 RGB frame (nothing else: no pose, no lasers, no
target position) and returns an action:

1. **Find the target.** Red pixels are the target (disc and marker; nothing else in the
   palette is red). None in view: turn towards the side where they were last seen.
2. **Centre it.** Their mean column more than ``centre_tolerance`` pixels off the middle:
   turn towards it (one turn moves the image about 8 columns).
3. **Drive, unless blocked.** Everything that is neither floor, sky nor target stands on
   the floor (a wall or a box). The lowest such pixel of a column is where it meets the
   floor; the camera's known height and tilt turn that row into a floor point. If a box's
   foot is within ``box_distance`` in any direction, or anything stands in the robot's lane
   within ``stop_distance``, wait (turn left and right in turn, which keeps the heading) for
   it to pass; otherwise drive.

Its success rates bound from below what the camera alone allows in each world; the closing
numbers are in the README ("Camera worlds").
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
import tyro

from dynnav_tasks.camera import CameraSpec
from dynnav_tasks.drive import require_discrete_drive
from dynnav_tasks.outcomes import outcome_of
from dynnav_tasks.robot import CAMERA_OFFSET
from dynnav_tasks.world import MOVING_OBSTACLE_COLOR, STATIC_OBSTACLE_COLOR

FORWARD, LEFT, RIGHT = 0, 1, 2


def target_mask(frame: np.ndarray) -> np.ndarray:
    """Pixels of the red target (disc and marker): bool (H, W)."""
    r, g, b = (frame[..., k].astype(np.int16) for k in range(3))
    return (r > 150) & (g < 100) & (b < 100)


def floor_mask(frame: np.ndarray) -> np.ndarray:
    """Pixels of the light gray floor: bool (H, W)."""
    f = frame.astype(np.int16)
    return (f.min(axis=-1) > 180) & (f.max(axis=-1) - f.min(axis=-1) < 25)


def colour_mask(frame: np.ndarray, rgba, tolerance: int = 40) -> np.ndarray:
    """Pixels within ``tolerance`` (per channel, 0-255) of a palette colour: bool (H, W)."""
    want = np.round(np.asarray(rgba[:3]) * 255).astype(np.int16)
    return (np.abs(frame.astype(np.int16) - want) <= tolerance).all(axis=-1)


def box_mask(frame: np.ndarray) -> np.ndarray:
    """Pixels of obstacle boxes (yellow moving, blue static): bool (H, W)."""
    return colour_mask(frame, MOVING_OBSTACLE_COLOR) | colour_mask(frame, STATIC_OBSTACLE_COLOR)


def sky_mask(frame: np.ndarray) -> np.ndarray:
    """Pixels where nothing was hit (black): bool (H, W)."""
    return frame.max(axis=-1) < 25


@dataclass
class CameraPilot:
    """Steers towards red pixels and around boxes, remembering what it saw."""

    camera: CameraSpec = field(default_factory=CameraSpec)
    """the camera's optics (its calibration: field of view and tilt)"""
    lens: tuple[float, float] = (CAMERA_OFFSET[0], CAMERA_OFFSET[2])
    """the lens's distance ahead of the robot's centre and height above the floor (m)"""
    forward_step: float = 0.15
    """metres one forward action drives (the task's ``forward_step``)"""
    turn_step: float = math.pi / 8
    """radians one turn action turns (the task's ``turn_step``)"""
    centre_tolerance: float = 0.2
    """radians the target may be off straight ahead before the pilot turns to it (a turn is 0.39)"""
    box_distance: float = 0.8
    """a box's foot closer than this ahead of the lens, in the lane, blocks the way (m)"""
    box_cone: float = 0.6
    """radians either side of straight ahead in which a box's foot within ``box_distance``
    blocks the way too (a box beside the lane may step into it)"""
    stop_distance: float = 0.45
    """anything (a wall) closer than this ahead of the lens, in the lane, blocks the way (m)"""
    lane_half_width: float = 0.35
    """half the width of the lane checked ahead (m; the chassis is 0.38 m wide)"""
    turn_clearance: float = 0.7
    """no turn towards the target while a remembered box's foot is this close to the centre (m)"""
    memory_steps: int = 8
    """steps a box's foot is remembered after it left the view (boxes move on)"""

    def __post_init__(self):
        rays = self.camera.pixel_rays()
        with np.errstate(divide="ignore"):
            k = np.where(rays[..., 2] < 0, self.lens[1] / -rays[..., 2], np.inf)
        # floor point (ahead of the centre, left) of each pixel centre (inf above the horizon)
        self._ahead, self._left = rays[..., 0] * k + self.lens[0], rays[..., 1] * k
        n = self.camera.size
        self._column_bearing = np.arctan2(rays[0, :, 1], 1.0)  # > 0: left of straight ahead
        self._half_view = self.camera.fov / 2
        self._nearest_seen = float(self._ahead[-1, n // 2])  # floor below the frame is not seen
        self.reset()

    def reset(self) -> None:
        """Forget the episode."""
        self._bearing = None  # where the target was last known to be (rad, > 0: left)
        self._boxes = np.zeros((0, 3))  # remembered box feet: ahead, left (m, robot frame), age
        self._last_action = FORWARD

    def _feet(self, solid: np.ndarray) -> np.ndarray:
        """Floor points (ahead, left) where the lowest solid pixel of each column meets the floor."""
        rows = np.arange(solid.shape[0])[:, None]
        lowest = np.where(solid, rows, -1).max(axis=0)  # -1: nothing in this column
        cols = np.nonzero(lowest >= 0)[0]
        feet = np.stack([self._ahead[lowest[cols], cols], self._left[lowest[cols], cols]], axis=1)
        return feet[np.isfinite(feet).all(axis=1)]  # a foot above the horizon is hidden: unknown

    def _in_view(self, points: np.ndarray) -> np.ndarray:
        ahead = points[:, 0] - self.lens[0]
        return (ahead > self._nearest_seen - self.lens[0]) & (np.abs(np.arctan2(points[:, 1], ahead)) < self._half_view)

    def _remember(self, frame: np.ndarray) -> None:
        """Boxes in view replace what was remembered there; boxes out of view age."""
        seen = self._feet(box_mask(frame))
        old = self._boxes[~self._in_view(self._boxes[:, :2])] if len(self._boxes) else self._boxes
        old = old[old[:, 2] < self.memory_steps]
        self._boxes = np.concatenate([np.column_stack([seen, np.zeros(len(seen))]), old])

    def _move(self, action: int) -> None:
        """Carry the remembered points and the target's bearing along with the robot's motion."""
        b = self._boxes
        if action == FORWARD:
            b[:, 0] -= self.forward_step
        else:
            a = self.turn_step if action == LEFT else -self.turn_step
            c, s = math.cos(a), math.sin(a)
            b[:, 0], b[:, 1] = c * b[:, 0] + s * b[:, 1], -s * b[:, 0] + c * b[:, 1]
            if self._bearing is not None:
                self._bearing -= a
        b[:, 2] += 1

    def blocked(self, frame: np.ndarray) -> bool:
        """Is a (remembered) box's foot in the lane within ``box_distance`` of the lens, or
        anything else (a wall) within ``stop_distance``?"""
        ahead, left = self._boxes[:, 0] - self.lens[0], self._boxes[:, 1]
        in_lane = (ahead > -self.lens[0]) & (np.abs(left) < self.lane_half_width)
        in_cone = (ahead > 0) & (np.abs(left) < ahead * math.tan(self.box_cone))
        if np.any((in_lane | in_cone) & (np.hypot(ahead, left) < self.box_distance)):
            return True
        wall = self._feet(~(floor_mask(frame) | sky_mask(frame) | target_mask(frame)))
        ahead, left = wall[:, 0] - self.lens[0], wall[:, 1]
        return bool(np.any((ahead < self.stop_distance) & (np.abs(left) < self.lane_half_width)))

    def box_side(self) -> int:
        """The side (LEFT / RIGHT) of the nearest remembered box."""
        nearest = np.argmin(np.hypot(self._boxes[:, 0], self._boxes[:, 1]))
        return LEFT if self._boxes[nearest, 1] > 0 else RIGHT

    def target_bearing(self, frame: np.ndarray) -> Optional[float]:
        """Radians from straight ahead to the target (> 0: left), None when it is out of sight.

        Measured on the highest row with red: a box in front hides the marker's foot, never
        its top, so that row shows the marker's full width."""
        red = target_mask(frame)
        rows = np.nonzero(red.any(axis=1))[0]
        if len(rows) == 0:
            return None
        cols = np.nonzero(red[rows[0]])[0]
        return float(self._column_bearing[cols].mean())

    def act(self, frame: np.ndarray) -> int:
        """The action for one RGB frame (H, W, 3) uint8."""
        seen = self.target_bearing(frame)
        if seen is not None:
            self._bearing = seen
        self._remember(frame)
        action = self._last_action = self._choose(frame)
        self._move(action)
        return action

    def _choose(self, frame: np.ndarray) -> int:
        if self._bearing is None:
            return LEFT  # never seen yet: look around
        toward = LEFT if self._bearing > 0 else RIGHT
        # a turn that swung the target across the middle left it within half a turn
        swung = self._last_action != FORWARD and toward != self._last_action
        aimed = abs(self._bearing) <= self.centre_tolerance or swung
        box_near = len(self._boxes) and np.hypot(self._boxes[:, 0], self._boxes[:, 1]).min() < self.turn_clearance
        blocked = self.blocked(frame)
        if aimed and not blocked:
            return FORWARD
        if not aimed and not box_near:
            return toward
        if not blocked:
            return FORWARD  # a box beside: drive on, clear of it, before turning
        if len(self._boxes):  # turn away from the box in the way
            return RIGHT if self.box_side() == LEFT else LEFT
        return toward


@dataclass
class PilotResult:
    """Outcomes of the pilot over a set of episodes."""

    task: str
    seeds: list[int]
    outcomes: list[str]
    """"success", "collision" or "timeout", per seed"""
    steps: list[int]
    target_seen: list[float]
    """fraction of each episode's frames with the target in view"""

    def rate(self, outcome: str = "success") -> float:
        return self.outcomes.count(outcome) / len(self.outcomes)

    def summary(self) -> str:
        n = len(self.outcomes)
        ok = [s for s, o in zip(self.steps, self.outcomes) if o == "success"]
        mean_steps = f"{np.mean(ok):.1f}" if ok else "-"
        return (f"{self.task}: success {self.rate():.0%}, collision {self.rate('collision'):.0%}, "
                f"timeout {self.rate('timeout'):.0%} over {n} episodes; {mean_steps} steps per success; "
                f"target in view in {np.mean(self.target_seen):.0%} of frames")


def run_pilot(task_id: str, seeds, pilot: Optional[CameraPilot] = None, env=None, progress: bool = False) -> PilotResult:
    """Drive ``pilot`` (default ``CameraPilot()``) for one episode per seed on ``task_id``.

    ``env``: an already made ``NumpyWrapper`` of the task with ``obs_mode="rgb"`` to reuse (in
    the default control mode, the discrete drive: the pilot chooses among its three actions).
    """
    from dynnav_tasks import NumpyWrapper, make

    own = env is None
    if own:
        env = NumpyWrapper(make(task_id, obs_mode="rgb"))
    if not own:
        require_discrete_drive(env.unwrapped, "the camera pilot")
    pilot = pilot or CameraPilot(camera=env.unwrapped.camera_spec)
    seeds = list(seeds)
    outcomes, steps, seen = [], [], []
    iterator = seeds
    if progress:
        from tqdm import tqdm

        iterator = tqdm(seeds, desc=task_id, unit="episode")
    try:
        for seed in iterator:
            frame, _ = env.reset(seed=int(seed))
            pilot.reset()
            n, in_view, done = 0, 0, False
            while not done:
                in_view += bool(target_mask(frame).any())
                frame, _, terminated, truncated, info = env.step(pilot.act(frame))
                n += 1
                done = terminated or truncated
            outcomes.append(outcome_of(info, terminated))
            steps.append(n)
            seen.append(in_view / n)
    finally:
        if own:
            env.close()
    return PilotResult(task_id, seeds, outcomes, steps, seen)


@dataclass
class Args:
    task: Optional[str] = None
    """camera world to drive in (default: all three)"""
    episodes: int = 100
    """episodes per world (seeds first_seed .. first_seed + episodes - 1)"""
    first_seed: int = 0
    """seed of the first episode"""
    out: Optional[str] = None
    """also write each task's success, collision and timeout rates into this JSON file (merged
    with what it holds, one entry per task), e.g. docs/results/camera_pilot.json"""


def main(args: Args) -> None:
    from dynnav_tasks import VISUAL_TASK_IDS
    from dynnav_tasks.baselines.cli import run_over_tasks

    run_over_tasks(args.task, VISUAL_TASK_IDS, "camera task id", args.episodes, args.first_seed,
                   lambda task, seeds: run_pilot(task, seeds, progress=True), out=args.out)

if __name__ == "__main__":
    main(tyro.cli(Args))
