"""A planner that sees the full state: the best achievable in each world, to compare learners with.

    python -m dynnav_tasks.baselines.state_planner --task DynNav-MovingObstacles-v1 --episodes 200

Every step, ``StatePlanner`` reads the task's world (walls, static boxes, how each thing moves)
and the state vector (robot, target and moving obstacles' positions), forecasts where every
moving obstacle can be over the next ``horizon`` steps, and searches (A* over the robot's
three actions, in space and time) for the shortest action sequence that reaches the target
without ever coming within ``clearance`` of a wall or a box. It takes the first action and
plans again from the next state.

Forecasts (``ObstacleForecast``), from the motion specs in ``motion.py``:

* ``BackAndForth``: exact (the spec gives the speed; the last two positions give the way).
* ``Route``: the arc position from the position; the speed from the last two positions (before
  that, every speed of the spec's range).
* ``RandomInRect``: anywhere within ``k * max speed`` of now, inside its area (no guessing).

Between two steps an obstacle sweeps the box spanning both positions; the planner keeps clear
of that, so a fast obstacle cannot pass through the robot between steps. The robot is taken
as the circle around its footprint (radius 0.295 m).
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import tyro

from dynnav_tasks.motion import BackAndForth, RandomInRect, Route, Static, wrap_angle
from dynnav_tasks.outcomes import outcome_of
from dynnav_tasks.robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH

FORWARD, LEFT, RIGHT = 0, 1, 2
ROBOT_RADIUS = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)


class ObstacleForecast:
    """Where each moving obstacle of a world can be, step by step, as boxes (lo, hi corners)."""

    def __init__(self, world, remember: bool = True):
        self.remember = remember  # False: forget the last positions, as a learner fed one state does
        self.specs = []  # (motion spec, half size) per moving obstacle, in state-vector order
        for group in world.obstacles:
            if group.moving:
                self.specs += [(group.motion, np.asarray(group.half_size, float))] * group.count
        self.previous: Optional[np.ndarray] = None

    def reset(self) -> None:
        self.previous = None

    def boxes(self, xy: np.ndarray, horizon: int) -> np.ndarray:
        """(horizon + 1, n, 2, 2): for step k, the box each obstacle may cover between steps
        k - 1 and k (step 0: where it is), grown by its half size."""
        centres = np.empty((horizon + 1, len(self.specs), 2, 2))
        for i, (spec, half) in enumerate(self.specs):
            prev = None if self.previous is None else self.previous[i]
            for k, (lo, hi) in enumerate(_reach(spec, xy[i], prev, horizon)):
                centres[k, i, 0], centres[k, i, 1] = lo - half, hi + half
        self.previous = xy.copy() if self.remember else None
        swept = centres.copy()  # step k >= 1 covers the boxes of steps k - 1 and k
        swept[1:, :, 0] = np.minimum(centres[:-1, :, 0], centres[1:, :, 0])
        swept[1:, :, 1] = np.maximum(centres[:-1, :, 1], centres[1:, :, 1])
        return swept


def _reach(spec, p, prev, steps):
    """Boxes (lo, hi) of the centre's possible positions now and at each of ``steps`` steps."""
    if isinstance(spec, Static):
        return [(p, p)] * (steps + 1)
    if isinstance(spec, RandomInRect):
        lo_a, hi_a = spec.extent()
        r = spec.speed_range[1]
        return [(np.maximum(p - k * r, lo_a), np.minimum(p + k * r, hi_a)) for k in range(steps + 1)]
    if isinstance(spec, BackAndForth):
        c, d = np.asarray(spec.center, float), np.asarray(spec.direction, float)
        d = d / np.linalg.norm(d)
        off = float(np.dot(p - c, d))
        signs = [1.0, -1.0]
        if prev is not None and abs(off - float(np.dot(prev - c, d))) > 1e-9:
            step = off - float(np.dot(prev - c, d))
            signs = [math.copysign(1.0, step)]
        paths = [_back_and_forth(off, s, spec.speed, spec.amplitude, steps) for s in signs]
        pts = [[c + o * d for o in offs] for offs in paths]
        return [(np.min([q[k] for q in pts], 0), np.max([q[k] for q in pts], 0)) for k in range(steps + 1)]
    if isinstance(spec, Route):
        s0, length = spec.nearest_arc_length(p), spec.length()
        if prev is not None:
            v = (s0 - spec.nearest_arc_length(prev)) % length
            lo_v = hi_v = v
        else:
            lo_v, hi_v = spec.speed_range
        out = []
        for k in range(steps + 1):
            arc = np.arange(s0 + k * lo_v, s0 + k * hi_v + 0.1, 0.1)  # every 0.1 m of the arc it may be on
            pts = np.array([spec.position_at(a) for a in arc])
            out.append((pts.min(0), pts.max(0)))
        return out
    raise TypeError(f"no forecast for motion {type(spec).__name__}")


def _back_and_forth(offset, sign, speed, amplitude, steps):
    offs = [offset]
    for _ in range(steps):
        s = offset + sign * speed
        while s > amplitude or s < -amplitude:
            s, sign = (2 * amplitude - s, -1.0) if s > amplitude else (-2 * amplitude - s, 1.0)
        offset = s
        offs.append(offset)
    return offs


def _hits(x, y, boxes, clearance_sq) -> bool:
    """Whether (x, y) comes closer than the clearance to any box (lo_x, lo_y, hi_x, hi_y).

    Plain Python over a few boxes: the search calls it for every node, where numpy's per-call
    cost is larger than the work (``benchmarks/state_planner.py``)."""
    for lx, ly, hx, hy in boxes:
        dx = lx - x if x < lx else (x - hx if x > hx else 0.0)
        dy = ly - y if y < ly else (y - hy if y > hy else 0.0)
        if dx * dx + dy * dy < clearance_sq:
            return True
    return False


@dataclass
class StatePlanner:
    """Plans every step with the world's geometry and motions and the current state vector."""

    world: object
    """the task's ``World`` (``env.unwrapped.world``)"""
    forward_step: float = 0.15
    turn_step: float = math.pi / 8
    reach_radius: float = 0.3
    clearance: float = ROBOT_RADIUS + 0.03
    """the robot's centre keeps this far from every wall and box (m)"""
    horizon: int = 60
    """steps planned ahead"""
    max_expansions: int = 30000
    """search budget per step; past it the planner heads for the best node found (with 6000 it
    cut through 5.5c's obstacle areas in 4 of 30 episodes instead of finding the lane around them)"""
    cell: float = 0.05
    """grid (m) on which two search nodes at the same step count as one"""
    remember: bool = True
    """False: forecast from the current state alone (every speed and way a box may have), as an
    agent fed one state vector must; True: also from the previous step's positions"""

    def __post_init__(self):
        self.forecast = ObstacleForecast(self.world, remember=self.remember)
        arena = self.world.arena
        self._x, self._y = arena.x_range, arena.y_range
        static = [(np.asarray(g.motion.at, float), np.asarray(g.half_size, float))
                  for g in self.world.obstacles if not g.moving]
        self._static = [(*(c - h), *(c + h)) for c, h in static]
        self._clearance_sq = self.clearance * self.clearance

    def reset(self) -> None:
        self.forecast.reset()

    def _free(self, x, y, moving_boxes) -> bool:
        c = self.clearance
        if not (self._x[0] + c <= x <= self._x[1] - c and self._y[0] + c <= y <= self._y[1] - c):
            return False
        return not (_hits(x, y, self._static, self._clearance_sq) or _hits(x, y, moving_boxes, self._clearance_sq))

    def act(self, state: np.ndarray, yaw: float) -> int:
        """The first action of the best plan from ``state`` (the task's state vector) and the
        robot's heading ``yaw`` (rad)."""
        x0, y0 = float(state[16]), float(state[17])
        tx, ty = float(state[18]), float(state[19])
        moving = np.asarray(state[20:], float).reshape(-1, 2)
        boxes = self.forecast.boxes(moving, self.horizon) if len(moving) else np.zeros((self.horizon + 1, 0, 2, 2))
        boxes = [step.reshape(-1, 4).tolist() for step in boxes]  # per step: [lo_x, lo_y, hi_x, hi_y] per box

        def h(x, y, yaw_):
            d = math.hypot(tx - x, ty - y)
            turn = abs(wrap_angle(math.atan2(ty - y, tx - x) - yaw_)) if d > self.reach_radius else 0.0
            return max(d - self.reach_radius, 0) / self.forward_step + max(turn - self.turn_step / 2, 0) / self.turn_step

        start = (x0, y0, yaw)
        frontier = [(h(*start), 0, 0, start, None)]
        parents, seen, best, count = {}, set(), None, 0
        while frontier and count < self.max_expansions:
            f, k, node_id, (x, y, a), first = heapq.heappop(frontier)
            hx = f - k
            if best is None or hx < best[0]:
                best = (hx, first)
            if math.hypot(tx - x, ty - y) <= self.reach_radius and k > 0:
                return first
            if k >= self.horizon:
                continue
            for action in (FORWARD, LEFT, RIGHT):
                if action == FORWARD:
                    nx, ny, na = x + self.forward_step * math.cos(a), y + self.forward_step * math.sin(a), a
                else:
                    nx, ny, na = x, y, a + (self.turn_step if action == LEFT else -self.turn_step)
                key = (k + 1, round(nx / self.cell), round(ny / self.cell), round(wrap_angle(na) / self.turn_step))
                if key in seen or not self._free(nx, ny, boxes[k + 1]):
                    continue
                seen.add(key)
                count += 1
                heapq.heappush(frontier, (k + 1 + h(nx, ny, na), k + 1, count, (nx, ny, na),
                                          action if first is None else first))
        if best is not None and best[1] is not None:
            return best[1]
        return LEFT  # boxed in: turning in place sweeps least


@dataclass
class PlannerResult:
    task: str
    outcomes: list

    def rate(self, outcome: str = "success") -> float:
        return self.outcomes.count(outcome) / len(self.outcomes)

    def summary(self) -> str:
        return (f"{self.task}: success {self.rate():.1%}, collision {self.rate('collision'):.1%}, "
                f"timeout {self.rate('timeout'):.1%} over {len(self.outcomes)} episodes")


def run_planner(task_id: str, seeds, progress: bool = False, **planner_kwargs) -> PlannerResult:
    """One episode per seed of ``task_id`` driven by a ``StatePlanner``."""
    from dynnav_tasks import NumpyWrapper, make

    env = NumpyWrapper(make(task_id, obs_mode="state"))
    base = env.unwrapped
    drive = base.drive_config
    planner = StatePlanner(base.world, forward_step=drive.forward_step, turn_step=drive.turn_step,
                           reach_radius=base.reach_radius, **planner_kwargs)
    seeds = list(seeds)
    if progress:
        from tqdm import tqdm

        seeds = tqdm(seeds, desc=task_id, unit="episode")
    outcomes = []
    try:
        for seed in seeds:
            obs, _ = env.reset(seed=int(seed))
            planner.reset()
            done = False
            while not done:
                yaw = float(base.agent.pose2d()[2])
                obs, _, terminated, truncated, info = env.step(planner.act(obs, yaw))
                done = terminated or truncated
            outcomes.append(outcome_of(info, terminated))
    finally:
        env.close()
    return PlannerResult(task_id, outcomes)


@dataclass
class Args:
    task: Optional[str] = None
    """task to plan in (default: every task)"""
    episodes: int = 200
    """episodes per task (seeds first_seed .. first_seed + episodes - 1)"""
    first_seed: int = 0
    """seed of the first episode"""
    max_expansions: int = StatePlanner.max_expansions
    """search budget per step (A* nodes)"""
    memoryless: bool = False
    """forecast the boxes from the current state alone, without the previous step's positions
    (the information an agent fed one state vector has)"""
    out: Optional[str] = None
    """also write each task's success, collision and timeout rates into this JSON file (merged
    with what it holds, one entry per task), e.g. docs/results/ceilings.json for agents.study.report"""


def main(args: Args) -> None:
    from dynnav_tasks import TASK_IDS
    from dynnav_tasks.baselines.cli import run_over_tasks

    run_over_tasks(args.task, TASK_IDS, "task id", args.episodes, args.first_seed,
                   lambda task, seeds: run_planner(task, seeds, progress=True, max_expansions=args.max_expansions,
                                                       remember=not args.memoryless),
                   out=args.out)

if __name__ == "__main__":
    main(tyro.cli(Args))
