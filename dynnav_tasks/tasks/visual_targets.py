from mani_skill.utils.registration import register_env

from ..motion import BackAndForth, RandomInRect, Static
from ..nav_env import NavEnv
from ..world import CAMERA_WORLD_BOX_SPEED, Obstacles, World


@register_env("DynNav-VisualTargets-v1", max_episode_steps=NavEnv.max_episode_steps)
class VisualTargetsEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.5b: three static targets, of which only the episode's chosen one is
    visible (the others are not rendered), two obstacles wandering at random in their areas
    and a third moving back and forth on a regular path.

    * arena: x and y in [-2, 4.5] m, walls 0.5 m high, coloured by side (see ``world.py``)
    * targets (one chosen per episode): (3.4, 3.0), (3.2, -0.5), (-0.5, 3.5); the chosen one
      is a red disc under a red column 1.2 m tall (visual only, see
      ``DynNav-VisualStaticTarget-v1``), the others are not rendered, so the camera tells
      which target was chosen from anywhere in the arena
    * random obstacles (0.5 m boxes, 0.05-0.15 m per step, no faster than the robot):
      x in [0.5, 1.8], y in [1.8, 3.2];
      and x in [1.2, 2.2], y in [-1.2, 0.0]; between them a lane 1.3 m wide (y from 0.25 to
      1.55 m) leads east, out of their reach
    * regular obstacle: along x = 2.5 between y = 1.6 and 3.4 at 0.1 m per step, clear of
      the lane's east end
    * state (26): 16 lasers | robot x, y | target x, y | obstacles 1-3 x, y
      (the thesis's 34 = latent 10 + 24; ours is latent + 26 because the target's position
      is part of the state)

    **Randomizations:**
    - the chosen target; the random obstacles' start points, heading changes and step
      lengths; the regular obstacle's start point and direction
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
        targets=(Static((3.4, 3.0)), Static((3.2, -0.5)), Static((-0.5, 3.5))),
        obstacles=(
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(0.5, 1.8), y_range=(1.8, 3.2), speed_range=CAMERA_WORLD_BOX_SPEED)),
            Obstacles(half_size=(0.25, 0.25), motion=RandomInRect(x_range=(1.2, 2.2), y_range=(-1.2, 0.0), speed_range=CAMERA_WORLD_BOX_SPEED)),
            Obstacles(half_size=(0.25, 0.25), motion=BackAndForth(center=(2.5, 2.5), direction=(0, 1), amplitude=0.9, speed=0.1)),
        ),
    )
