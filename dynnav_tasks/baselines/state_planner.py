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

The search is guided by a lower bound on the steps still needed (``heuristic``): in the study's
worlds (at most ``STUDY_STATIC_BOXES`` static boxes) the straight line to the target and the
turn towards it; in worlds of many static blocks (``dynnav_tasks.generation``'s corridors and
rooms) the way through the static layout on an occupancy grid (``way_grid.py``) and the turn
towards where that way leads, so that the search follows corridors and doorways instead of
pushing at the wall between the robot and the target. There the collision check looks only at
the blocks near each point (``way_grid.StaticBuckets``), which gives the same answer.

Pedestrians (``world.pedestrians``) are forecast by their own motion model stepped forward on a
copy of the crowd (``NavEnv.pedestrian_forecast``: exact for pedestrians blind to the robot that
stop at their goals), each kept clear of as a box round its body, swept between steps.

``PlannerController`` drives a task with it from the task's public state (``snapshot``,
``world``), planning anew for each episode's world; ``run_planner`` plays episodes.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import tyro

from dynnav_tasks.baselines.episodes import ROBOT_RADIUS, EpisodeResults, run_episodes
from dynnav_tasks.baselines.tracked_forecast import TrackedForecast
from dynnav_tasks.baselines.way_grid import StaticBuckets, WayGrid, static_boxes
from dynnav_tasks.motion import BackAndForth, RandomInRect, Route, Static, wrap_angle

FORWARD, LEFT, RIGHT = 0, 1, 2
HEURISTICS = ("auto", "straight", "way")
"""``StatePlanner.heuristic``'s choices"""
STUDY_STATIC_BOXES = 3
"""the most static boxes a study world has (5.2's three): "auto" takes the straight line up to this"""


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

    def boxes(self, xy: np.ndarray, horizon: int, robot=None) -> np.ndarray:
        """(horizon + 1, n, 2, 2): for step k, the box each obstacle may cover between steps
        k - 1 and k (step 0: where it is), grown by its half size (``robot``: unused, every
        box is known)."""
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
    tracked: int = 0
    """0: forecast every box from its motion (the full state); k > 0: see only the k nearest boxes and
    forecast them at constant velocity (``tracked_forecast.py``: what the egocentric state tells)"""
    heuristic: str = "auto"
    """"straight": the straight line to the target; "way": the way through the static layout
    on an occupancy grid; "auto": "straight" in worlds of at most ``STUDY_STATIC_BOXES`` static
    boxes (the study's, where it is what the ceilings were measured with), "way" otherwise"""

    def __post_init__(self):
        if self.heuristic not in HEURISTICS:
            raise ValueError(f"heuristic must be one of {HEURISTICS}; got {self.heuristic!r}")
        self.forecast = (TrackedForecast(self.world, self.tracked) if self.tracked
                         else ObstacleForecast(self.world, remember=self.remember))
        arena = self.world.arena
        self._x, self._y = arena.x_range, arena.y_range
        self._static = static_boxes(self.world)
        self._clearance_sq = self.clearance * self.clearance
        self.uses_way = self.heuristic == "way" or (self.heuristic == "auto" and len(self._static) > STUDY_STATIC_BOXES)
        """whether the search follows the way through the static layout (see ``heuristic``)"""
        self._way = WayGrid(self.world, self.clearance) if self.uses_way else None
        self._buckets = StaticBuckets(self._static, self._x, self._y, self.clearance) if self.uses_way else None

    def reset(self) -> None:
        self.forecast.reset()

    def _free(self, x, y, moving_boxes) -> bool:
        c = self.clearance
        if not (self._x[0] + c <= x <= self._x[1] - c and self._y[0] + c <= y <= self._y[1] - c):
            return False
        static = self._static if self._buckets is None else self._buckets.near(x, y)
        return not (_hits(x, y, static, self._clearance_sq) or _hits(x, y, moving_boxes, self._clearance_sq))

    def _way_heuristic(self, tx: float, ty: float):
        """The lower bound of "way": steps along the way through the static layout, and the
        turn towards where it leads (towards the target once within reach)."""
        field, fs, ts, reach = self._way.to((tx, ty)), self.forward_step, self.turn_step, self.reach_radius

        def h(x, y, yaw_):
            d = field.distance(x, y)
            if math.hypot(tx - x, ty - y) <= reach:
                return 0.0
            ax, ay = field.aim(x, y)
            turn = abs(wrap_angle(math.atan2(ay - y, ax - x) - yaw_))
            return max(d - reach, 0) / fs + max(turn - ts / 2, 0) / ts

        return h

    def act(self, state: np.ndarray, yaw: float, humans: Optional[np.ndarray] = None, human_radius: float = 0.0,
            boxed_in: Optional[int] = LEFT) -> Optional[int]:
        """The first action of the best plan from ``state`` (the task's state vector) and the
        robot's heading ``yaw`` (rad); ``humans``: the pedestrians' forecast centres
        (``NavEnv.pedestrian_forecast``, at least ``horizon`` + 1 steps), kept clear of as boxes
        of half side ``human_radius`` swept between steps, as the moving boxes are; ``boxed_in``: the
        answer when no first step is free (turning in place sweeps least)."""
        n = len(state) - 4 - 2 * self.world.moving_obstacle_count  # laser readings: 16 unless laser_rays says
        x0, y0 = float(state[n]), float(state[n + 1])
        tx, ty = float(state[n + 2]), float(state[n + 3])
        moving = np.asarray(state[n + 4:], float).reshape(-1, 2)
        boxes = (self.forecast.boxes(moving, self.horizon, robot=(x0, y0)) if len(moving)
                 else np.zeros((self.horizon + 1, 0, 2, 2)))
        if humans is not None and humans.shape[1]:
            boxes = np.concatenate([boxes, _swept_circles(humans[:self.horizon + 1], human_radius)], axis=1)
        boxes = [step.reshape(-1, 4).tolist() for step in boxes]  # per step: [lo_x, lo_y, hi_x, hi_y] per box

        def h(x, y, yaw_):
            d = math.hypot(tx - x, ty - y)
            turn = abs(wrap_angle(math.atan2(ty - y, tx - x) - yaw_)) if d > self.reach_radius else 0.0
            return max(d - self.reach_radius, 0) / self.forward_step + max(turn - self.turn_step / 2, 0) / self.turn_step

        if self.uses_way:
            h = self._way_heuristic(tx, ty)

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
        return boxed_in


def _swept_circles(centres: np.ndarray, radius: float) -> np.ndarray:
    """(k + 1, n, 2, 2) boxes round circles of ``radius`` at ``centres`` (k + 1, n, 2), step k >= 1
    covering steps k - 1 and k (as ``ObstacleForecast.boxes``)."""
    lo, hi = centres - radius, centres + radius
    lo[1:], hi[1:] = np.minimum(lo[:-1], lo[1:]), np.maximum(hi[:-1], hi[1:])
    return np.stack([lo, hi], axis=2)


HUMAN_FORECASTS = ("model", "constant_velocity")
"""how ``PlannerController`` forecasts the pedestrians"""


class PlannerController:
    """Drives a task with a ``StatePlanner`` built for each episode's world (``run_episodes``'s
    controller): it reads the task's ``world`` and ``snapshot`` (the study's state vector, which
    ``snapshot.state_vector()`` gives in every task, and the robot's heading)."""

    def __init__(self, human_margin: float = 0.0, human_forecast: str = "model", **planner_kwargs):
        if isinstance(human_margin, bool) or not isinstance(human_margin, (int, float)) or not 0 <= human_margin <= 1:
            raise ValueError(f"human_margin must be a distance in [0, 1] m; got {human_margin!r}")
        if human_forecast not in HUMAN_FORECASTS:
            raise ValueError(f"human_forecast must be one of {', '.join(HUMAN_FORECASTS)}; got {human_forecast!r}")
        self.human_forecast = human_forecast
        """"model": where the pedestrians' own model walks them (``NavEnv.pedestrian_forecast``, the full
        state); "constant_velocity": each keeps its last step's velocity (what the egocentric state tells)"""
        self._last_humans = None
        self.human_margin = float(human_margin)
        """personal space (m) the plans keep from every pedestrian beyond the robot's clearance, where a
        plan with it exists (CrowdNav's discomfort counts a human within 0.2 m of the robot's edge)"""
        self.planner_kwargs = planner_kwargs
        self.planner: Optional[StatePlanner] = None

    def start(self, env) -> None:
        """A new episode: a new planner when the world changed, else the same one reset."""
        if self.planner is None or self.planner.world is not env.world:
            drive = env.drive_config
            self.planner = StatePlanner(env.world, forward_step=drive.forward_step, turn_step=drive.turn_step,
                                        reach_radius=env.reach_radius, **self.planner_kwargs)
        self.planner.reset()
        self._last_humans = None

    def _humans_ahead(self, env) -> np.ndarray:
        """(horizon + 1, n, 2): the pedestrians' centres over the planner's horizon (``human_forecast``)."""
        if self.human_forecast == "model":
            return env.pedestrian_forecast(self.planner.horizon)
        now = np.asarray(env.snapshot.human_xy, float).reshape(-1, 2)
        step = np.zeros_like(now) if self._last_humans is None else now - self._last_humans
        self._last_humans = now
        return now[None] + np.arange(self.planner.horizon + 1)[:, None, None] * step[None]

    def act(self, env) -> int:
        """The planner's action for the task's current snapshot (and, among pedestrians, their
        forecast: ``NavEnv.pedestrian_forecast``)."""
        s = env.snapshot
        walkers = env.world.pedestrians
        if walkers is None or not walkers.count:
            return self.planner.act(s.state_vector(), s.pose[2])
        forecast = self._humans_ahead(env)
        if self.human_margin > 0:
            action = self.planner.act(s.state_vector(), s.pose[2], forecast, walkers.radius + self.human_margin,
                                      boxed_in=None)
            if action is not None:
                return action  # else a pedestrian is already within the margin: plan round its body alone
        return self.planner.act(s.state_vector(), s.pose[2], forecast, walkers.radius)


def run_planner(task_id: str, seeds, progress: bool = False, label: Optional[str] = None, task_kwargs=None,
                **planner_kwargs) -> EpisodeResults:
    """One episode per seed of ``task_id`` (made with ``task_kwargs``) driven by a ``StatePlanner``."""
    return run_episodes(label or task_id, task_id, seeds, PlannerController(**planner_kwargs), progress=progress,
                        **(task_kwargs or {}))


@dataclass
class Args:
    task: Optional[str] = None
    """task to plan in (default: every study task); DynNav-Procedural-v1 runs its difficulties
    and splits; DynNav-Crowd-v1 and DynNav-Map-v1 take their options from --task-options"""
    difficulty: Optional[str] = None
    """with a procedural task: "easy", "medium" or "hard" (default: each)"""
    split: Optional[str] = None
    """with a procedural task: "train", "test" or "ood" (default: each)"""
    task_options: Optional[str] = None
    """with a task that is not procedural: its options as key=value,... (e.g. obstacle_count=4,obstacle_speed_scale=1.5
    for 5.3's transfer test); the --out entry is then named "<task> [<options>]" """
    episodes: int = 200
    """episodes per task (seeds first_seed .. first_seed + episodes - 1)"""
    first_seed: int = 0
    """seed of the first episode"""
    max_expansions: int = StatePlanner.max_expansions
    """search budget per step (A* nodes)"""
    tracked: int = 0
    """0: the full state; K > 0: plan seeing only the K nearest boxes at constant velocity (what a navigator
    reading the egocentric state knows); its --out entries are named state_planner_tracked<K>/..."""
    memoryless: bool = False
    """forecast the boxes from the current state alone, without the previous step's positions
    (the information an agent fed one state vector has)"""
    human_margin: float = 0.0
    """personal space (m) kept from every pedestrian where a plan with it exists; its --out entries are
    named state_planner_margin<M>/..."""
    human_forecast: str = "model"
    """the pedestrians' future: "model" (their own model, the full state) or "constant_velocity" (each
    keeps its last step's velocity, what a navigator reading the egocentric state knows); the latter's
    --out entries are named state_planner_cv..."""
    out: Optional[str] = None
    """also write each task's success, collision and timeout rates into this JSON file (merged
    with what it holds, one entry per task), e.g. docs/results/ceilings.json for agents.study.report;
    with a procedural task one entry per difficulty and split, e.g. docs/results/procedural_ceilings.json"""


def main(args: Args) -> None:
    """Run the planner over the tasks (or a procedural task's difficulties and splits) ``args`` names."""
    from dynnav_tasks import CROWD_TASK_IDS, MAP_TASK_IDS, PROCEDURAL_TASK_IDS, TASK_IDS
    from dynnav_tasks.baselines.cli import run_over_cells, run_over_tasks

    planner = dict(max_expansions=args.max_expansions, remember=not args.memoryless, tracked=args.tracked,
                   human_margin=args.human_margin, human_forecast=args.human_forecast)
    name = "state_planner" + (f"_tracked{args.tracked}" if args.tracked else "") + (
        "_cv" if args.human_forecast == "constant_velocity" else "") + (
        f"_margin{args.human_margin:g}" if args.human_margin else "")
    if args.task in PROCEDURAL_TASK_IDS:
        run_over_cells(args.task, args.difficulty, args.split, args.episodes, args.first_seed,
                       lambda d, s, seeds: run_planner(args.task, seeds, progress=True, label=f"{args.task} {d} {s}",
                                                       task_kwargs=dict(difficulty=d, split=s), **planner),
                       controller=name,
                       out=args.out)
        return
    if args.difficulty or args.split:
        raise SystemExit(f"error: --difficulty and --split apply to a procedural task ({', '.join(PROCEDURAL_TASK_IDS)})")
    options = {}
    if args.task_options is not None:
        from dynnav_tasks.task_options import parse_task_options

        if not args.task:
            raise SystemExit("error: --task-options needs --task (the options are one task's)")
        try:
            options = parse_task_options(args.task_options)
        except ValueError as err:
            raise SystemExit(f"error: {err}")
    others = CROWD_TASK_IDS + MAP_TASK_IDS  # their entries name the planner, as the other controllers' do
    run_over_tasks(args.task, TASK_IDS + others, "task id", args.episodes, args.first_seed,
                   lambda task, seeds: run_planner(task, seeds, progress=True, task_kwargs=options, **planner),
                   out=args.out, options=options, controller=name if args.task in others or name != "state_planner" else None)


if __name__ == "__main__":
    main(tyro.cli(Args))
