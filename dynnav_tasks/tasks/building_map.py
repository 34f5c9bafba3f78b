"""DynNav-Map-v1: a building's occupancy map (ROS ``map_server`` format) as the world."""

from pathlib import Path
from typing import Optional, Sequence

from mani_skill.utils.registration import register_env

from ..map_world import TARGET_DISTANCE, world_from_map
from ..nav_env import NavEnv
from .egocentric_task import EgocentricTask
from .procedural import DEFAULT_OBSTACLE_K

OFFICE_MAP = str(Path(__file__).resolve().parents[2] / "assets" / "maps" / "office.yaml")
"""the office floor shipped with dynnav (16 m x 10 m: a corridor, seven rooms; ``scripts/draw_office_map.py``)"""


@register_env("DynNav-Map-v1", max_episode_steps=NavEnv.max_episode_steps)
class MapEnv(EgocentricTask, NavEnv):
    """
    **Task Description:**
    Drive to a target through a building, read from its occupancy map: a ROS ``map_server`` YAML
    file and its PGM or PNG (``map``; default the shipped office floor, ``OFFICE_MAP``). The
    map's occupied and unknown cells become static boxes 0.5 m high; the world is built once,
    when the task is made (``World.from_occupancy_map``, ``map_world.py``):

    * ``start`` (x, y): where the robot starts (within 0.1 m, any heading); default: drawn with
      ``map_seed`` where the robot has 0.495 m clear around it
    * ``target`` (x, y): the one target; default: ``targets`` (8) targets drawn with ``map_seed``
      among the places whose way from the start through the map is ``target_distance`` (2-20 m)
      long, one of them per episode
    * ``moving_obstacles`` (0-30): 0.5 m boxes moving in the map's free space on the generator's
      motion models; ``pedestrians`` (0-20): walkers in its free space (``pedestrian_model``
      "orca" or "social_force"), blind to the robot
    * state (``obs_mode="state"``): the procedural task's egocentric state: the lasers | target
      distance, sin and cos of its bearing | with ``way=True`` the way to the target through the
      map (length, sin and cos of the bearing of the point 0.5 m along it) | with ``odometry=True``
      the robot's own last move | the ``obstacle_k``
      (default 4) nearest moving boxes | the ``human_k`` (default 0) nearest pedestrians; so a
      navigator of ``DynNav-Procedural-v1`` plays a building with the same options
    * both control modes: the discrete drive and ``control_mode="diff_drive_vel"``

    **Randomizations:**
    - which of the targets (when drawn), the robot's heading and its start within the start area
    - the boxes' and the pedestrians' motions

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the target's centre

    **Failure Conditions:**
    - any contact between the robot and a wall, box or pedestrian (``info["human_collision"]``)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    def __init__(self, *args, map: str = OFFICE_MAP, start: Optional[Sequence[float]] = None,
                 target: Optional[Sequence[float]] = None, targets: int = 8, map_seed: int = 0,
                 target_distance: Sequence[float] = TARGET_DISTANCE, moving_obstacles: int = 0, pedestrians: int = 0,
                 pedestrian_model: str = "orca", obstacle_k: int = DEFAULT_OBSTACLE_K, way: bool = False,
                 human_k: int = 0, odometry: bool = False, **kwargs):
        self.set_egocentric_options(obstacle_k, way, human_k, odometry)
        self.map_path = str(map)
        """the occupancy map's YAML file"""
        self.world = world_from_map(self.map_path, start, target, targets=targets, seed=map_seed,
                                    moving_obstacles=moving_obstacles, pedestrians=pedestrians,
                                    pedestrian_model=pedestrian_model, target_distance=tuple(target_distance))
        super().__init__(*args, **kwargs)
