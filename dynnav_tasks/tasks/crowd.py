import numbers

import numpy as np
from mani_skill.utils.registration import register_env

from ..crowd.crowd import MODELS, ON_ARRIVAL, Pedestrians
from ..errors import check_choice
from ..motion import Static
from ..nav_env import NavEnv
from ..world import Arena, StartArea, World
from .egocentric_task import EgocentricTask

SCENARIOS = ("circle_crossing", "square_crossing", "corridor")
"""the task's scenarios (``crowd.crowd.SCENARIOS`` less ``free_space``, which needs a static layout)"""
MAX_HUMANS = 20
"""the most pedestrians a crowd task holds"""
DEFAULT_HUMAN_K = 5
"""pedestrian slots in the state unless ``human_k`` says otherwise"""


def crowd_world(scenario: str = "circle_crossing", humans: int = 5, model: str = "orca",
                see_robot: bool = False, on_arrival: str = "renew") -> World:
    """The world of ``DynNav-Crowd-v1`` with these options (the task's docstring gives the geometry)."""
    check_choice(scenario, SCENARIOS, "scenario")
    check_choice(model, MODELS, "model")
    check_choice(on_arrival, ON_ARRIVAL, "on_arrival")
    if isinstance(humans, bool) or not isinstance(humans, numbers.Integral) or not 0 <= humans <= MAX_HUMANS:
        raise ValueError(f"humans must be an integer from 0 to {MAX_HUMANS}; got {humans!r}")
    if scenario == "corridor":
        return World(targets=(Static((5.0, 0.0)),), arena=Arena((-6.0, 6.0), (-1.5, 1.5)),
                     start=StartArea((-5.1, -4.9), (-0.1, 0.1), (-0.1, 0.1)),
                     pedestrians=Pedestrians(int(humans), model, scenario, square_width=12.0, corridor_width=3.0,
                                             see_robot=bool(see_robot), on_arrival=on_arrival))
    radius = 4.0 if humans <= 10 else 5.0  # a circle that keeps 20 pedestrians 0.2 m apart at the start
    side = 6.0 if scenario == "square_crossing" or humans <= 10 else 6.5
    return World(targets=(Static((0.0, 4.0)),), arena=Arena((-side, side), (-side, side)),
                 start=StartArea((-0.1, 0.1), (-4.1, -3.9), (np.pi / 2 - 0.1, np.pi / 2 + 0.1)),
                 pedestrians=Pedestrians(int(humans), model, scenario, circle_radius=radius, square_width=10.0,
                                         see_robot=bool(see_robot), on_arrival=on_arrival))


@register_env("DynNav-Crowd-v1", max_episode_steps=NavEnv.max_episode_steps)
class CrowdEnv(EgocentricTask, NavEnv):
    """
    **Task Description:**
    Cross a crowd of pedestrians to a static target, in CrowdNav's scenarios (Chen et al. 2019)
    or a corridor with two-way flow. Pedestrians are upright cylinders (radius 0.3 m, 1.7 m tall)
    that the lasers and the camera see, each walking to a goal at 0.75 m/s (the robot's
    discrete speed) and taking a new one on arrival, moved by ORCA or the social force
    (``dynnav_tasks.crowd``).

    * ``scenario="circle_crossing"`` (default): pedestrians start on a circle of radius 4 m
      (5 m beyond 10 of them) and cross to the opposite side; the robot starts at (0, -4)
      facing north, the target is (0, 4): CrowdNav's set-up. Arena 12 m x 12 m (13 m beyond 10).
    * ``scenario="square_crossing"``: pedestrians cross a 10 m square from side to side.
    * ``scenario="corridor"``: a 12 m x 3 m corridor; half the crowd walks east, half west; the
      robot drives from (-5, 0) to (5, 0).
    * options: ``humans`` (0-20, default 5), ``model`` ("orca" or "social_force"),
      ``see_robot`` (default False: the pedestrians do not see the robot, CrowdNav's invisible
      setting), ``on_arrival`` ("renew", default: an arrived pedestrian takes a new goal; "stop":
      it stays at its goal, as CrowdNav's humans do), ``human_k`` (pedestrian slots in the state,
      default 5), ``odometry`` (default False: with True the state holds the robot's own move over
      the last step, after the target)
    * state (``obs_mode="state"``): the egocentric state (``egocentric.py``): the lasers | target
      distance, sin and cos of its bearing | for each of the ``human_k`` nearest pedestrians its
      x, y, vx, vy relative to the robot in the robot's frame and its radius; 19 + 5 ``human_k``
      values with 16 rays
    * both control modes: the discrete drive and ``control_mode="diff_drive_vel"``

    **Randomizations:**
    - the pedestrians' starts and goals (the scenario's draws, 0.2 m apart or more and clear of
      the robot's start and the target), and each new goal
    - the robot's start: within 0.1 m of its point, heading within 0.1 rad of the target

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the target's centre

    **Failure Conditions:**
    - a contact with a pedestrian (``info["human_collision"]``) or a wall
    - 200 steps without success is a truncation (timeout), not a failure
    """

    world = crowd_world()

    def __init__(self, *args, scenario: str = "circle_crossing", humans: int = 5, model: str = "orca",
                 see_robot: bool = False, on_arrival: str = "renew", human_k: int = DEFAULT_HUMAN_K, odometry: bool = False,
                 **kwargs):
        self.set_egocentric_options(human_k=human_k, odometry=odometry)
        if not isinstance(see_robot, bool):
            raise ValueError(f"see_robot must be True or False; got {see_robot!r}")
        self.world = crowd_world(scenario, humans, model, see_robot, on_arrival)
        super().__init__(*args, **kwargs)
