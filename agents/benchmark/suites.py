"""The suites a policy is scored on: fixed tasks, seeds and episode counts.

==============  =============================================================================
``study``       the study's nine worlds (``dynnav_tasks.TASK_IDS``), 100 episodes each from
                seed 1,000,000: the test episodes of every run of the study
``procedural``  ``DynNav-Procedural-v1``'s held-out test and ood worlds of each difficulty,
                100 episodes each from seed 1,000,000 (the test phase's seeds)
``crowd``       ``DynNav-Crowd-v1``: 5 pedestrians crossing a circle of radius 4 m, blind to
                the robot, stopping at their goals (CrowdNav's setting), 500 episodes
==============  =============================================================================

A single task with options (``--task``, ``--options``) is a suite of one cell, 100 episodes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from dynnav_tasks.task_options import options_name

FIRST_SEED = 1_000_000
"""the first episode's seed of every suite: the test phase's (no training episode uses it)"""
EPISODES = 100
"""episodes of a cell unless its suite says otherwise"""
CROWD = dict(scenario="circle_crossing", humans=5, on_arrival="stop")
DRIVE = "control_mode"
"""the option that chooses the drive: the navigator's, not the cell's (``Cell.task_name``)"""


@dataclass(frozen=True)
class Cell:
    """One task with options, played for ``episodes`` episodes from seed ``first_seed``."""

    task: str
    options: dict = field(default_factory=dict)
    episodes: int = EPISODES
    first_seed: int = FIRST_SEED

    @property
    def name(self) -> str:
        """``task`` or ``task [key=value,...]``."""
        return f"{self.task} [{options_name(self.options)}]" if self.options else self.task

    @property
    def task_name(self) -> str:
        """``name`` without the drive option: what the references are measured on (each on its own drive) and
        the leaderboard's column, shared by navigators on either drive."""
        return Cell(self.task, {k: v for k, v in self.options.items() if k != DRIVE}).name

    @property
    def seeds(self) -> range:
        return range(self.first_seed, self.first_seed + self.episodes)


def suite_cells(suite: str) -> list[Cell]:
    """The cells of a named suite; ValueError naming the suites for another name."""
    import dynnav_tasks
    from dynnav_tasks.generation import DIFFICULTIES

    suites = {
        "study": lambda: [Cell(t) for t in dynnav_tasks.TASK_IDS],
        "procedural": lambda: [Cell("DynNav-Procedural-v1", dict(difficulty=d, split=s))
                               for d in DIFFICULTIES for s in ("test", "ood")],
        "crowd": lambda: [Cell("DynNav-Crowd-v1", dict(CROWD), episodes=500)],
    }
    if suite not in suites:
        raise ValueError(f"unknown suite {suite!r}; the suites are {', '.join(suites)}, or give --task for one task")
    return suites[suite]()


SUITES = ("study", "procedural", "crowd")
