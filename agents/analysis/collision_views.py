"""Where the obstacle that ended each collision was, seen from the robot: inside the front
camera's view or beside and behind it.

    python -m agents.analysis.collision_views RUN_DIR [RUN_DIR ...] [--before 5]

Reads each run's ``eval.json`` and, for every test episode that ended in a collision, replays
its moving obstacles: the task is reset with the episode's seed and the robot turns in place
for as many steps as the episode took. That gives the obstacles' true positions because their
motions are drawn at reset and never depend on the robot (``tests/test_collision_views.py``
checks it). The robot's heading is not in the trajectory, so it is taken from its motion: the
direction from the last point at least ``MIN_MOVE`` m behind. An obstacle is in view when its
centre's bearing lies within half the camera's field of view (``CameraSpec.fov``).
"""

from __future__ import annotations

import argparse
import math
from collections import Counter
from pathlib import Path

import numpy as np

from agents.analysis.outcomes import load_evals

MIN_MOVE = 0.05  # m
TURN_IN_PLACE = 1  # the robot's "left" action (dynnav_tasks/robot.py)


def motion_heading(trajectory, k: int, min_move: float = MIN_MOVE) -> float | None:
    """Heading (rad) at point ``k``: the direction to it from the latest earlier point at least
    ``min_move`` m away, or None if the robot never moved that far before ``k``."""
    x, y = trajectory[k]
    for j in range(k - 1, -1, -1):
        dx, dy = x - trajectory[j][0], y - trajectory[j][1]
        if dx * dx + dy * dy >= min_move * min_move:
            return math.atan2(dy, dx)
    return None


def relative_bearing(robot_xy, heading: float, point) -> float:
    """Bearing (deg) of ``point`` from a robot at ``robot_xy`` facing ``heading``, in (-180, 180]:
    positive to its left."""
    angle = math.atan2(point[1] - robot_xy[1], point[0] - robot_xy[0]) - heading
    wrapped = math.degrees(math.atan2(math.sin(angle), math.cos(angle)))
    return 180.0 if wrapped == -180.0 else wrapped


def replay_obstacles(env, seed: int, steps: int) -> np.ndarray:
    """(steps + 1, m, 2) centres of the task's moving obstacles after reset(seed) and each step."""
    env.reset(seed=seed)
    positions = [env.unwrapped.snapshot.moving_obstacle_xy.copy()]
    for _ in range(steps):
        env.step(TURN_IN_PLACE)
        positions.append(env.unwrapped.snapshot.moving_obstacle_xy.copy())
    return np.array(positions)


def collision_views(run_dirs: list[str | Path], before: int = 5) -> list[dict]:
    """One record per collision test episode of the runs: the moving obstacle nearest the robot at
    the end, its distance (m) and its bearing (deg) at the end and ``before`` steps earlier."""
    import gymnasium as gym

    import dynnav_tasks  # noqa: F401  (registers the tasks)

    task, evals = load_evals(run_dirs)
    env = gym.make(task)
    records = []
    try:
        for run, e in evals:
            for ep in e["episodes"]:
                if ep["outcome"] != "collision" or not ep.get("trajectory"):
                    continue
                path = ep["trajectory"]
                boxes = replay_obstacles(env, ep["seed"], len(path) - 1)
                if boxes.shape[1] == 0:
                    raise ValueError(f"{e['task']} has no moving obstacles")
                end = len(path) - 1
                nearest = int(np.argmin(np.linalg.norm(boxes[end] - np.asarray(path[end]), axis=1)))
                bearings = {}
                for label, k in (("end", end), ("before", max(end - before, 0))):
                    h = motion_heading(path, k)
                    bearings[label] = None if h is None else relative_bearing(path[k], h, boxes[k, nearest])
                records.append(dict(run=str(run), seed=ep["seed"], obstacle=nearest,
                                    distance=float(np.linalg.norm(boxes[end, nearest] - np.asarray(path[end]))),
                                    bearing_end=bearings["end"], bearing_before=bearings["before"]))
    finally:
        env.close()
    return records


def summarize(records: list[dict], half_fov_deg: float, near: float, before: int) -> str:
    """Counts over the collisions whose nearest moving obstacle is within ``near`` m at the end."""
    touching = [r for r in records if r["distance"] <= near]
    per_obstacle = Counter(r["obstacle"] for r in touching)

    def out_of_view(key):
        return sum(1 for r in touching if r[key] is not None and abs(r[key]) > half_fov_deg)

    lines = [f"collisions: {len(records)}",
             f"with a moving obstacle within {near} m at the end: {len(touching)} "
             f"(by obstacle index: {dict(sorted(per_obstacle.items()))})",
             f"of those, that obstacle outside the {2 * half_fov_deg:.0f} deg view at the end: {out_of_view('bearing_end')}, "
             f"{before} steps before: {out_of_view('bearing_before')}"]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    from dynnav_tasks.camera import CameraSpec

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="run directories (with eval.json)")
    parser.add_argument("--before", type=int, default=5, help="steps before the end for the second bearing")
    parser.add_argument("--near", type=float, default=0.7,
                        help="distance (m, centre to centre) within which the nearest obstacle counts as the one hit")
    args = parser.parse_args(argv)
    if args.before < 1:
        parser.error(f"--before must be at least 1, got {args.before}")
    try:
        records = collision_views(args.runs, args.before)
    except (FileNotFoundError, ValueError) as err:
        raise SystemExit(f"agents.analysis.collision_views: {err}") from None
    print(summarize(records, math.degrees(CameraSpec().fov / 2), args.near, args.before))


if __name__ == "__main__":
    main()
