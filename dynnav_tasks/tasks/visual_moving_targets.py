from mani_skill.utils.registration import register_env

from ..motion import RandomInRect
from ..nav_env import NavEnv
from ..world import CAMERA_WORLD_BOX_SPEED, Obstacles, World


@register_env("DynNav-VisualMovingTargets-v1", max_episode_steps=NavEnv.max_episode_steps)
class VisualMovingTargetsEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.5c: two targets wander at random in their areas (only the chosen one is
    visible) and two obstacles wander at random in theirs. Meant for stacked grayscale
    camera frames (``dynnav_tasks.wrappers.GrayFrameStack``), which show motion.

    * arena: x and y in [-2, 4.5] m, walls 0.5 m high, coloured by side (see ``world.py``)
    * target areas (one chosen per episode, starting at (3.3, 3.2) or (3.3, -0.6), moving
      0.05-0.1 m per step): x in [2.8, 3.8] with y in [2.6, 3.8], and with y in [-1.2, 0.0].
      The chosen target is a red disc under a red column 1.2 m tall (visual only, see
      ``DynNav-VisualStaticTarget-v1``); the other is not rendered. In gray (the frame
      stack) the column is the darkest thing but the sky, 40+ levels from everything else
    * obstacle areas (0.5 m boxes, 0.05-0.15 m per step, no faster than the robot): x in
      [0.6, 2.0] with y in [1.8, 3.4], and with y in [-1.5, 0.0]; between them a lane 1.3 m
      wide (y from 0.25 to 1.55 m) leads from the start to both target areas out of the
      obstacles' reach
    * state (24): 16 lasers | robot x, y | target x, y | obstacle 1 x, y | obstacle 2 x, y

    **Randomizations:**
    - the chosen target; every target and obstacle step's heading change and length; the
      obstacles' start points (uniform in their areas)
    - the robot's start: x, y uniform in [-0.9, -0.4] m, heading uniform in [-45, 135] deg

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the chosen target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    camera_world = True
    world = World(
        target_marker=True,
        targets=(
            RandomInRect(x_range=(2.8, 3.8), y_range=(2.6, 3.8), speed_range=(0.05, 0.1), start=(3.3, 3.2)),
            RandomInRect(x_range=(2.8, 3.8), y_range=(-1.2, 0.0), speed_range=(0.05, 0.1), start=(3.3, -0.6)),
        ),
        obstacles=(
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(0.6, 2.0), y_range=(1.8, 3.4), speed_range=CAMERA_WORLD_BOX_SPEED)),
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(0.6, 2.0), y_range=(-1.5, 0.0), speed_range=CAMERA_WORLD_BOX_SPEED)),
        ),
    )
