"""Cost of Rerun recording: steps/s of a random policy with and without a Recorder
writing every step to a .rrd file, for a laser world and a camera world, measured in the
same run on one core.

    python benchmarks/recording_overhead.py [--steps 3000]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from machine import cpu_name, pin_one_core


def steps_per_second(task_id: str, steps: int, obs_mode: str, record_to: Path | None) -> tuple[float, float]:
    import dynnav_tasks
    from dynnav_tasks.viz.recording import Recorder

    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task_id, obs_mode=obs_mode))
    recorder = Recorder(record_to) if record_to is not None else None
    rng = np.random.default_rng(0)
    env.reset(seed=0)
    if recorder:
        recorder.start_episode(env)
    t0 = time.perf_counter()
    for _ in range(steps):
        action = int(rng.integers(3))
        _, reward, terminated, truncated, info = env.step(action)
        if recorder:
            recorder.log_step(env, action=action, reward=float(reward))
        if terminated or truncated:
            if recorder:
                recorder.end_episode(info)
            env.reset()
            if recorder:
                recorder.start_episode(env)
    if recorder:
        recorder.close()
    rate = steps / (time.perf_counter() - t0)
    env.close()
    size = record_to.stat().st_size / 1e6 if record_to is not None else 0.0
    return rate, size


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=3000)
    args = parser.parse_args()
    pinned = pin_one_core()
    print(f"machine: {cpu_name()}, {os.cpu_count()} cores ({pinned})")
    print(f"{args.steps} random steps per figure, resets included\n")
    print(f"{'task':<40} {'obs':<10} {'off steps/s':>11} {'on steps/s':>10} {'overhead':>9} {'MB/1k steps':>11}")
    with tempfile.TemporaryDirectory() as tmp:
        for task_id, obs_mode in [("DynNav-MovingObstacles-v1", "state"), ("DynNav-VisualTargets-v1", "rgb+state")]:
            off, _ = steps_per_second(task_id, args.steps, obs_mode, None)
            on, size = steps_per_second(task_id, args.steps, obs_mode, Path(tmp) / f"{task_id}.rrd")
            print(f"{task_id:<40} {obs_mode:<10} {off:>11.0f} {on:>10.0f} {1e3 / on - 1e3 / off:>7.2f}ms "
                  f"{size / args.steps * 1e3:>11.2f}")


if __name__ == "__main__":
    main()
