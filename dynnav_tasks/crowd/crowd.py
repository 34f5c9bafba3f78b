"""A crowd: pedestrians with goals, moved by social force or ORCA, one control step at a time.

``Pedestrians`` declares a crowd (how many, which motion model, which scenario, their body and
speed); ``Crowd`` is its state in an episode: ``reset(rng)`` places them and gives each a goal,
``step(dt, robot)`` moves them one control step and gives a pedestrian that has arrived its next
goal. Scenarios (``SCENARIOS``), after CrowdNav (Chen et al. 2019):

``circle_crossing``
    starts on a circle of ``circle_radius`` about ``center`` at uniform angles, each moved by up
    to half the preferred speed's value in metres on each axis (CrowdNav's noise), the goal
    opposite the start; on arrival the pedestrian walks back to where it started.
``square_crossing``
    starts uniform on one side (x < 0 or x > 0 of ``center``) of a square of ``square_width``,
    the goal uniform on the other side; on arrival a new goal on the side it came from.
``corridor``
    a corridor along x of ``square_width`` by ``corridor_width``: half the crowd starts in the
    west end's last 40% walking east, half in the east end's walking west (two-way flow), each
    goal within 2 m of the far end; on arrival the goal is at the other end again.
``free_space``
    for worlds with a static layout (the procedural worlds, a building's map): starts uniform in
    the rectangle ``area``, clear of the static boxes and walls by ``spacing``; each goal a point
    of ``area`` as clear, at least ``MIN_LEG`` m away and in straight sight of the pedestrian
    (the segment clears every box by its radius), so that no pedestrian walks into a wall it
    cannot get round; on arrival the next such goal (none found in ``MAX_DRAWS`` draws: back to
    where it came from). The boxes are those the task gives ``reset`` (its walls and blocks).

With ``on_arrival="stop"`` a pedestrian that has arrived stays at its goal instead (a body at
rest the others walk round), as CrowdNav's humans do.

Every start keeps ``radius`` + ``radius`` + ``spacing`` from the others and from ``keep_clear``
points (the robot's start and target), redrawn until it does (``PlacementError`` after
``MAX_DRAWS``). A pedestrian's preferred velocity points to its goal at ``preferred_speed``,
slowed to reach it in one step when nearer; it has arrived within ``goal_radius``.

Speeds: the defaults make a pedestrian as fast as the robot's discrete drive (0.75 m/s, 0.15 m a
control step of 0.2 s), as CrowdNav's humans are as fast as its robot (1 m/s each); the models'
constants are in seconds and metres (``social_force.SocialForceParams``, ``orca``), so the
control step is the one time scale to give.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from . import orca, social_force

MODELS = ("social_force", "orca")
"""the motion models a crowd can follow"""
SCENARIOS = ("circle_crossing", "square_crossing", "corridor", "free_space")
"""where the pedestrians start and where they head (module docstring)"""
ON_ARRIVAL = ("renew", "stop")
"""what a pedestrian does at its goal: take a new one, or stay"""
MAX_DRAWS = 1000
"""draws per pedestrian before a crowd that does not fit is refused"""
MIN_LEG = 1.0
"""m: the shortest walk to a new goal in ``free_space``"""
CANDIDATES = 64
"""``free_space``: points drawn at once when looking for a start or a goal"""


class PlacementError(ValueError):
    """The crowd does not fit its scenario's area with the spacing asked for."""


@dataclass(frozen=True)
class Pedestrians:
    """A crowd of ``count`` pedestrians (module docstring)."""

    count: int
    model: str = "orca"
    """"orca" or "social_force\""""
    scenario: str = "circle_crossing"
    center: tuple[float, float] = (0.0, 0.0)
    """m: the middle of the scenario's circle, square or corridor"""
    circle_radius: float = 4.0
    """m: circle crossing's circle (CrowdNav's 4 m)"""
    square_width: float = 10.0
    """m: square crossing's square (CrowdNav's 10 m) and the corridor's length"""
    corridor_width: float = 3.0
    """m: the corridor's width"""
    area: tuple[tuple[float, float], tuple[float, float]] = ((-5.0, 5.0), (-5.0, 5.0))
    """m: free space's rectangle, ((x low, x high), (y low, y high)), e.g. the arena's"""
    radius: float = 0.3
    """m: a pedestrian's body (CrowdNav's 0.3 m)"""
    height: float = 1.7
    """m: a pedestrian's height (the camera and the lasers see the whole body)"""
    preferred_speed: float = 0.75
    """m/s: the speed a pedestrian walks at when nothing is in its way (module docstring)"""
    goal_radius: float = 0.3
    """m: a pedestrian within this of its goal has arrived"""
    spacing: float = 0.2
    """m: the least gap between two bodies at the start (CrowdNav's discomfort distance)"""
    time_horizon: float = 5.0
    """s: ORCA's horizon (CrowdNav's 5 s)"""
    on_arrival: str = "renew"
    """"renew": an arrived pedestrian takes its scenario's next goal; "stop": it stays at its goal
    (CrowdNav's humans)"""
    see_robot: bool = False
    """whether the pedestrians avoid the robot (visible) or walk as if it were not there
    (invisible, CrowdNav's harder setting, where the robot must do all the avoiding)"""
    social_force: social_force.SocialForceParams = field(default_factory=social_force.SocialForceParams)

    def __post_init__(self):
        if self.model not in MODELS:
            raise ValueError(f"pedestrian model {self.model!r} is not one of {', '.join(MODELS)}")
        if self.on_arrival not in ON_ARRIVAL:
            raise ValueError(f"pedestrians' on_arrival {self.on_arrival!r} is not one of {', '.join(ON_ARRIVAL)}")
        if self.scenario not in SCENARIOS:
            raise ValueError(f"pedestrian scenario {self.scenario!r} is not one of {', '.join(SCENARIOS)}")
        if not (isinstance(self.count, int) and self.count >= 0):
            raise ValueError(f"pedestrian count must be an integer >= 0, got {self.count!r}")
        for name in ("radius", "height", "preferred_speed", "goal_radius", "time_horizon", "circle_radius",
                     "square_width", "corridor_width"):
            if not getattr(self, name) > 0:
                raise ValueError(f"pedestrians' {name} must be > 0, got {getattr(self, name)!r}")
        (x_lo, x_hi), (y_lo, y_hi) = self.area
        if not (x_hi - x_lo > 2 * self.radius and y_hi - y_lo > 2 * self.radius):
            raise ValueError(f"pedestrians' area {self.area} must be wider than a pedestrian on both axes")


class Crowd:
    """The state of a ``Pedestrians`` crowd in one episode (module docstring)."""

    def __init__(self, spec: Pedestrians):
        self.spec = spec
        n = spec.count
        self.positions, self.velocities = np.zeros((n, 2)), np.zeros((n, 2))
        self.goals, self.starts = np.zeros((n, 2)), np.zeros((n, 2))
        self.radii = np.full(n, spec.radius)
        self.speeds = np.full(n, spec.preferred_speed)
        self._east = np.zeros(n, bool)  # square crossing and corridor: which side a pedestrian heads for
        self._boxes = np.zeros((0, 4))  # free space: the static boxes and walls (``reset``)

    # ------------------------------------------------------------------ placing
    def reset(self, rng: np.random.Generator, keep_clear=(), boxes=None) -> None:
        """Place every pedestrian and give it a goal, clear of each other and of ``keep_clear`` (x, y)
        points; ``boxes`` (k, 4: lo_x, lo_y, hi_x, hi_y), the static boxes and walls ``free_space``
        keeps clear of and sees past."""
        s, placed = self.spec, []
        self._boxes = np.zeros((0, 4)) if boxes is None else np.asarray(boxes, float).reshape(-1, 4)
        clear = [np.asarray(p, float) for p in keep_clear]
        for i in range(s.count):
            for _ in range(MAX_DRAWS):
                start, goal, east = self._draw(i, rng)
                if goal is None:
                    continue
                gap = 2 * s.radius + s.spacing
                if all(np.hypot(*(start - q)) >= gap for q in placed + clear) and \
                        all(np.hypot(*(goal - self.goals[j])) >= gap for j in range(i)):
                    break
            else:
                raise PlacementError(f"{s.count} pedestrians of radius {s.radius} m do not fit the {s.scenario} "
                                     f"scenario with {s.spacing} m between them: make it larger or the crowd smaller")
            placed.append(start)
            self.starts[i], self.positions[i], self.goals[i], self._east[i] = start, start, goal, east
        self.velocities[:] = 0.0

    def _draw(self, i: int, rng: np.random.Generator):
        s, (cx, cy) = self.spec, self.spec.center
        if s.scenario == "free_space":
            points = self._free_points(rng, CANDIDATES)
            clear = self._clear(points)
            if not clear.any():
                return None, None, False
            start = points[int(np.argmax(clear))]
            return start, self._free_goal(start, rng), False
        if s.scenario == "circle_crossing":
            angle = rng.uniform(0.0, 2.0 * math.pi)
            noise = rng.uniform(-0.5, 0.5, 2) * s.preferred_speed  # CrowdNav: (rand - 0.5) * v_pref on each axis
            start = np.array([cx + s.circle_radius * math.cos(angle), cy + s.circle_radius * math.sin(angle)]) + noise
            return start, 2.0 * np.array([cx, cy]) - start, False
        if s.scenario == "square_crossing":
            east = bool(rng.integers(2))
            half = s.square_width / 2
            side = -1.0 if east else 1.0  # start on the west to head east
            start = np.array([cx + side * rng.uniform(0.0, half), cy + rng.uniform(-half, half)])
            return start, self._square_goal(east, rng), east
        east = i % 2 == 0  # corridor: half each way
        half_l, half_w = s.square_width / 2, s.corridor_width / 2 - s.radius
        start = np.array([cx + (-half_l if east else half_l) * rng.uniform(0.6, 1.0), cy + rng.uniform(-half_w, half_w)])
        return start, self._corridor_goal(east, rng), east

    def _square_goal(self, east: bool, rng) -> np.ndarray:
        s, (cx, cy) = self.spec, self.spec.center
        half = s.square_width / 2
        return np.array([cx + (1.0 if east else -1.0) * rng.uniform(0.0, half), cy + rng.uniform(-half, half)])

    def _corridor_goal(self, east: bool, rng) -> np.ndarray:
        s, (cx, cy) = self.spec, self.spec.center
        half_w = s.corridor_width / 2 - s.radius
        along = s.square_width / 2 - rng.uniform(0.0, min(2.0, s.square_width / 4))  # within 2 m of the end
        return np.array([cx + (1.0 if east else -1.0) * along, cy + rng.uniform(-half_w, half_w)])

    def _free_points(self, rng, n: int) -> np.ndarray:
        """``n`` uniform points of ``area`` kept ``radius`` from its edges (free or not: see ``_clear``)."""
        s = self.spec
        (x_lo, x_hi), (y_lo, y_hi) = s.area
        r = s.radius
        return np.column_stack([rng.uniform(x_lo + r, x_hi - r, n), rng.uniform(y_lo + r, y_hi - r, n)])

    def _clear(self, points: np.ndarray) -> np.ndarray:
        """Which ``points`` leave a pedestrian's body ``spacing`` from every box."""
        b, gap = self._boxes, self.spec.radius + self.spec.spacing
        if not len(b):
            return np.ones(len(points), bool)
        dx = np.maximum(np.maximum(b[None, :, 0] - points[:, None, 0], points[:, None, 0] - b[None, :, 2]), 0.0)
        dy = np.maximum(np.maximum(b[None, :, 1] - points[:, None, 1], points[:, None, 1] - b[None, :, 3]), 0.0)
        return (np.hypot(dx, dy) > gap).all(axis=1)

    def _in_sight(self, origin: np.ndarray, points: np.ndarray) -> np.ndarray:
        """Which segments from ``origin`` to ``points`` miss every box grown by a pedestrian's radius
        (the slab test of a segment against an axis-aligned box)."""
        b = self._boxes
        if not len(b):
            return np.ones(len(points), bool)
        r = self.spec.radius
        lo, hi = b[:, :2] - r, b[:, 2:] + r  # (k, 2)
        d = points - origin  # (m, 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / d[:, None, :]  # (m, 1, 2)
            t1, t2 = (lo[None] - origin) * inv, (hi[None] - origin) * inv  # (m, k, 2)
        flat = d[:, None, :] == 0.0  # a segment parallel to an axis: inside that slab or not at all
        inside = (origin >= lo[None]) & (origin <= hi[None])
        t_near = np.where(flat, np.where(inside, -np.inf, np.inf), np.minimum(t1, t2)).max(axis=2)
        t_far = np.where(flat, np.where(inside, np.inf, -np.inf), np.maximum(t1, t2)).min(axis=2)
        hits = (t_near <= t_far) & (t_far >= 0.0) & (t_near <= 1.0)
        return ~hits.any(axis=1)

    def _free_goal(self, origin: np.ndarray, rng) -> Optional[np.ndarray]:
        """A ``free_space`` goal for a pedestrian at ``origin`` (module docstring), or None."""
        for _ in range(MAX_DRAWS // CANDIDATES):
            points = self._free_points(rng, CANDIDATES)
            ok = (np.hypot(*(points - origin).T) >= MIN_LEG) & self._clear(points)
            ok[ok] = self._in_sight(origin, points[ok])
            if ok.any():
                return points[int(np.argmax(ok))]
        return None

    # ------------------------------------------------------------------ moving
    def preferred_velocities(self, dt: float) -> np.ndarray:
        """Each pedestrian's preferred velocity: towards its goal at its speed, slower to stop on it."""
        delta = self.goals - self.positions
        distance = np.hypot(delta[:, 0], delta[:, 1])
        speed = np.minimum(self.speeds, distance / dt)
        return np.divide(delta * speed[:, None], distance[:, None], out=np.zeros_like(delta),
                         where=distance[:, None] > 1e-9)

    def step(self, dt: float, rng: np.random.Generator, robot: Optional[tuple] = None, boxes=None) -> np.ndarray:
        """Move every pedestrian one step of ``dt`` s and return the new positions (n, 2). ``robot``:
        ((x, y), (vx, vy), radius) of a robot the crowd sees (None: invisible to it); ``boxes``:
        static boxes and walls (k, 4) as (lo_x, lo_y, hi_x, hi_y), which the social force avoids and
        ORCA meets as resting neighbours at their nearest points (``orca.orca_velocities``)."""
        s = self.spec
        if s.count == 0:
            return self.positions
        if s.model == "social_force":
            bodies = None if robot is None else (np.array([robot[0]], float), np.array([robot[2]], float))
            a = social_force.accelerations(self.positions, self.velocities, self.radii, self.goals, self.speeds,
                                           s.social_force, bodies, boxes)
            self.velocities = social_force.step_velocities(self.velocities, a, self.speeds, dt, s.social_force)
        else:
            others = () if robot is None else ((robot[0], robot[1], robot[2], 1.0),)  # it does not do its share
            self.velocities = orca.orca_velocities(self.positions, self.velocities, self.radii,
                                                   self.preferred_velocities(dt), self.speeds, dt, s.time_horizon,
                                                   others=others, boxes=boxes)
        self.positions = self.positions + self.velocities * dt
        self._next_goals(rng)
        return self.positions

    def _next_goals(self, rng) -> None:
        s = self.spec
        if s.on_arrival == "stop":
            return
        arrived = np.hypot(*(self.goals - self.positions).T) <= s.goal_radius
        for i in np.flatnonzero(arrived):
            if s.scenario == "circle_crossing":
                self.goals[i], self.starts[i] = self.starts[i].copy(), self.goals[i].copy()
            elif s.scenario == "free_space":
                goal = self._free_goal(self.positions[i], rng)
                self.starts[i], self.goals[i] = self.positions[i].copy(), self.starts[i] if goal is None else goal
            else:
                self._east[i] = not self._east[i]
                self.goals[i] = (self._square_goal if s.scenario == "square_crossing"
                                 else self._corridor_goal)(bool(self._east[i]), rng)
