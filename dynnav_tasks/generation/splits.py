"""World seeds of the train and test splits, fixed for every difficulty.

* ``test_world_seeds(d)``: ``TEST_WORLDS`` (100) distinct seeds in [0, 2**31), drawn once from
  a numpy ``Generator(PCG64)`` seeded by ``SeedSequence([TEST_STREAM, i])``, where ``i`` is the
  difficulty's index in ``DIFFICULTIES``: the same tuple on every machine and in every version
  that keeps these two numbers.
* ``train_world_seed(d, k)``: the k-th non-negative integer that is not a test seed of ``d``
  (0, 1, 2, ... skipping the test seeds), so every ``k >= 0`` has a train world, different
  ``k`` give different worlds, and no train world is a test world. A world seed passes through
  ``SeedSequence`` (``generate_world``), so consecutive seeds give unrelated worlds and train
  and test worlds come from the same distribution.

The ``ood`` split draws its world seeds from the episode seed (any integer); it has no list.
"""

from __future__ import annotations

import numbers
from functools import lru_cache

import numpy as np

from .presets import DIFFICULTIES, check_difficulty
from .spec import GenerationError

TEST_WORLDS = 100
"""test worlds per difficulty"""
TEST_STREAM = 61_001
"""the first entropy word of the test seeds' stream"""


@lru_cache(maxsize=None)
def test_world_seeds(difficulty: str) -> tuple[int, ...]:
    """The fixed test world seeds of ``difficulty`` (see the module docstring)."""
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([TEST_STREAM, DIFFICULTIES.index(check_difficulty(difficulty))])))
    seeds: list[int] = []
    while len(seeds) < TEST_WORLDS:
        seed = int(rng.integers(0, 2**31))
        if seed not in seeds:
            seeds.append(seed)
    return tuple(seeds)


test_world_seeds.__test__ = False  # its name starts with "test": tell pytest it is not a test


@lru_cache(maxsize=None)
def _sorted_test_seeds(difficulty: str) -> tuple[int, ...]:
    return tuple(sorted(test_world_seeds(difficulty)))


def train_world_seed(difficulty: str, k: int) -> int:
    """The world seed of the ``k``-th train world of ``difficulty`` (``k`` >= 0): the k-th
    non-negative integer outside ``test_world_seeds(difficulty)``."""
    check_difficulty(difficulty)
    if isinstance(k, (bool, np.bool_)) or not isinstance(k, numbers.Integral) or k < 0:
        raise GenerationError(f"k must be a non-negative integer (the train world's index); got {k!r}", "k")
    seed = int(k)
    for test in _sorted_test_seeds(difficulty):
        if test > seed:
            break
        seed += 1
    return seed
