"""Cost of opening a camera task: seconds from ``make`` to the first frame, for a first camera
task in a process and for a second one opened after the first was closed, with dynnav's
render-pipeline keeper (``dynnav_tasks.vulkan.keep_render_pipelines``) and without it
(the baseline, SAPIEN's default: its render context, compiled pipelines included, goes with
the last render system). Each case runs in a fresh process pinned to one core.

    python benchmarks/camera_startup.py [--task DynNav-VisualStaticTarget-v1]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

from machine import describe, pin_one_core

CHILD = r"""
import gc, json, os, sys, time
os.environ.setdefault("MS_RENDERER_LOG_LEVEL", "error")
import dynnav_tasks

task, keep = sys.argv[1], sys.argv[2] == "1"
if not keep:
    import dynnav_tasks.nav_env as nav_env
    nav_env.keep_render_pipelines = lambda device: None
times = []
for _ in range(2):
    start = time.perf_counter()
    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task, obs_mode="rgb"))
    env.reset(seed=0)
    times.append(time.perf_counter() - start)
    env.close()
    del env
    gc.collect()
print(json.dumps(times))
"""


def run_case(task: str, keep: bool) -> list[float]:
    """Open, render and close ``task`` twice in a new process (it inherits this one's core)."""
    out = subprocess.run([sys.executable, "-c", CHILD, task, "1" if keep else "0"], capture_output=True,
                         text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="DynNav-VisualStaticTarget-v1", help="a camera task")
    args = parser.parse_args()
    print(describe(pin_one_core()))
    print(f"{'case':<34} {'first camera task (s)':>22} {'second, after close (s)':>24}")
    for name, keep in (("SAPIEN's default (baseline)", False), ("dynnav (pipelines kept)", True)):
        first, second = run_case(args.task, keep)
        print(f"{name:<34} {first:>22.1f} {second:>24.1f}")


if __name__ == "__main__":
    main()
