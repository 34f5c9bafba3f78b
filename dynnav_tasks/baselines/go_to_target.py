"""A floor: turn towards the target and drive, blind to every wall and obstacle.

    python -m dynnav_tasks.baselines.go_to_target --task DynNav-Procedural-v1 --difficulty easy --split test

``GoToTarget`` reads the target's bearing from the task's snapshot: while the target lies more
than half a turn step to one side it turns that way (LEFT or RIGHT), else it drives FORWARD.
It never avoids anything, so its success rate is what a navigator gets from the target's
direction alone: the share of episodes in which the straight way is free for long enough.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import tyro

from dynnav_tasks.baselines.cli import ControllerArgs, drive_controller
from dynnav_tasks.baselines.episodes import EpisodeResults, run_episodes

FORWARD, LEFT, RIGHT = 0, 1, 2


class GoToTarget:
    """Turn towards the target, then drive (a ``run_episodes`` controller)."""

    def __init__(self):
        self.turn_step = 0.0

    def start(self, env) -> None:
        """A new episode: read the task's turn step (rad)."""
        self.turn_step = env.drive_config.turn_step

    def act(self, env) -> int:
        """LEFT or RIGHT while the target's bearing exceeds half a turn step, else FORWARD."""
        bearing = env.snapshot.bearing
        if abs(bearing) <= self.turn_step / 2:
            return FORWARD
        return LEFT if bearing > 0 else RIGHT


def run_go_to_target(task_id: str, seeds, progress: bool = False, label: Optional[str] = None,
                     task_kwargs=None) -> EpisodeResults:
    """One episode per seed of ``task_id`` (made with ``task_kwargs``) driven by ``GoToTarget``."""
    return run_episodes(label or task_id, task_id, seeds, GoToTarget(), progress=progress, **(task_kwargs or {}))


@dataclass
class Args(ControllerArgs):
    task: str = "DynNav-Procedural-v1"
    """task to drive in: a study task or a procedural one (which runs its difficulties and splits)"""


def main(args: Args) -> None:
    """Drive the episodes ``args`` names and print (and with ``--out`` record) the rates."""
    from dynnav_tasks import TASK_IDS

    drive_controller(args, lambda task, seeds, label, kwargs: run_go_to_target(task, seeds, progress=True, label=label,
                                                                 task_kwargs=kwargs),
                     "go_to_target", TASK_IDS)


if __name__ == "__main__":
    main(tyro.cli(Args))
