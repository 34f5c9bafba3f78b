"""Observation scaling: each bounded component of a state vector mapped to [-1, 1] (the DQN's inputs)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np


class ObsScaler:
    """Maps each bounded state component from [low, high] to [-1, 1]; unbounded ones pass unchanged.

    dynnav states mix laser ranges (0-5 m) and coordinates (about -2 to 4.5 m); the bounds
    come from the task's observation space, so the same task always scales the same way.
    """

    def __init__(self, space: gym.spaces.Box, enabled: bool = True):
        low, high = space.low.astype(np.float64), space.high.astype(np.float64)
        bounded = np.isfinite(low) & np.isfinite(high) & (high > low) & enabled
        low, high = np.where(bounded, low, -1.0), np.where(bounded, high, 1.0)
        mid, half = (low + high) / 2, (high - low) / 2
        self.offset = mid.astype(np.float32)
        self.scale = (1.0 / half).astype(np.float32)

    def __call__(self, obs):
        return (obs - self.offset) * self.scale
