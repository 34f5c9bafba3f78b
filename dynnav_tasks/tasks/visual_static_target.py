from mani_skill.utils.registration import register_env

from ..motion import BackAndForth, Static
from ..nav_env import NavEnv
from ..world import Obstacles, World


@register_env("DynNav-VisualStaticTarget-v1", max_episode_steps=NavEnv.max_episode_steps)
class VisualStaticTargetEnv(NavEnv):
    """
    **Task Description:**
    Thesis world 5.5a, the first camera world: one static target and two obstacles moving
    back and forth on regular paths. Meant for ``obs_mode="rgb"`` (the thesis's camera-only
    experiment); the state vector is there too.

    * arena: x and y in [-2, 4.5] m, walls 0.5 m high, coloured by side (see ``world.py``)
    * target: (3, 3), a red disc on the floor under a red column 1.2 m tall and 0.3 m in
      radius (the success radius), visual only: the lasers do not see it. At 32x32 the camera
      sees the column as 408 pixels from 1 m, 36 from 4 m and 10 from 8 m, in every direction
      (``tests/test_camera_worlds.py``), and over the 0.5 m boxes from most of the arena
    * moving obstacles (0.5 m boxes), no faster than the robot so the camera sees them coming:
      one along y = 1 between x = 0.6 and 2.8, across the way from the start to the target
      on the robot's right; one along x = 1.5 between y = 2.3 and 3.9; both at 0.04 m per
      step
    * state (24): 16 lasers | robot x, y | target x, y | obstacle 1 x, y | obstacle 2 x, y

    **Randomizations:**
    - each obstacle's start point on its segment (uniform) and direction (either way)
    - the robot's start: x, y uniform in [-0.9, -0.4] m, heading uniform in [-45, 135] deg

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall or obstacle (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    camera_world = True
    world = World(
        target_marker=True,
        targets=(Static((3.0, 3.0)),),
        obstacles=(
            Obstacles(half_size=(0.25, 0.25), motion=BackAndForth(center=(1.7, 1.0), direction=(1, 0), amplitude=1.1, speed=0.04)),
            Obstacles(half_size=(0.25, 0.25), motion=BackAndForth(center=(1.5, 3.1), direction=(0, 1), amplitude=0.8, speed=0.04)),
        ),
    )
