"""One module per registered task (thesis world)."""

from .moving_obstacles import MovingObstaclesEnv
from .moving_target import MovingTargetEnv

__all__ = ["MovingObstaclesEnv", "MovingTargetEnv"]
