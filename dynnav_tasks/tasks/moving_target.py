from mani_skill.utils.registration import register_env

from ..motion import BackAndForth, Static
from ..nav_env import NavEnv
from ..world import Obstacles, World


@register_env("DynNav-MovingTarget-v1", max_episode_steps=NavEnv.max_episode_steps)
class MovingTargetEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.2: three targets move back and forth among static obstacles. The robot
    starts in the south-west of a 6.5 m x 6.5 m arena and must drive to the one target
    chosen for the episode without touching a wall or an obstacle.

    * arena: x and y in [-2, 4.5] m, walls 0.5 m high, coloured by side
    * targets (one chosen per episode), each sliding +-0.5 m at 0.05 m per step:
      (-0.5, 3) along y, (3, 3) along y, (3, -0.5) along x
    * static obstacles: three 0.5 m x 0.5 m boxes at (-0.8, 1.2), (1.1, 1.1), (1.2, -0.8),
      one on the straight line to each target
    * state (20): 16 lasers | robot x, y | target x, y

    **Randomizations:**
    - the chosen target (uniform over the three)
    - each target's start point on its segment (uniform) and direction (either way)
    - the robot's start: x, y uniform in [-0.9, -0.4] m, heading uniform in [-45, 135] deg

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the chosen target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    world = World(
        targets=(
            BackAndForth(center=(-0.5, 3.0), direction=(0, 1), amplitude=0.5, speed=0.05),
            BackAndForth(center=(3.0, 3.0), direction=(0, 1), amplitude=0.5, speed=0.05),
            BackAndForth(center=(3.0, -0.5), direction=(1, 0), amplitude=0.5, speed=0.05),
        ),
        obstacles=(
            Obstacles(half_size=(0.25, 0.25), motion=Static((-0.8, 1.2))),
            Obstacles(half_size=(0.25, 0.25), motion=Static((1.1, 1.1))),
            Obstacles(half_size=(0.25, 0.25), motion=Static((1.2, -0.8))),
        ),
    )
