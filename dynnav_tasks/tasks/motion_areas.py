from mani_skill.utils.registration import register_env

from ..motion import RandomInRect
from ..nav_env import NavEnv
from ..world import Obstacles, World

# Shared by the three worlds of thesis Fig. 5.4: where the targets wander (red areas).
TARGET_SPEED = (0.02, 0.08)
TARGET_AREAS = (
    RandomInRect(x_range=(2.5, 3.5), y_range=(2.5, 3.5), speed_range=TARGET_SPEED, start=(3.0, 3.0)),
    RandomInRect(x_range=(2.5, 3.5), y_range=(-1.0, 0.0), speed_range=TARGET_SPEED, start=(3.0, -0.5)),
)
OBSTACLE_SPEED = (0.05, 0.5)


@register_env("DynNav-MotionAreas-v1", max_episode_steps=NavEnv.max_episode_steps)
class MotionAreasEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.4a: the target wanders at random inside its red area and two obstacles
    wander at random inside their blue areas. No blue area overlaps a red one.

    * arena: x and y in [-2, 4.5] m, walls 0.5 m high, coloured by side
    * target areas (one target chosen per episode, starting at the area's centre, moving
      0.02-0.08 m per step): x in [2.5, 3.5] with y in [2.5, 3.5], and with y in [-1, 0]
    * obstacle areas (0.5 m boxes, 0.05-0.5 m per step, a new speed every step; the box's
      centre stays in its area): x in [0.5, 1.5], y in [1.7, 3.0]; and x in [0.5, 1.8],
      y in [-1.5, -0.1]. Between the two a lane 1.3 m wide (y from 0.15 to 1.45 m) leads
      from the start to both target areas out of the obstacles' reach: the obstacles move up
      to 0.5 m per step, faster than the robot, so a route through their areas is a gamble
    * state (24): 16 lasers | robot x, y | target x, y | obstacle 1 x, y | obstacle 2 x, y

    **Randomizations:**
    - the chosen target; every target and obstacle step's heading change (up to +-45 deg)
      and length; the obstacles' start points (uniform in their areas)
    - the robot's start: x, y uniform in [-0.9, -0.4] m, heading uniform in [-45, 135] deg

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the chosen target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    world = World(
        targets=TARGET_AREAS,
        obstacles=(
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(0.5, 1.5), y_range=(1.7, 3.0), speed_range=OBSTACLE_SPEED)),
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(0.5, 1.8), y_range=(-1.5, -0.1), speed_range=OBSTACLE_SPEED)),
        ),
    )
