"""Hand-written policies for tests/test_benchmark.py (``--policy bench_policies:...``)."""

import numpy as np

calls = {"reset": 0}


def toward_target(obs):
    """Drive forward when the target is ahead, else turn towards it (the egocentric state's
    target bearing: its sine and cosine after the lasers and the distance)."""
    sin_b, cos_b = float(obs[-2]), float(obs[-1])
    if cos_b > 0.97:
        return 0
    return 1 if sin_b > 0 else 2


def reset():
    calls["reset"] += 1


def wrong_action(obs):
    return 7


def velocity(obs):
    return np.array([0.5, 0.0], np.float32)
