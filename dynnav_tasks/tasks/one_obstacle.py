from mani_skill.utils.registration import register_env

from ..motion import BackAndForth, Static
from ..nav_env import NavEnv
from ..world import Obstacles, World


@register_env("DynNav-OneObstacle-v1", max_episode_steps=NavEnv.max_episode_steps)
class OneObstacleEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.1, the basic set-up: one obstacle slides back and forth across the way
    from the robot's start to a single static target.

    * arena: x and y in [-2, 4.5] m, walls 0.5 m high, coloured by side
    * target: (3, 3), static
    * moving obstacle: a 0.5 m box sliding along the diagonal x + y = 2.4 between
      (0.35, 2.05) and (2.05, 0.35) (centre (1.2, 1.2), +-1.2 m) at 0.1 m per step
    * state (22): 16 lasers | robot x, y | target x, y | obstacle x, y

    **Randomizations:**
    - the obstacle's start point on its segment (uniform) and direction (either way)
    - the robot's start: x, y uniform in [-0.9, -0.4] m, heading uniform in [-45, 135] deg

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or the obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    world = World(
        targets=(Static((3.0, 3.0)),),
        obstacles=(
            Obstacles(half_size=(0.25, 0.25), motion=BackAndForth(center=(1.2, 1.2), direction=(1, -1), amplitude=1.2, speed=0.1)),
        ),
    )
