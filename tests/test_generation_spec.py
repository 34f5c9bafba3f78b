"""WorldSpec validation (each bad field is a GenerationError naming it) and the presets as documented."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from dynnav_tasks.generation import (
    DIFFICULTIES, SPLITS, GenerationError, WorldSpec, generate_world, spec_for, train_world_seed,
)

BAD_FIELDS = [
    ("arena_size", (-1.0, 8.0)),
    ("arena_size", (5.0, 8.0)),
    ("arena_size", (8.0, 25.0)),
    ("arena_size", (10.0, 8.0)),
    ("arena_size", ("8", 10.0)),
    ("arena_size", (float("nan"), 10.0)),
    ("arena_size", (8.0, 9.0, 10.0)),
    ("layout", "maze"),
    ("layout", ()),
    ("layout", ("open", "mazes")),
    ("layout_density", (-0.1, 0.1)),
    ("layout_density", (0.1, 0.5)),
    ("moving_obstacles", (-1, 3)),
    ("moving_obstacles", (0, 31)),
    ("moving_obstacles", (5, 3)),
    ("moving_obstacles", (0, 2.5)),
    ("motion_mix", ("teleport",)),
    ("motion_mix", ()),
    ("relative_speed", (0.0, 1.0)),
    ("relative_speed", (0.5, 4.0)),
    ("relative_speed", (-1.0, 1.0)),
    ("target_motion", ("flying",)),
    ("target_distance", (0.2, 3.0)),
    ("target_distance", (3.0, 2.0)),
    ("camera", "yes"),
    ("pedestrians", (0, 21)),
    ("pedestrians", (3, 2)),
    ("pedestrian_model", ("zombie",)),
]


@pytest.mark.parametrize("field,value", BAD_FIELDS)
def test_each_bad_field_is_an_error_naming_it(field, value):
    with pytest.raises(GenerationError, match=field) as info:
        WorldSpec(**{field: value})
    assert info.value.field == field
    assert isinstance(info.value, ValueError)


def test_an_unknown_name_suggests_the_close_one():
    with pytest.raises(GenerationError, match="Did you mean 'corridors'"):
        WorldSpec(layout="coridors")


def test_more_obstacles_than_fit_the_arena_is_an_error():
    with pytest.raises(GenerationError, match="moving_obstacles.*18 moving obstacles fit") as info:
        WorldSpec(arena_size=(6.0, 10.0), moving_obstacles=(0, 19), target_distance=(2.0, 4.0))
    assert info.value.field == "moving_obstacles"
    WorldSpec(arena_size=(6.0, 10.0), moving_obstacles=(0, 18), target_distance=(2.0, 4.0))  # fits


def test_a_target_distance_no_arena_holds_is_an_error():
    with pytest.raises(GenerationError, match="target_distance") as info:
        WorldSpec(arena_size=(6.0, 6.0), moving_obstacles=(0, 3), target_distance=(5.0, 6.0))
    assert info.value.field == "target_distance"


def test_replace_validates_too():
    with pytest.raises(GenerationError, match="layout"):
        replace(spec_for("easy", "train"), layout=("tunnels",))


def test_a_spec_no_world_satisfies_is_an_error_naming_the_field():
    """Legal ranges that cannot all hold at once: 18 route boxes beside thick clutter in 6 m."""
    spec = WorldSpec(arena_size=(6.0, 6.0), layout="clutter", layout_density=0.3, moving_obstacles=18,
                     motion_mix="route", target_distance=(2.0, 3.0))
    with pytest.raises(GenerationError, match="no valid world.*moving_obstacles") as info:
        generate_world(spec, 0)
    assert info.value.field == "moving_obstacles"


@pytest.mark.parametrize("seed", [-1, 1.5, True, 2**64, "3", None])
def test_a_bad_world_seed_is_an_error(seed):
    with pytest.raises(GenerationError, match="world_seed") as info:
        generate_world(spec_for("easy", "train"), seed)
    assert info.value.field == "world_seed"


def test_generate_world_wants_a_spec():
    with pytest.raises(GenerationError, match="WorldSpec") as info:
        generate_world({"arena_size": (6, 8)}, 0)
    assert info.value.field == "spec"


def test_bad_difficulty_split_and_index_are_errors():
    with pytest.raises(GenerationError, match="difficulty 'expert'.*easy, medium, hard") as info:
        spec_for("expert", "train")
    assert info.value.field == "difficulty"
    with pytest.raises(GenerationError, match="split 'validation'") as info:
        spec_for("easy", "validation")
    assert info.value.field == "split"
    with pytest.raises(GenerationError, match="k must be a non-negative integer") as info:
        train_world_seed("easy", -1)
    assert info.value.field == "k"


def test_train_and_test_share_a_spec_and_ood_differs():
    for d in DIFFICULTIES:
        assert spec_for(d, "train") == spec_for(d, "test")
        train, ood = spec_for(d, "train"), spec_for(d, "ood")
        assert set(ood.layout).isdisjoint(train.layout), "ood uses layouts training never produces"
        assert ood.arena_size[0] >= train.arena_size[1]
        assert ood.moving_obstacles[1] > train.moving_obstacles[1]
        assert ood.relative_speed[1] >= train.relative_speed[1]
        camera = spec_for(d, "train", camera=True)
        assert camera.camera and replace(camera, camera=False) == train
    assert SPLITS == ("train", "test", "ood")


def _sample(difficulty, split, n=150):
    spec = spec_for(difficulty, split)
    seeds = [train_world_seed(difficulty, k) for k in range(n)] if split == "train" else range(n)
    return [generate_world(spec, s) for s in seeds]


def test_the_presets_differ_as_documented():
    worlds = {(d, s): _sample(d, s) for d in DIFFICULTIES for s in ("train", "ood")}

    def mean(key, f):
        return float(np.mean([f(w) for w in worlds[key]]))

    def side(w):
        return max(w.arena.x_range[1], w.arena.y_range[1])

    moving = {key: mean(key, lambda w: w.moving_obstacle_count) for key in worlds}
    assert moving["easy", "train"] < moving["medium", "train"] < moving["hard", "train"]
    for d in DIFFICULTIES:
        assert moving[d, "ood"] > moving[d, "train"]
        lows, highs = spec_for(d, "train").arena_size, spec_for(d, "ood").arena_size
        assert all(lows[0] <= min(w.arena.x_range[1], w.arena.y_range[1]) and side(w) <= lows[1] for w in worlds[d, "train"])
        assert all(14.0 <= min(w.arena.x_range[1], w.arena.y_range[1]) and side(w) <= highs[1] for w in worlds[d, "ood"])
    assert mean(("easy", "train"), side) < mean(("medium", "train"), side) < mean(("hard", "train"), side)
    for key, sample in worlds.items():
        low, high = spec_for(*key).moving_obstacles
        assert all(low <= w.moving_obstacle_count <= high for w in sample), key
    # the hall of hard ood has no static block; easy never has a moving target, hard has both kinds
    assert all(not any(not o.moving for o in w.obstacles) for w in worlds["hard", "ood"])
    kinds = {key: {type(w.targets[0]).__name__ for w in sample} for key, sample in worlds.items()}
    assert kinds["easy", "train"] == {"Static"}
    assert "Static" in kinds["hard", "train"] and kinds["hard", "train"] - {"Static"}
    # speeds stay in the spec's range (in m per step: relative speed x 0.15)
    for key, sample in worlds.items():
        low, high = (v * 0.15 for v in spec_for(*key).relative_speed)
        for w in sample:
            for o in w.obstacles:
                if o.moving:
                    speeds = (o.motion.speed,) if hasattr(o.motion, "speed") else o.motion.speed_range
                    assert all(low - 1e-3 <= s <= high + 1e-3 for s in speeds), (key, o.motion)


def test_pedestrians_come_on_top_of_the_same_world():
    """A spec with pedestrians draws them last: the same layout, start, target and boxes as the
    spec without them, plus a free-space crowd in the arena; the count comes from its range."""
    from dataclasses import replace

    from dynnav_tasks.generation import generate_world, spec_for

    spec = spec_for("medium", "test")
    for seed in (3, 11):
        plain = generate_world(spec, seed)
        crowded = generate_world(replace(spec, pedestrians=(2, 6), pedestrian_model=("social_force",)), seed)
        assert plain.pedestrians is None and replace(crowded, pedestrians=None) == plain
        p = crowded.pedestrians
        assert 2 <= p.count <= 6 and (p.scenario, p.model) == ("free_space", "social_force")
        assert p.area == (plain.arena.x_range, plain.arena.y_range)
    with pytest.raises(GenerationError, match="pedestrians.*fit") as info:
        WorldSpec(arena_size=(6.0, 10.0), pedestrians=(0, 19), target_distance=(2.0, 4.0))
    assert info.value.field == "pedestrians"
