"""One module per registered task: the thesis's worlds in the thesis's order, then the
procedural worlds, the crowd and the building maps."""

from .one_obstacle import OneObstacleEnv  # 5.1
from .moving_target import MovingTargetEnv  # 5.2
from .moving_obstacles import MovingObstaclesEnv  # 5.3
from .motion_areas import MotionAreasEnv  # 5.4a
from .motion_areas_route import MotionAreasRouteEnv  # 5.4b
from .overlapping_areas import OverlappingAreasEnv  # 5.4c
from .visual_static_target import VisualStaticTargetEnv  # 5.5a
from .visual_targets import VisualTargetsEnv  # 5.5b
from .visual_moving_targets import VisualMovingTargetsEnv  # 5.5c
from .procedural import ProceduralEnv  # generated worlds
from .crowd import CrowdEnv  # pedestrians
from .building_map import MapEnv  # occupancy maps

__all__ = [
    "OneObstacleEnv", "MovingTargetEnv", "MovingObstaclesEnv", "MotionAreasEnv", "MotionAreasRouteEnv",
    "OverlappingAreasEnv", "VisualStaticTargetEnv", "VisualTargetsEnv", "VisualMovingTargetsEnv", "ProceduralEnv",
    "CrowdEnv", "MapEnv",
]
