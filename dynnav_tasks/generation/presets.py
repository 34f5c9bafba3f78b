"""The difficulty presets: ``spec_for(difficulty, split)``.

``train`` and ``test`` share one spec per difficulty (they differ only in world seeds, see
``splits.py``); ``ood`` is larger, has more and faster obstacles, and uses layouts that the
difficulty's training spec never produces. Speeds are in robot forward steps (0.15 m per
step); every preset mixes the three motion models evenly (``BackAndForth``, ``Route``,
``RandomInRect``).

| preset | arena (m) | layouts | clutter | moving obstacles | speed (robot steps) | target | way (m) |
|---|---|---|---|---|---|---|---|
| easy | 6-8 | open, clutter | 0.03-0.08 | 0-3 | 0.3-0.6 | static | 2-6 |
| medium | 8-12 | clutter, corridors | 0.05-0.12 | 3-8 | 0.3-1.0 | static | 3-10 |
| hard | 10-14 | clutter, corridors, rooms | 0.06-0.15 | 8-15 | 0.3-1.5 | static or moving | 4-12 |
| easy ood | 14-20 | corridors | 0.03-0.08 | 6-12 | 0.5-1.0 | static | 5-15 |
| medium ood | 14-20 | rooms | 0.05-0.12 | 10-20 | 0.5-1.5 | static | 5-15 |
| hard ood | 14-20 | open (a crowded hall) | - | 20-30 | 0.5-2.0 | static or moving | 5-15 |

"clutter" is the fraction of block cells covered by scattered blocks (half of it in corridors
and rooms, none in the open); "way" (``target_distance``) is the length of the way from the
start to the target through the static layout, on the occupancy grid.
The out-of-distribution layouts: easy trains on open floors and clutter and is tested in
corridors; medium trains on clutter and corridors and is tested in rooms with doorways; hard
trains among static structure of every kind and is tested in a hall with no structure at all,
crowded with 20-30 boxes at up to twice the robot's speed. ``camera=True`` gives the same
spec with the target's marker (and its visibility from the start) on.
"""

from __future__ import annotations

from dataclasses import replace

from ..errors import close_matches_message
from .spec import GenerationError, WorldSpec

DIFFICULTIES = ("easy", "medium", "hard")
SPLITS = ("train", "test", "ood")

_TRAIN = {
    "easy": WorldSpec(
        arena_size=(6.0, 8.0), layout=("open", "clutter"), layout_density=(0.03, 0.08), moving_obstacles=(0, 3),
        relative_speed=(0.3, 0.6), target_motion=("static",), target_distance=(2.0, 6.0),
    ),
    "medium": WorldSpec(
        arena_size=(8.0, 12.0), layout=("clutter", "corridors"), layout_density=(0.05, 0.12), moving_obstacles=(3, 8),
        relative_speed=(0.3, 1.0), target_motion=("static",), target_distance=(3.0, 10.0),
    ),
    "hard": WorldSpec(
        arena_size=(10.0, 14.0), layout=("clutter", "corridors", "rooms"), layout_density=(0.06, 0.15),
        moving_obstacles=(8, 15), relative_speed=(0.3, 1.5), target_motion=("static", "moving"),
        target_distance=(4.0, 12.0),
    ),
}
_OOD = {
    "easy": replace(
        _TRAIN["easy"], arena_size=(14.0, 20.0), layout=("corridors",), moving_obstacles=(6, 12),
        relative_speed=(0.5, 1.0), target_distance=(5.0, 15.0),
    ),
    "medium": replace(
        _TRAIN["medium"], arena_size=(14.0, 20.0), layout=("rooms",), moving_obstacles=(10, 20),
        relative_speed=(0.5, 1.5), target_distance=(5.0, 15.0),
    ),
    "hard": replace(
        _TRAIN["hard"], arena_size=(14.0, 20.0), layout=("open",), moving_obstacles=(20, 30),
        relative_speed=(0.5, 2.0), target_distance=(5.0, 15.0),
    ),
}


def check_difficulty(difficulty: str) -> str:
    """``difficulty`` if it is one of ``DIFFICULTIES``; a ``GenerationError`` naming it if not."""
    if difficulty not in DIFFICULTIES:
        raise GenerationError(
            f"Unknown difficulty {difficulty!r}. " + close_matches_message(difficulty, DIFFICULTIES, "difficulty"),
            "difficulty",
        )
    return difficulty


def spec_for(difficulty: str, split: str, camera: bool = False) -> WorldSpec:
    """The ``WorldSpec`` of ``difficulty`` ("easy", "medium", "hard") and ``split`` ("train",
    "test", "ood"); ``camera=True`` turns the target's marker on (see the module docstring)."""
    check_difficulty(difficulty)
    if split not in SPLITS:
        raise GenerationError(f"Unknown split {split!r}. " + close_matches_message(split, SPLITS, "split"), "split")
    if not isinstance(camera, bool):
        raise GenerationError(f"camera must be True or False; got {camera!r}", "camera")
    spec = _OOD[difficulty] if split == "ood" else _TRAIN[difficulty]
    return replace(spec, camera=True) if camera else spec
