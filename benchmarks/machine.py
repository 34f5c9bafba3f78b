"""What a benchmark prints about the machine it ran on, and pinning to one core."""

from __future__ import annotations

import os
import platform
import time


def pin_one_core() -> str:
    """Run this process on one CPU core; say which."""
    if hasattr(os, "sched_setaffinity"):
        core = sorted(os.sched_getaffinity(0))[0]
        os.sched_setaffinity(0, {core})
        return f"pinned to core {core}"
    return "not pinned (no sched_setaffinity)"


def cpu_name() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def describe(pinned: str) -> str:
    """One line: CPU, cores, pinning, Python."""
    return f"machine: {cpu_name()}, {os.cpu_count()} cores ({pinned}), Python {platform.python_version()}"


def timed_steps(env, actions, on_end) -> float:
    """Seconds spent inside ``env.step`` over ``actions`` (resets excluded): ``on_end()`` is
    called, untimed, whenever an episode ends."""
    clock, spent = time.perf_counter, 0.0
    for a in actions:
        t0 = clock()
        _, _, terminated, truncated, _ = env.step(a)
        spent += clock() - t0
        if terminated or truncated:
            on_end()
    return spent
