from mani_skill.utils.registration import register_env

from ..motion import Route
from ..nav_env import NavEnv
from ..world import Obstacles, World
from .motion_areas import MotionAreasEnv


@register_env("DynNav-MotionAreasRoute-v1", max_episode_steps=NavEnv.max_episode_steps)
class MotionAreasRouteEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.4b: world 5.4a plus a third obstacle on a regular clockwise route whose
    upper leg runs straight through the north-east target area.

    * everything of ``DynNav-MotionAreas-v1``, plus
    * route obstacle: a 0.5 m box on the loop (2.0, 3.0) -> (4.0, 3.0) -> (4.0, 2.0) ->
      (2.0, 2.0) at one speed per episode in 0.05-0.3 m per step
    * state (26): 16 lasers | robot x, y | target x, y | obstacles 1-3 x, y

    **Randomizations:**
    - as ``DynNav-MotionAreas-v1``; and the route obstacle's speed and start along its loop

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the chosen target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    world = World(
        targets=MotionAreasEnv.world.targets,
        obstacles=MotionAreasEnv.world.obstacles + (
            Obstacles(
                half_size=(0.25, 0.25),
                motion=Route(waypoints=((2.0, 3.0), (4.0, 3.0), (4.0, 2.0), (2.0, 2.0)), speed_range=(0.05, 0.3)),
            ),
        ),
    )
