"""Whole episodes of a scripted controller, with each one's outcome, steps and SPL.

A controller here is any object with ``start(env)`` (called after every reset with the task,
``env.unwrapped``) and ``act(env)`` (the next action; it may read the task's public state:
``snapshot``, ``world``, ``obstacle_motions``), and optionally ``control_mode``, the drive its
actions are for: the discrete drive's (the default, the task's ``control_mode="discrete_drive"``)
or the velocity drive's (``"diff_drive_vel"``). ``run_episodes`` plays one episode
per seed and returns an ``EpisodeResults``; in a task with pedestrians each episode also keeps
its social metrics (``dynnav_tasks.crowd.metrics``).

SPL (success weighted by path length, Anderson et al. 2018) is the mean over episodes of
``S * l / max(p, l)``, with S 1 on success, p the metres driven and l the shortest way: the
way from the robot's start to the target's position at the reset through the static layout
(``way_grid.WayGrid`` with the robot's radius; the straight line where the grid shows it
free), less the reach radius. In a world without static boxes that is the straight line less
the reach radius, as ``agents.training.stats`` takes it. (The grid's way runs through cell
centres in eight directions, so it may be a few percent longer than the shortest; SPL is
capped at 1 per episode.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Protocol

from dynnav_tasks.baselines.way_grid import WayGrid
from dynnav_tasks.crowd.metrics import aggregate as aggregate_social
from dynnav_tasks.crowd.metrics import episode_social
from dynnav_tasks.drive import DISCRETE_DRIVE
from dynnav_tasks.outcomes import outcome_of
from dynnav_tasks.robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH

ROBOT_RADIUS = math.hypot(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)
"""metres: the circle around the robot's footprint"""


class Controller(Protocol):
    """What ``run_episodes`` drives (see the module docstring)."""

    def start(self, env) -> None:
        """Called after every reset with the task (``env.unwrapped``)."""

    def act(self, env) -> int:
        """The action to take in the task's current state."""


def control_mode_of(controller) -> str:
    """The drive ``controller`` commands (the discrete drive unless it says otherwise)."""
    return getattr(controller, "control_mode", DISCRETE_DRIVE)


@dataclass(frozen=True)
class Episode:
    """One episode's end: its outcome, steps, metres driven, shortest way (m) and SPL term."""

    seed: int
    world_seed: Optional[int]
    outcome: str
    steps: int
    path_length: float
    shortest: float
    social: Optional[dict] = None
    """in a task with pedestrians: the episode's social metrics and ``human_collision``
    (``dynnav_tasks.crowd.metrics.episode_social``)"""

    @property
    def spl(self) -> float:
        """``shortest / max(path_length, shortest)`` on success, else 0."""
        if self.outcome != "success":
            return 0.0
        return self.shortest / max(self.path_length, self.shortest, 1e-9)


@dataclass
class EpisodeResults:
    """The episodes of one controller on one task (``label`` names both in summaries)."""

    label: str
    episodes: list = field(default_factory=list)

    @property
    def outcomes(self) -> list:
        """Each episode's outcome, in seed order."""
        return [e.outcome for e in self.episodes]

    def rate(self, outcome: str = "success") -> float:
        """Share of the episodes that ended in ``outcome``."""
        return self.outcomes.count(outcome) / len(self.episodes)

    def spl(self) -> float:
        """Mean SPL over the episodes (see the module docstring)."""
        return sum(e.spl for e in self.episodes) / len(self.episodes)

    def numbers(self) -> dict:
        """The extra numbers a results file keeps beside the rates: SPL, steps per success and
        how many different worlds the episodes played."""
        steps = [e.steps for e in self.episodes if e.outcome == "success"]
        worlds = {e.world_seed for e in self.episodes if e.world_seed is not None}
        numbers = dict(spl=round(self.spl(), 4), steps_per_success=round(sum(steps) / len(steps), 1) if steps else None,
                       worlds=len(worlds) or None)
        social = self.social()
        return numbers if social is None else dict(numbers, social=social)

    def social(self) -> Optional[dict]:
        """The social metrics over the episodes (``dynnav_tasks.crowd.metrics.aggregate``); None
        in a task without pedestrians."""
        if not self.episodes or self.episodes[0].social is None:
            return None
        return aggregate_social([dict(e.social, steps=e.steps) for e in self.episodes])

    def summary(self) -> str:
        """One line: success, collision and timeout rates, SPL and the episode count."""
        social = self.social()
        crowd = "" if social is None else (f", human collision {social['human_collision_rate']:.1%}, "
                                           f"discomfort {social['discomfort_frequency']:.3f}")
        return (f"{self.label}: success {self.rate():.1%}, collision {self.rate('collision'):.1%}, "
                f"timeout {self.rate('timeout'):.1%}, SPL {self.spl():.3f}{crowd} over {len(self.episodes)} episodes")


def shortest_way(env) -> float:
    """The shortest way (m) the robot must drive from where it is to reach the current target
    (see the module docstring)."""
    s = env.snapshot
    grid, start, target = WayGrid(env.world, ROBOT_RADIUS), s.pose[:2], tuple(s.target_xy.tolist())
    straight = math.hypot(target[0] - start[0], target[1] - start[1])
    way = straight if grid.line_free(start, target) else max(grid.to(target).distance(*start), straight)
    return max(way - env.reach_radius, 0.0)


def run_episodes(label: str, task_id: str, seeds, controller: Controller, progress: bool = False,
                 options: Optional[dict] = None, **task_kwargs) -> EpisodeResults:
    """One episode per seed of ``task_id`` (made with ``task_kwargs``) driven by ``controller``;
    ``options`` go to every reset (e.g. ``{"world": w}`` for a procedural task)."""
    from dynnav_tasks import NumpyWrapper, make

    mode, given = control_mode_of(controller), task_kwargs.get("control_mode", DISCRETE_DRIVE)
    if given != mode:
        what = "chooses among the three discrete actions" if mode == DISCRETE_DRIVE else "commands velocities"
        raise ValueError(f"{label}'s controller {what}: make the task with control_mode={mode!r}, not {given!r}")
    env = NumpyWrapper(make(task_id, obs_mode="state", **task_kwargs))
    base = env.unwrapped
    seeds = [int(s) for s in seeds]
    if progress:
        from tqdm import tqdm

        seeds = tqdm(seeds, desc=label, unit="episode")
    results = EpisodeResults(label)
    try:
        for seed in seeds:
            env.reset(seed=seed, options=options)
            controller.start(base)
            shortest, done = shortest_way(base), False
            while not done:
                _, _, terminated, truncated, info = env.step(controller.act(base))
                done = terminated or truncated
            results.episodes.append(Episode(seed, getattr(base, "world_seed", None), outcome_of(info, terminated),
                                            int(info["elapsed_steps"]), float(info["path_length"]), shortest,
                                            episode_social(info)))
    finally:
        env.close()
    return results
