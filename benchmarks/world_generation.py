"""World generation speed: milliseconds per ``generate_world`` call for every preset.

    python benchmarks/world_generation.py [--worlds 300]

For each difficulty and split (train, ood; test shares train's spec), with and without the
camera's visibility check, it generates ``--worlds`` worlds from consecutive seeds on one
pinned core and prints the mean, median and slowest time per world, and the mean numbers of
static blocks and moving boxes. Nothing is simulated: this is the generator alone.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from dynnav_tasks.generation import DIFFICULTIES, generate_world, spec_for  # noqa: E402
from machine import describe, pin_one_core  # noqa: E402


def main() -> None:
    """Time the presets and print one row each."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=300, help="worlds per preset (default 300)")
    args = parser.parse_args()
    if args.worlds < 1:
        parser.error("--worlds must be at least 1")
    print(describe(pin_one_core()))
    print(f"{'preset':<18} {'mean ms':>8} {'median':>8} {'max':>8} {'blocks':>7} {'moving':>7}")
    for difficulty in DIFFICULTIES:
        for split in ("train", "ood"):
            for camera in (False, True):
                spec = spec_for(difficulty, split, camera=camera)
                generate_world(spec, 10**6)  # warm up
                times, blocks, moving = [], 0, 0
                for seed in range(args.worlds):
                    start = time.perf_counter()
                    world = generate_world(spec, seed)
                    times.append((time.perf_counter() - start) * 1e3)
                    blocks += sum(not o.moving for o in world.obstacles)
                    moving += world.moving_obstacle_count
                name = f"{difficulty} {split}{' camera' if camera else ''}"
                print(
                    f"{name:<18} {statistics.fmean(times):8.2f} {statistics.median(times):8.2f} {max(times):8.2f} "
                    f"{blocks / args.worlds:7.1f} {moving / args.worlds:7.1f}"
                )


if __name__ == "__main__":
    main()
