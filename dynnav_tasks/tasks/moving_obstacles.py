import numbers
from dataclasses import replace

from mani_skill.utils.registration import register_env

from ..motion import Route, Static
from ..nav_env import NavEnv
from ..world import Obstacles, World

MAX_OBSTACLE_COUNT = 8
"""boxes the loop holds at most with room between them (its length is 12.8 m)"""


@register_env("DynNav-MovingObstacles-v1", max_episode_steps=NavEnv.max_episode_steps)
class MovingObstaclesEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.3: two obstacles circle clockwise on a rectangular route that lies across
    every way from the robot's start to the two static targets. The robot must cross the
    route between the obstacles and reach the chosen target.

    * arena: x and y in [-2, 4.5] m, walls 0.5 m high, coloured by side
    * targets (one chosen per episode): (3, 3) and (3, 1), static
    * moving obstacles: two 0.5 m x 0.5 m boxes on the clockwise loop
      (0.6, 3.8) -> (2.0, 3.8) -> (2.0, -1.2) -> (0.6, -1.2), half a loop (6.4 m) apart,
      at one speed per episode drawn uniformly from 0.05-0.5 m per step
    * state (24): 16 lasers | robot x, y | target x, y | obstacle 1 x, y | obstacle 2 x, y
      (the thesis's size 24: lasers and the positions of the robot and the obstacles, plus
      the target's position, without which the robot could not tell the two targets apart)

    A harder world 5.3 for the transfer question (a navigator trained in 5.3 tested with more
    and faster obstacles), set by two options:

    * ``obstacle_count`` (default 2, up to 8): boxes on the loop, evenly spaced (not fewer than
      the state's two obstacle places)
    * ``obstacle_speed_scale`` (default 1, up to 4): multiplies the speed range
    * the state keeps its 24 values: its two obstacle places hold the two boxes nearest to the
      robot, in the loop's order (with 2 boxes, both, as in 5.3); the lasers see every box

    **Randomizations:**
    - the chosen target (uniform over the two)
    - the obstacles' speed (uniform in [0.05, 0.5] m per step) and their common position
      along the loop (uniform)
    - the robot's start: x, y uniform in [-0.9, -0.4] m, heading uniform in [-45, 135] deg

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the chosen target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    world = World(
        targets=(Static((3.0, 3.0)), Static((3.0, 1.0))),
        obstacles=(
            Obstacles(
                half_size=(0.25, 0.25),
                motion=Route(
                    waypoints=((0.6, 3.8), (2.0, 3.8), (2.0, -1.2), (0.6, -1.2)),
                    speed_range=(0.05, 0.5),
                    count=2,
                ),
            ),
        ),
    )

    state_obstacle_slots = 2

    def __init__(self, *args, obstacle_count: int = 2, obstacle_speed_scale: float = 1.0, **kwargs):
        if isinstance(obstacle_count, bool) or not isinstance(obstacle_count, numbers.Integral) or not (
            self.state_obstacle_slots <= obstacle_count <= MAX_OBSTACLE_COUNT
        ):
            raise ValueError(f"obstacle_count must be an integer from {self.state_obstacle_slots} (the state's "
                             f"obstacle places) to {MAX_OBSTACLE_COUNT} (boxes on the loop); got {obstacle_count!r}")
        if isinstance(obstacle_speed_scale, bool) or not isinstance(obstacle_speed_scale, numbers.Real) or not (
            0 < obstacle_speed_scale <= 4
        ):
            raise ValueError(f"obstacle_speed_scale must be a number in (0, 4] (it multiplies the speed range "
                             f"0.05-0.5 m per step); got {obstacle_speed_scale!r}")
        self.world = world_with(obstacle_count, obstacle_speed_scale)
        super().__init__(*args, **kwargs)


def world_with(obstacle_count: int = 2, obstacle_speed_scale: float = 1.0) -> World:
    """World 5.3 with ``obstacle_count`` boxes on its loop at ``obstacle_speed_scale`` times its speeds
    (the options' defaults: the world itself)."""
    world = MovingObstaclesEnv.world
    if (obstacle_count, obstacle_speed_scale) == (2, 1.0):
        return world
    (group,) = world.obstacles
    low, high = group.motion.speed_range
    motion = replace(group.motion, count=int(obstacle_count),
                     speed_range=(low * obstacle_speed_scale, high * obstacle_speed_scale))
    return replace(world, obstacles=(replace(group, motion=motion),))
