"""Pictures of generated worlds: the docs' sample worlds and the test phase's trajectories.png."""

import numpy as np
import pytest
from PIL import Image

from agents.training.test_report import OUTCOME_COLORS, TILE_SIZE, draw_trajectories, episode_worlds, one_world
from dynnav_tasks.outcomes import outcome_of
from dynnav_tasks.viz.pictures import (
    SAMPLE_WORLDS, arena_box, sample_world_path, sample_world_picture, write_sample_worlds,
)
from dynnav_tasks.world import STATIC_OBSTACLE_COLOR, WALL_COLORS

TASK = "DynNav-Procedural-v1"


def near(pixel, rgba, tolerance=40) -> bool:
    return int(np.abs(np.asarray(pixel, int) - np.array([round(255 * c) for c in rgba[:3]])).sum()) <= tolerance


@pytest.fixture
def medium(make_env):
    return make_env(TASK, difficulty="medium", split="train")


def test_sample_world_picture_shows_the_world(medium):
    """The picture is the task's own render of that world, cropped to its arena: its walls,
    blocks and target where the world puts them."""
    seed = SAMPLE_WORLDS["medium"][0][1]
    img = sample_world_picture(medium, seed, size=320)
    base = medium.unwrapped
    world = base.world
    assert base.world_seed == seed and max(img.size) == 320
    box = arena_box(medium, (base.TOP_DOWN_SIZE, base.TOP_DOWN_SIZE))
    scale = img.width / (box[2] - box[0])
    assert img.height == pytest.approx((box[3] - box[1]) * scale, abs=1)  # the arena's shape, not a square

    pixels = np.asarray(img.convert("RGB"))

    def at(x, y):
        c, r = base.top_down_pixel(x, y)
        return pixels[int((r - box[1]) * scale), int((c - box[0]) * scale)]

    for side, (center, _) in world.arena.walls().items():
        assert near(at(*center), WALL_COLORS[side]), side
    blocks = [g.motion.at for g in world.obstacles if not g.moving]
    assert len(blocks) > 10
    assert np.mean([near(at(*b), STATIC_OBSTACLE_COLOR) for b in blocks]) > 0.9
    assert near(at(*base.snapshot.target_xy), (1.0, 0.0, 0.0), tolerance=60)
    assert (np.abs(pixels.astype(int) - (255, 140, 0)).sum(axis=2) < 30).sum() > 50  # the motions drawn in orange
    other = np.asarray(sample_world_picture(medium, SAMPLE_WORLDS["medium"][1][1], size=320).convert("RGB"))
    assert other.shape != pixels.shape or np.abs(other.astype(int) - pixels).mean() > 5


def test_sample_worlds_are_written_small_and_reproducibly(tmp_path):
    samples = {"easy": (("ood", SAMPLE_WORLDS["easy"][-1][1]),)}
    (path,) = write_sample_worlds(tmp_path, samples, size=256)
    assert path == sample_world_path(tmp_path, "easy", "ood", samples["easy"][0][1]) and path.name.startswith("procedural-easy-ood-")
    first = path.read_bytes()
    assert 1_000 < len(first) < 60_000
    write_sample_worlds(tmp_path, samples, size=256)
    assert path.read_bytes() == first  # the same seeds draw the same picture
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary file left


def test_every_sample_world_is_a_world_of_its_split():
    from dynnav_tasks.generation import DIFFICULTIES, test_world_seeds

    assert set(SAMPLE_WORLDS) == set(DIFFICULTIES)
    for difficulty, pairs in SAMPLE_WORLDS.items():
        assert [split for split, _ in pairs].count("train") == 2 and [split for split, _ in pairs].count("ood") == 1
        assert not {seed for split, seed in pairs if split == "train"} & set(test_world_seeds(difficulty))


def random_records(env, seeds, steps=30):
    """Test-phase records (as ``agents.training.test_phase.run_episodes`` writes them) of short random episodes."""
    records, rng = [], np.random.default_rng(0)
    for seed in seeds:
        env.reset(seed=seed)
        snap = env.unwrapped.snapshot
        path, info, terminated = [snap.robot_xy.tolist()], {}, False
        for _ in range(steps):
            _, _, terminated, truncated, info = env.step(int(rng.integers(3)))
            path.append(list(env.unwrapped.snapshot.pose[:2]))
            if terminated or truncated:
                break
        outcome = outcome_of(info, terminated) if terminated else "timeout"
        records.append(dict(seed=seed, outcome=outcome, trajectory=path, target_start=list(snap.target_xy)))
    return records


def test_trajectories_of_per_episode_worlds_are_a_grid_of_their_own_worlds(make_env, tmp_path):
    env = make_env(TASK, difficulty="easy", split="test")
    records = random_records(env, seeds=range(5))
    worlds = episode_worlds(env, records)
    assert not one_world(worlds)
    draw_trajectories(env, records, tmp_path / "trajectories.png")
    img = np.asarray(Image.open(tmp_path / "trajectories.png").convert("RGB"))
    header = img.shape[0] - 2 * TILE_SIZE
    assert img.shape[1] == 4 * TILE_SIZE and 0 < header < 60  # 5 episodes: two rows of four tiles under a legend
    base = env.unwrapped
    for i, (r, world) in enumerate(zip(records, worlds)):
        env.reset(seed=r["seed"])
        assert base.world == world
        tile = img[header + (i // 4) * TILE_SIZE:][:TILE_SIZE, (i % 4) * TILE_SIZE:][:, :TILE_SIZE]
        shrink = TILE_SIZE / base.TOP_DOWN_SIZE
        for side, (center, _) in world.arena.walls().items():  # this episode's arena, not another's
            c, w = base.top_down_pixel(*center)
            assert near(tile[int(w * shrink), int(c * shrink)], WALL_COLORS[side]), (i, side)
        # the path's point farthest from its start lies on the drawn path, in the outcome's colour
        points = np.array([base.top_down_pixel(x, y) for x, y in r["trajectory"]]) * shrink
        far = points[np.argmax(np.linalg.norm(points - points[0], axis=1))]
        assert np.linalg.norm(far - points[0]) > 4, "a longer random episode is needed to see its path"
        c, w = int(round(far[0])), int(round(far[1]))
        around = tile[w - 1:w + 2, c - 1:c + 2].reshape(-1, 3).astype(int)
        assert (np.abs(around - OUTCOME_COLORS[r["outcome"]]).sum(axis=1) < 60).any(), f"episode {i}: no path"


def test_one_world_tasks_keep_one_picture(make_env):
    env = make_env("DynNav-MovingObstacles-v1")
    assert one_world(episode_worlds(env, [dict(seed=s) for s in range(4)]))
    with pytest.raises(ValueError, match="no test episodes"):
        draw_trajectories(env, [], "unused.png")


def test_the_crowd_picture_shows_the_pedestrians_and_crosses_on_their_goals(make_env):
    """The crowd task's annotated picture: pink bodies, and a plum cross on each pedestrian's goal
    at the pixel of the goal's floor point."""
    from dynnav_tasks.viz.pictures import PEDESTRIAN_GOAL, annotated_top_down
    from dynnav_tasks.world import PEDESTRIAN_COLOR

    env = make_env("DynNav-Crowd-v1", humans=5)
    env.reset(seed=0)
    img = np.asarray(annotated_top_down(env))
    base = env.unwrapped
    for gx, gy in base.pedestrian_goals.tolist():
        c, r = (int(round(v)) for v in base.top_down_pixel(gx, gy))
        assert near(img[r, c], [v / 255 for v in PEDESTRIAN_GOAL]), (gx, gy)
    pink = np.array([round(255 * v) for v in PEDESTRIAN_COLOR[:3]])
    assert (np.abs(img.astype(int) - pink).sum(axis=-1) <= 40).sum() > 5 * 200  # five bodies' pixels, at least
