"""DynNav-Procedural-v1: a generated world every episode, with train, test and ood splits."""

import math
import numbers
from dataclasses import replace
from typing import Optional

import numpy as np
import sapien
from mani_skill.sensors.camera import CameraConfig
from mani_skill.utils import sapien_utils
from mani_skill.utils.registration import register_env

from .. import generation
from ..generation.spec import ARENA_SIDE_RANGE
from ..errors import check_choice
from ..nav_env import NavEnv
from ..observations import OBS_MODES
from ..scene import BuiltWorld
from ..scene_pool import PoolSizes, ScenePool
from ..world import World
from . import moving_obstacles
from .egocentric_task import EgocentricTask

DEFAULT_OBSTACLE_K = 4
"""moving obstacles in the egocentric state unless ``obstacle_k`` says otherwise"""
MAX_ARENA_SIDE = ARENA_SIDE_RANGE[1]
"""metres: the longest arena side of any generated world (the scene's walls and floor cover it)"""
TOP_DOWN_MARGIN = 0.3
"""metres of floor beyond the walls in the top-down picture (as ``viz.top_down``)"""
WORLD_SEED_DRAW = 2**31
"""train and ood world seeds (train: the index k of ``train_world_seed``) are drawn below this"""
MIXED = "mixed"
"""the train split's ``difficulty`` that draws each world's difficulty, evenly, from the three"""
STUDY_WORLDS = {"5.3": dict(obstacle_count=2, obstacle_speed_scale=1.0),
                "5.3-transfer": dict(obstacle_count=4, obstacle_speed_scale=1.5)}
"""``study_world``'s choices: world 5.3 (``DynNav-MovingObstacles-v1``) and its transfer test's
version (twice the boxes at 1.5 times their speed), each with the options that make it"""


@register_env("DynNav-Procedural-v1", max_episode_steps=NavEnv.max_episode_steps)
class ProceduralEnv(EgocentricTask, NavEnv):
    """
    **Task Description:**
    A new generated world every episode (``dynnav_tasks.generation``): an arena of 6-20 m a
    side with a static layout of 0.5 m blocks (open, clutter, corridors or rooms), up to 30
    moving 0.5 m boxes (back and forth, on routes, at random in rectangles) and one static or
    moving target. The robot must reach the target. The worlds come from a ``difficulty``'s
    distribution and a ``split`` of it, so that a navigator trained on some worlds can be
    tested on worlds it never saw:

    * ``difficulty`` ("easy", "medium", "hard"): ``generation.spec_for(difficulty, split)``
      says what each sets (arena size, layouts, obstacle count and speed, target motion);
      ``"mixed"`` (train split only): each reset draws the difficulty, each with probability
      1/3, then a train world of it (``env.unwrapped.world_difficulty`` says which)
    * ``split="train"``: world seed ``train_world_seed(difficulty, k)``, k drawn from the
      reset's seed; never a test world
    * ``split="test"``: the fixed list ``test_world_seeds(difficulty)`` (100 or more worlds of
      the train distribution): a reset with seed s shows world ``s mod len(list)``, so seeds
      0 to len - 1 cover the list once; an unseeded reset draws one
    * ``split="ood"``: ``spec_for(difficulty, "ood")``: larger arenas, more and faster
      obstacles, layouts the train distribution never has; world seed drawn from the seed
    * ``study_world="5.3"`` or ``"5.3-transfer"``: every episode plays that study world instead
      (``STUDY_WORLDS``; its target drawn from the reset's seed among the world's two, as 5.3
      draws it, its start and motions as 5.3's), read through this task's state: how a navigator
      of generated worlds does in the study's own
    * ``options={"world_seed": k}`` picks world k of the split (a test seed in the test split;
      never a test seed in the train split); ``options={"world": w}`` shows any ``World`` of
      this task's kind (0.5 m blocks and boxes, one target, arena sides up to 20 m)
    * the current world and its seed: ``env.unwrapped.world``, ``env.unwrapped.world_seed``
      (None for a world passed in ``options``)
    * state (``obs_mode="state"``, 19 + 5 k values with 16 rays; ``egocentric.py``): the lasers | target
      distance, sin and cos of its bearing | for each of the ``obstacle_k`` (default 4)
      nearest moving obstacles, its x, y and velocity relative to the robot in the robot's
      frame and a 1 (present); missing ones padded with (30, 0, 0, 0, 0). ``way=True`` adds,
      after the target, the way to it through the static layout (``way_sense.py``: its
      length, sin and cos of the bearing of the point 0.5 m along it), as a robot with a map
      and a global planner knows it: 22 + 5 k values
    * ``pedestrians=n`` (0-20, default 0): every world also holds n pedestrians walking its free
      space (``WorldSpec.pedestrians``; the same layout, start, target and boxes as without
      them), moved by ``pedestrian_model`` ("orca", default, or "social_force"), blind to the
      robot; touching one is a collision (``info["human_collision"]``) and the episode's last
      info holds the social metrics. ``human_k`` (default 0) adds, after the obstacles, the
      k nearest pedestrians' relative x, y, vx, vy and radius (5 values each), as
      ``DynNav-Crowd-v1``'s state does
    * ``odometry=True`` adds, after the target (and the way), the robot's own move over the last
      step: ahead and left (m) in its heading, and the turn (rad)
    * ``obs_mode="rgb"`` and ``"rgb+state"``: the camera worlds' red marker stands on the
      target (the generator makes it visible from the start)
    * reward: as every task's; ``normalized_dense`` divides by the current world's bound
      (``NavEnv.reward_bound_of(world)``, recomputed every episode), so it stays in [-1, 1]

    The scene is built once with every body a world can need and each reset moves the bodies
    this world uses into place and parks the rest under the floor (``scene_pool.py``).

    **Randomizations:**
    - the world (as the split says), and in it: the robot's start (uniform in a small square
      around the world's start point, any heading), the obstacles' and the target's motions
      (start phases, directions, speeds, as ``motion.py`` draws them)

    **Success Conditions:**
    - the robot's centre is within 0.3 m of the target's centre (reward +20)

    **Failure Conditions:**
    - any contact between the robot and a wall, block or moving box (reward -20)
    - 200 steps without success is a truncation (timeout), not a failure
    """

    def __init__(
        self,
        *args,
        difficulty: str = "easy",
        split: str = "train",
        obstacle_k: int = DEFAULT_OBSTACLE_K,
        way: bool = False,
        study_world: str = "",
        pedestrians: int = 0,
        pedestrian_model: str = "orca",
        human_k: int = 0,
        odometry: bool = False,
        obs_mode: Optional[str] = None,
        **kwargs,
    ):
        self.difficulty = check_choice(difficulty, (*generation.DIFFICULTIES, MIXED), "difficulty")
        self.split = check_choice(split, generation.SPLITS, "split")
        if self.difficulty == MIXED and self.split != "train":
            raise ValueError(f"difficulty='mixed' draws train worlds of every difficulty; split {self.split!r} needs "
                             f"one difficulty of {generation.DIFFICULTIES}")
        # a task-options string reads study_world=5.3 as the number 5.3: the name is its text
        study_world = str(study_world) if isinstance(study_world, (int, float)) and not isinstance(study_world, bool) \
            else study_world
        self.study_world = check_choice(study_world, ("", *STUDY_WORLDS), "study_world") if study_world else ""
        self.set_egocentric_options(obstacle_k, way, human_k, odometry)
        if isinstance(pedestrians, bool) or not isinstance(pedestrians, numbers.Integral) \
                or not 0 <= pedestrians <= generation.MAX_PEDESTRIANS:
            raise ValueError(f"pedestrians must be an integer from 0 to {generation.MAX_PEDESTRIANS}; got {pedestrians!r}")
        crowd = dict(pedestrians=(int(pedestrians),) * 2,
                     pedestrian_model=check_choice(pedestrian_model, generation.PEDESTRIAN_MODELS, "pedestrian_model"))
        camera = "rgb" in check_choice(obs_mode or OBS_MODES[0], self.SUPPORTED_OBS_MODES, "obs_mode")
        self._draws = generation.DIFFICULTIES if self.difficulty == MIXED else (self.difficulty,)
        self._specs = {d: generation.spec_for(d, self.split, camera=camera) for d in self._draws}
        if pedestrians:
            self._specs = {d: replace(spec, **crowd) for d, spec in self._specs.items()}
        self.world_difficulty = self._next_difficulty = self._draws[0]
        """the current world's difficulty (one of three with ``difficulty="mixed"``)"""
        self.world_spec = self._specs[self.world_difficulty]
        """the ``WorldSpec`` the current world was drawn from"""
        self._test_seeds = generation.test_world_seeds(self.world_difficulty)
        self._test_set = frozenset(self._test_seeds)
        self.world_seed = self._test_seeds[0] if self.split == "test" else self._seed_of_draw(0)
        """the current world's seed (None for a world given in ``reset``'s options)"""
        self.world = generation.generate_world(self.world_spec, self.world_seed)
        """the current episode's world"""
        self._request: Optional[tuple] = None  # what reset's options asked for, checked
        self._reset_seed: Optional[int] = None
        super().__init__(*args, obs_mode=obs_mode, **kwargs)

    # ------------------------------------------------------------------ choosing the world
    def reset(self, seed=None, options=None):
        """Reset into a new world (see the class docstring); ``options`` may hold
        ``world_seed`` (an int) or ``world`` (a ``World``), checked before anything changes."""
        options = dict(options or {})
        self._request = self._check_request(options)
        self._reset_seed = int(seed[0]) if isinstance(seed, (list, tuple, np.ndarray)) else seed
        return super().reset(seed=seed, options=options)

    def _check_request(self, options: dict) -> Optional[tuple]:
        """("world", World) or ("seed", k) from ``options``, validated; None: draw a world."""
        if self.study_world and ("world" in options or "world_seed" in options):
            raise ValueError(f"this task plays study world {self.study_world!r} (study_world); its reset takes no "
                             f"'world' or 'world_seed'")
        if "world" in options and "world_seed" in options:
            raise ValueError("give reset's options either 'world' or 'world_seed', not both")
        if "world" in options:
            world = options["world"]
            if not isinstance(world, World):
                raise ValueError(f"options['world'] must be a dynnav_tasks.world.World; got {type(world).__name__}")
            self._pool.check(world)
            return ("world", world)
        if "world_seed" not in options:
            return None
        if self.difficulty == MIXED:
            raise ValueError("options['world_seed'] names a world of one difficulty: make the task with that "
                             "difficulty, or pass the World itself as options['world']")
        k = options["world_seed"]
        if isinstance(k, bool) or not isinstance(k, numbers.Integral) or k < 0:
            raise ValueError(f"options['world_seed'] must be a non-negative integer; got {k!r}")
        k = int(k)
        if self.split == "test" and k not in self._test_set:
            raise ValueError(f"world seed {k} is not one of the {len(self._test_seeds)} test worlds of difficulty "
                             f"{self.difficulty!r}; dynnav_tasks.generation.test_world_seeds({self.difficulty!r}) "
                             "lists them")
        if self.split == "train" and k in self._test_set:
            raise ValueError(f"world seed {k} is a test world of difficulty {self.difficulty!r}; the train split "
                             "never shows one (make the task with split='test' to see it)")
        return ("seed", k)

    def _seed_of_draw(self, k: int) -> int:
        """The world seed a draw ``k`` picks in the train and ood splits."""
        return generation.train_world_seed(self._next_difficulty, k) if self.split == "train" else k

    def _draw_world_seed(self) -> int:
        if self.split == "test":
            n = len(self._test_seeds)
            i = self._reset_seed % n if self._reset_seed is not None else int(self.np_random.integers(n))
            return self._test_seeds[i]
        if self.difficulty == MIXED:
            self._next_difficulty = self._draws[int(self.np_random.integers(len(self._draws)))]
        return self._seed_of_draw(int(self.np_random.integers(WORLD_SEED_DRAW)))

    # ------------------------------------------------------------------ scene and episodes
    def _build_world(self) -> BuiltWorld:
        g = generation
        sizes = PoolSizes(g.MAX_STATIC_BLOCKS, g.MAX_MOVING_OBSTACLES, g.BLOCK_HALF, max_arena_side=MAX_ARENA_SIDE,
                          max_pedestrians=g.MAX_PEDESTRIANS)
        self._pool = ScenePool(self.scene, sizes)
        self._shown = None  # ManiSkill puts every body back where it was built: the first reset places them
        return self._pool.place(self.world)

    def _initialize_episode(self, env_idx, options: dict):
        request, self._request = self._request, None
        self._next_difficulty = self.world_difficulty
        if self.study_world:
            world = moving_obstacles.world_with(**STUDY_WORLDS[self.study_world])
            target = world.targets[int(self.np_random.integers(len(world.targets)))]
            self._show(replace(world, targets=(target,)), None)
        elif request is not None and request[0] == "world":
            self._show(request[1], None)
        else:
            seed = request[1] if request is not None else self._draw_world_seed()
            same = seed == self.world_seed and self._next_difficulty == self.world_difficulty
            if not same or self._shown is None:  # the same world again needs nothing moved
                spec = self._specs[self._next_difficulty]
                world = self.world if same else generation.generate_world(spec, seed)
                self.world_difficulty, self.world_spec = self._next_difficulty, spec
                self._show(world, seed)
        super()._initialize_episode(env_idx, options)

    def _show(self, world: World, seed: Optional[int]):
        """Make ``world`` the scene's world from this reset on."""
        self.world, self.world_seed = world, seed
        self._way = None
        self._use_world(self._pool.place(world))
        self._shown = world
        self.reward_bound = self.reward_bound_of(world)
        self._aim_top_down_camera()

    def close(self):
        """Release the scene's pooled bodies with the scene (see ``NavEnv.close``)."""
        for name in ("_pool", "_shown"):
            self.__dict__.pop(name, None)
        super().close()

    # ------------------------------------------------------------------ top-down picture
    @property
    def _default_human_render_camera_configs(self):
        """The top-down camera, wide enough for the largest arena from ``TOP_DOWN_HEIGHT``;
        each episode lowers it over its own arena (``_aim_top_down_camera``)."""
        h, n = self.TOP_DOWN_HEIGHT, self.TOP_DOWN_SIZE
        pose = sapien_utils.look_at(eye=[0.0, 0.0, h], target=[0.0, 0.0, 0.0], up=[0, 1, 0])
        fov = 2 * math.atan(self._largest_half_extent() / h)
        return CameraConfig("top_down", pose=pose, width=n, height=n, fov=fov, near=0.1, far=2 * h)

    def _largest_half_extent(self) -> float:
        return MAX_ARENA_SIDE / 2 + self.world.arena.wall_thickness + TOP_DOWN_MARGIN

    def _aim_top_down_camera(self):
        """Centre the top-down camera over this world's arena, at the height where its view
        spans what ``top_down_pixel`` maps (``_top_down_half_extent``)."""
        h = self._top_down_half_extent() / self._largest_half_extent() * self.TOP_DOWN_HEIGHT
        cx, cy = (float(v) for v in self.world.arena.center)
        if getattr(self, "_down", None) is None:  # looking straight down, y up in the picture: one rotation for all
            self._down = sapien_utils.look_at(eye=[0.0, 0.0, 1.0], target=[0.0, 0.0, 0.0], up=[0, 1, 0]).sp.q
        self._human_render_cameras["top_down"].camera.set_local_pose(sapien.Pose([cx, cy, h], self._down))
