"""Pictures of every task, rendered by the task itself, for the README and the docs.

    python -m dynnav_tasks.viz.pictures --out docs/images [--worlds all|tasks|procedural]

``<task>.png``: the task's top-down camera (all candidate targets shown as red discs) with
the targets' motion (dark red: segments, or the areas they wander in), the obstacles' motion
(orange: routes with arrows, or the areas their boxes can cover) and the start area (white).
Where the start area or the target's disc would be only a few pixels wide (the large
generated arenas), a white square and a dark red ring of a readable size mark them.

``<task>-camera.png`` (camera worlds): what the robot's front camera sees (32x32, shown
enlarged) every 4 steps while ``camera_pilot.CameraPilot``, which reads only these frames,
drives to the target.

``DynNav-Crowd-v1-<scenario>.png``: the crowd task's scenarios after a few steps, each
pedestrian (pink) with a line to the goal it heads for and a cross on that goal (plum).

``procedural-<difficulty>-<split>-<world seed>.png``: the sample worlds of
``DynNav-Procedural-v1`` listed in ``SAMPLE_WORLDS``, annotated the same way and cropped to
the arena (``sample_world_picture``).
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import tyro
from PIL import Image, ImageDraw

from dynnav_tasks.motion import BackAndForth, RandomInRect, Route
from dynnav_tasks.scene import TARGET_DISC_RADIUS

TARGET_PATH = (120, 0, 0)
OBSTACLE_PATH = (255, 140, 0)
START_AREA = (255, 255, 255)
PEDESTRIAN_GOAL = (150, 40, 110)
CROWD_TASK = "DynNav-Crowd-v1"
MAP_TASK = "DynNav-Map-v1"
CROWD_STEPS = 8
"""steps of the crowd pictures' episode before the picture (the pedestrians under way)"""
MARK_MIN_PX = 20
"""least width (pixels of the 512-pixel top-down picture) of the start area's square and the
target's ring: smaller ones are drawn this wide"""

PROCEDURAL_TASK = "DynNav-Procedural-v1"
SAMPLE_SIZE = 320
"""pixels of the longer side of a sample world's picture"""
SAMPLE_RESET_SEED = 0
"""reset seed of every sample picture (the robot's start and the motions' phases)"""
SAMPLE_WORLDS: dict[str, tuple[tuple[str, int], ...]] = {
    "easy": (("train", 0), ("train", 3), ("ood", 0)),
    "medium": (("train", 0), ("train", 3), ("ood", 0)),
    "hard": (("train", 1), ("train", 4), ("ood", 2)),
}
"""(split, world seed) of the pictured worlds of each difficulty: two train worlds and one ood
world, chosen to show the difficulty's layouts and motions: easy, clutter and an open floor
(ood: corridors); medium, corridors and clutter (ood: rooms); hard, rooms and clutter with a
moving target (ood: a crowded hall)"""


@dataclass
class Args:
    out: Path = Path("docs/images")
    """folder to write <task>.png into"""
    seed: int = 0
    """reset seed of the pictured episode (the study's worlds)"""
    worlds: Literal["all", "tasks", "procedural", "crowd", "map"] = "all"
    """which pictures: the study's tasks, the procedural sample worlds, the crowd's scenarios, the
    office map, or all"""


def _motion_lines(motion) -> list[np.ndarray]:
    if isinstance(motion, BackAndForth):
        lo, hi = motion.extent()
        c, d = np.array(motion.center), np.array(motion.direction, dtype=float)
        d /= np.linalg.norm(d)
        return [np.stack([c - motion.amplitude * d, c + motion.amplitude * d])]
    if isinstance(motion, Route):
        pts = np.array(list(motion.waypoints) + [motion.waypoints[0]], dtype=float)
        return [pts]
    return []


def _area_corners(motion, margin=(0.0, 0.0)):
    """Top-left and bottom-right floor corners of a RandomInRect's area grown by ``margin``."""
    lo, hi = motion.extent()
    lo, hi = np.asarray(lo) - margin, np.asarray(hi) + margin
    return (lo[0], hi[1]), (hi[0], lo[1])


def _arrow(draw, a, b, color, width):
    draw.line([tuple(a), tuple(b)], fill=color, width=width)
    d = np.asarray(b, float) - np.asarray(a, float)
    n = np.linalg.norm(d)
    if n < 1e-6:
        return
    d /= n
    mid = (np.asarray(a) + np.asarray(b)) / 2
    left = mid - 10 * d + 6 * np.array([-d[1], d[0]])
    right = mid - 10 * d - 6 * np.array([-d[1], d[0]])
    draw.polygon([tuple(mid), tuple(left), tuple(right)], fill=color)


def annotated_top_down(env) -> Image.Image:
    """The task's top-down render with its motions and start area drawn on."""
    base = env.unwrapped
    img = Image.fromarray(base.render_top_down(show_all_targets=True))
    draw = ImageDraw.Draw(img)
    px = base.top_down_pixel
    for target in base.world.targets:
        if isinstance(target, RandomInRect):
            a, b = _area_corners(target)
            draw.rectangle([px(*a), px(*b)], outline=TARGET_PATH, width=3)
        for line in _motion_lines(target):
            pts = [px(*p) for p in line]
            draw.line(pts, fill=TARGET_PATH, width=3)
    for group in base.world.obstacles:
        if isinstance(group.motion, RandomInRect):
            a, b = _area_corners(group.motion, np.asarray(group.half_size))
            draw.rectangle([px(*a), px(*b)], outline=OBSTACLE_PATH, width=3)
        for line in _motion_lines(group.motion):
            pts = [px(*p) for p in line]
            for a, b in zip(pts[:-1], pts[1:]):
                _arrow(draw, a, b, OBSTACLE_PATH, 3)
    for (hx, hy), (gx, gy) in zip(base.snapshot.human_xy.tolist(), base.pedestrian_goals.tolist()):
        draw.line([px(hx, hy), px(gx, gy)], fill=PEDESTRIAN_GOAL, width=2)
        (c, r) = px(gx, gy)
        draw.line([(c - 6, r - 6), (c + 6, r + 6)], fill=PEDESTRIAN_GOAL, width=3)
        draw.line([(c - 6, r + 6), (c + 6, r - 6)], fill=PEDESTRIAN_GOAL, width=3)
    s = base.world.start
    (c0, r0), (c1, r1) = px(s.x_range[0], s.y_range[1]), px(s.x_range[1], s.y_range[0])
    draw.rectangle(_at_least([c0, r0, c1, r1], MARK_MIN_PX), outline=START_AREA, width=2)
    (tc, tr), (ec, _) = px(*base.snapshot.target_xy), px(base.snapshot.target_xy[0] + TARGET_DISC_RADIUS, 0.0)
    if 2 * (ec - tc) < MARK_MIN_PX:
        half = MARK_MIN_PX / 2
        draw.ellipse([tc - half, tr - half, tc + half, tr + half], outline=TARGET_PATH, width=2)
    return img


def _at_least(box, size: float) -> list[float]:
    """``box`` (left, top, right, bottom) grown about its centre to ``size`` pixels or more a side."""
    (c0, r0, c1, r1), half = box, size / 2
    cc, cr = (c0 + c1) / 2, (r0 + r1) / 2
    return [min(c0, cc - half), min(r0, cr - half), max(c1, cc + half), max(r1, cr + half)]


def arena_box(env, img_size: tuple[int, int], margin: float = 0.3) -> tuple[int, int, int, int]:
    """(left, top, right, bottom) pixels of the arena, its walls and ``margin`` metres in the
    task's top-down picture of ``img_size`` (width, height), clipped to the picture."""
    arena = env.unwrapped.world.arena
    grow = arena.wall_thickness + margin
    px = env.unwrapped.top_down_pixel
    (c0, r0) = px(arena.x_range[0] - grow, arena.y_range[1] + grow)
    (c1, r1) = px(arena.x_range[1] + grow, arena.y_range[0] - grow)
    return max(0, int(c0)), max(0, int(r0)), min(img_size[0], int(np.ceil(c1))), min(img_size[1], int(np.ceil(r1)))


def crop_to_arena(env, img: Image.Image, margin: float = 0.3) -> Image.Image:
    """``img`` (the task's top-down picture) cropped to ``arena_box``."""
    return img.crop(arena_box(env, img.size, margin))


def sample_world_picture(env, world_seed: int, size: int = SAMPLE_SIZE, reset_seed: int = SAMPLE_RESET_SEED) -> Image.Image:
    """The annotated top-down picture of world ``world_seed`` of ``env`` (a ``DynNav-Procedural-v1``
    of some difficulty and split) after ``reset(seed=reset_seed)``, cropped to the arena, with
    its longer side ``size`` pixels."""
    env.reset(seed=reset_seed, options={"world_seed": world_seed})
    img = crop_to_arena(env, annotated_top_down(env))
    scale = size / max(img.size)
    return img.resize((max(1, round(img.width * scale)), max(1, round(img.height * scale))), Image.LANCZOS)


def sample_world_path(out: Path, difficulty: str, split: str, world_seed: int) -> Path:
    """Where ``write_sample_worlds`` puts the picture of one sample world."""
    return Path(out) / f"procedural-{difficulty}-{split}-{world_seed}.png"


def write_sample_worlds(out: Path, samples: dict = SAMPLE_WORLDS, size: int = SAMPLE_SIZE) -> list[Path]:
    """Write the picture of every sample world of ``samples`` (difficulty -> (split, world seed)
    pairs) into ``out``; returns the paths."""
    import dynnav_tasks

    paths = []
    for difficulty, pairs in samples.items():
        for split in dict.fromkeys(split for split, _ in pairs):
            env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(PROCEDURAL_TASK, difficulty=difficulty, split=split))
            try:
                for seed in (seed for s, seed in pairs if s == split):
                    path = sample_world_path(out, difficulty, split, seed)
                    save_png(sample_world_picture(env, seed, size), path)
                    paths.append(path)
            finally:
                env.close()
    return paths


def crowd_picture(scenario: str, seed: int = 0, humans: int = 10) -> Image.Image:
    """The annotated top-down picture of the crowd task's ``scenario`` with ``humans`` pedestrians,
    ``CROWD_STEPS`` steps into episode ``seed`` (the robot turning in place), cropped to the arena."""
    return _picture_after_steps(CROWD_TASK, seed, scenario=scenario, humans=humans)


def map_picture(seed: int = 0) -> Image.Image:
    """The annotated top-down picture of the shipped office map with 3 moving boxes and 4
    pedestrians, ``CROWD_STEPS`` steps into episode ``seed``, cropped to the arena."""
    return _picture_after_steps(MAP_TASK, seed, moving_obstacles=3, pedestrians=4)


def _picture_after_steps(task_id: str, seed: int, **options) -> Image.Image:
    """``task_id`` made with ``options``, ``CROWD_STEPS`` steps (turning in place) into episode
    ``seed``: its annotated top-down picture cropped to the arena."""
    import dynnav_tasks

    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task_id, **options))
    try:
        env.reset(seed=seed)
        for _ in range(CROWD_STEPS):
            env.step(1)
        return crop_to_arena(env, annotated_top_down(env))
    finally:
        env.close()


def save_png(img: Image.Image, path: Path) -> None:
    """Write ``img`` to ``path`` as an optimised PNG, atomically (a temporary file beside it,
    renamed over it)."""
    data = io.BytesIO()
    img.save(data, format="PNG", optimize=True)
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_bytes(data.getvalue())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def camera_strip(task_id: str, seed: int, frames: int = 6, every: int = 4, scale: int = 4) -> Image.Image:
    """Front-camera frames of one episode driven by the camera-only pilot, side by side."""
    import dynnav_tasks
    from dynnav_tasks.baselines.camera_pilot import CameraPilot

    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task_id, obs_mode="rgb"))
    obs, _ = env.reset(seed=seed)
    base, shots, step = env.unwrapped, [obs], 0
    pilot = CameraPilot(camera=base.camera_spec)
    while len(shots) < frames:
        obs, _, terminated, truncated, _ = env.step(pilot.act(obs))
        step += 1
        if step % every == 0 or terminated or truncated:
            shots.append(obs)
        if terminated or truncated:
            break
    env.close()
    size, gap = base.camera_spec.size * scale, 4
    strip = Image.new("RGB", (len(shots) * (size + gap) - gap, size), (255, 255, 255))
    for i, shot in enumerate(shots):
        strip.paste(Image.fromarray(shot).resize((size, size), Image.NEAREST), (i * (size + gap), 0))
    return strip


def main(args: Args) -> None:
    """Write every task's picture and the camera worlds' frame strips (``--worlds tasks``) and
    the procedural sample worlds (``--worlds procedural``) into ``args.out``."""
    import dynnav_tasks

    args.out.mkdir(parents=True, exist_ok=True)
    if args.worlds in ("all", "map"):
        path = args.out / f"{MAP_TASK}-office.png"
        save_png(map_picture(args.seed), path)
        print(f"wrote {path}")
    if args.worlds == "map":
        return
    if args.worlds in ("all", "crowd"):
        from dynnav_tasks.tasks.crowd import SCENARIOS

        for scenario in SCENARIOS:
            path = args.out / f"{CROWD_TASK}-{scenario}.png"
            save_png(crowd_picture(scenario, args.seed), path)
            print(f"wrote {path}")
    if args.worlds == "crowd":
        return
    if args.worlds in ("all", "procedural"):
        for path in write_sample_worlds(args.out):
            print(f"wrote {path}")
    if args.worlds == "procedural":
        return
    for task_id in dynnav_tasks.TASK_IDS:
        env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task_id))
        env.reset(seed=args.seed)
        path = args.out / f"{task_id}.png"
        save_png(annotated_top_down(env), path)
        print(f"wrote {path}")
        env.close()
    for task_id in dynnav_tasks.VISUAL_TASK_IDS:
        path = args.out / f"{task_id}-camera.png"
        save_png(camera_strip(task_id, args.seed), path)
        print(f"wrote {path}")


if __name__ == "__main__":
    main(tyro.cli(Args))
