"""Pictures of every task, rendered by the task itself, for the README.

    python -m dynnav_tasks.viz.pictures --out docs/images

``<task>.png``: the task's top-down camera (all candidate targets shown as red discs) with
the targets' motion (dark red: segments, or the areas they wander in), the obstacles' motion
(orange: routes with arrows, or the areas their boxes can cover) and the start area (white).

``<task>-camera.png`` (camera worlds): what the robot's front camera sees (32x32, shown
enlarged) every 4 steps while ``camera_pilot.CameraPilot``, which reads only these frames,
drives to the target.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tyro
from PIL import Image, ImageDraw

from dynnav_tasks.motion import BackAndForth, RandomInRect, Route

TARGET_PATH = (120, 0, 0)
OBSTACLE_PATH = (255, 140, 0)
START_AREA = (255, 255, 255)


@dataclass
class Args:
    out: Path = Path("docs/images")
    """folder to write <task>.png into"""
    seed: int = 0
    """reset seed of the pictured episode"""


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
    s = base.world.start
    (c0, r0), (c1, r1) = px(s.x_range[0], s.y_range[1]), px(s.x_range[1], s.y_range[0])
    draw.rectangle([c0, r0, c1, r1], outline=START_AREA, width=2)
    return img


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
    """Write every task's picture, and the camera worlds' frame strips, into ``args.out``."""
    import dynnav_tasks

    args.out.mkdir(parents=True, exist_ok=True)
    for task_id in dynnav_tasks.TASK_IDS:
        env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task_id))
        env.reset(seed=args.seed)
        path = args.out / f"{task_id}.png"
        annotated_top_down(env).save(path)
        print(f"wrote {path}")
        env.close()
    for task_id in dynnav_tasks.VISUAL_TASK_IDS:
        path = args.out / f"{task_id}-camera.png"
        camera_strip(task_id, args.seed).save(path)
        print(f"wrote {path}")


if __name__ == "__main__":
    main(tyro.cli(Args))
