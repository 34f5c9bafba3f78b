"""Per-episode schedules of the exploration rate and the learning rate."""

from __future__ import annotations

import math


def interpolate(start: float, end: float, fraction: float, kind: str) -> float:
    """``start`` at fraction 0 to ``end`` at fraction 1 (clamped), linearly or geometrically."""
    f = min(max(fraction, 0.0), 1.0)
    if kind == "linear":
        return start + (end - start) * f
    if kind == "exponential":
        if start <= 0 or end <= 0:
            raise ValueError(f"an exponential schedule needs positive end points, got {start} -> {end}")
        return start * math.exp(math.log(end / start) * f)
    raise ValueError(f"unknown schedule {kind!r}; valid: linear, exponential")


def epsilon_at(config, episode: int) -> float:
    """1 during the random episodes, then epsilon_start -> epsilon_end over epsilon_decay_episodes."""
    if episode < config.random_episodes:
        return 1.0
    decay = max(config.epsilon_decay_episodes, 1)
    return interpolate(config.epsilon_start, config.epsilon_end,
                       (episode - config.random_episodes) / decay, config.epsilon_schedule)


def learning_rate_at(config, episode: int) -> float:
    """learning_rate, or learning_rate -> learning_rate_end over lr_decay_episodes."""
    if config.lr_schedule == "constant":
        return config.learning_rate
    return interpolate(config.learning_rate, config.learning_rate_end,
                       episode / config.lr_decay_episodes, config.lr_schedule)
