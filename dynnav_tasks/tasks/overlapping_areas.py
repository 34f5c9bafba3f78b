from mani_skill.utils.registration import register_env

from ..motion import RandomInRect
from ..nav_env import NavEnv
from ..world import Obstacles, World
from .motion_areas import OBSTACLE_SPEED, TARGET_AREAS


@register_env("DynNav-OverlappingAreas-v1", max_episode_steps=NavEnv.max_episode_steps)
class OverlappingAreasEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.4c: as 5.4a, but each obstacle's area partly overlaps a target area, so
    an obstacle can wander onto the target while the robot drives there (the world where
    the thesis's agent failed).

    * arena and target areas as ``DynNav-MotionAreas-v1``
    * obstacle areas (0.5 m boxes, 0.05-0.5 m per step): x in [1.5, 3.0], y in [2.0, 3.2]
      (overlaps the north-east target area in x [2.5, 3.0], y [2.5, 3.2]); and x in
      [1.5, 3.0], y in [-1.5, -0.4] (overlaps the south-east one in x [2.5, 3.0], y [-1, -0.4])
    * state (24): 16 lasers | robot x, y | target x, y | obstacle 1 x, y | obstacle 2 x, y

    **Randomizations:**
    - as ``DynNav-MotionAreas-v1``

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the chosen target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    world = World(
        targets=TARGET_AREAS,
        obstacles=(
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(1.5, 3.0), y_range=(2.0, 3.2), speed_range=OBSTACLE_SPEED)),
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(1.5, 3.0), y_range=(-1.5, -0.4), speed_range=OBSTACLE_SPEED)),
        ),
    )
