"""Procedural worlds: ``generate_world(spec, world_seed)`` builds a valid ``World`` from a seed.

``WorldSpec`` (``spec.py``) describes the distribution (arena size, layout, moving obstacles
and their speeds, the target); ``spec_for(difficulty, split)`` (``presets.py``) gives the
presets of ``DIFFICULTIES`` x ``SPLITS``; ``test_world_seeds`` and ``train_world_seed``
(``splits.py``) fix the disjoint train and test worlds. Every generated world is checked as
``validity.py`` describes: the start and the target free, a way through the static layout on
an occupancy grid, the target's marker visible in camera worlds. Bad input is a
``GenerationError`` (a ``ValueError``) naming the field.

    from dynnav_tasks.generation import generate_world, spec_for, train_world_seed

    world = generate_world(spec_for("medium", "train"), train_world_seed("medium", 0))
"""

from .generator import generate_world
from .presets import DIFFICULTIES, SPLITS, spec_for
from .spec import (
    BLOCK_HALF, MAX_MOVING_OBSTACLES, MAX_PEDESTRIANS, MAX_STATIC_BLOCKS, PEDESTRIAN_MODELS, GenerationError, WorldSpec,
)
from .splits import test_world_seeds, train_world_seed

__all__ = [
    "BLOCK_HALF", "DIFFICULTIES", "GenerationError", "MAX_MOVING_OBSTACLES", "MAX_PEDESTRIANS", "MAX_STATIC_BLOCKS",
    "PEDESTRIAN_MODELS", "SPLITS",
    "WorldSpec", "generate_world", "spec_for", "test_world_seeds", "train_world_seed",
]
