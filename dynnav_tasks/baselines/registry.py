"""The scripted controllers by name, for tools that pick one from a string (``dynnav-benchmark
--policy controller:NAME``).

======================  =========================================================================
``planner``             the full-state planner (``state_planner.PlannerController``), discrete drive
``go_to_target``        turn to the target, then drive (``go_to_target.GoToTarget``), discrete drive
``dwa``                 the dynamic window approach on the laser scan (``dwa.DWA``), continuous drive
``orca_robot``          the robot walking as an ORCA pedestrian (``crowd_robot.CrowdRobot``),
                        continuous drive
``social_force_robot``  the same with the social force
======================  =========================================================================

Each is a ``run_episodes`` controller (``episodes.Controller``): ``start(env)`` after every
reset, ``act(env)`` reading the task's public state, and ``control_mode``, the drive it commands
(``episodes.control_mode_of``).
"""

from __future__ import annotations

from typing import Callable


def _planner():
    from dynnav_tasks.baselines.state_planner import PlannerController

    return PlannerController()


def _go_to_target():
    from dynnav_tasks.baselines.go_to_target import GoToTarget

    return GoToTarget()


def _dwa():
    from dynnav_tasks.baselines.dwa import DWA

    return DWA()


def _crowd_robot(model: str) -> Callable:
    def make():
        from dynnav_tasks.baselines.crowd_robot import CrowdRobot

        return CrowdRobot(model)

    return make


CONTROLLERS: dict[str, Callable] = {"planner": _planner, "go_to_target": _go_to_target, "dwa": _dwa,
                                    "orca_robot": _crowd_robot("orca"),
                                    "social_force_robot": _crowd_robot("social_force")}
"""name -> a function making a fresh controller (see the module docstring)"""


def make_controller(name: str):
    """A fresh controller named ``name``; ValueError naming the controllers for another name."""
    if name not in CONTROLLERS:
        raise ValueError(f"no scripted controller {name!r}; the controllers: {', '.join(CONTROLLERS)}")
    return CONTROLLERS[name]()
