"""The top-down picture of a task's arena: ManiSkill's human-render camera, looking down."""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
import sapien
from mani_skill.sensors.camera import CameraConfig
from mani_skill.utils import sapien_utils


class TopDownView:
    """Mixed into ``NavEnv``: the camera over the arena, its pixel mapping and its picture."""

    TOP_DOWN_SIZE: ClassVar[int] = 512
    TOP_DOWN_HEIGHT: ClassVar[float] = 12.0

    def _top_down_half_extent(self) -> float:
        """Half the width of floor (m) the top-down picture covers."""
        arena = self.world.arena
        return float(max(arena.size)) / 2 + arena.wall_thickness + 0.3

    @property
    def _default_human_render_camera_configs(self):
        """A top-down camera over the whole arena (image right = +x, image up = +y)."""
        cx, cy = self.world.arena.center
        h = self.TOP_DOWN_HEIGHT
        pose = sapien_utils.look_at(eye=[cx, cy, h], target=[cx, cy, 0.0], up=[0, 1, 0])
        fov = 2 * math.atan(self._top_down_half_extent() / h)
        n = self.TOP_DOWN_SIZE
        return CameraConfig("top_down", pose=pose, width=n, height=n, fov=fov, near=0.1, far=2 * h)

    def top_down_pixel(self, x: float, y: float) -> tuple[float, float]:
        """(column, row) of the floor point (x, y) in the top-down picture."""
        cx, cy = self.world.arena.center
        half, n = self._top_down_half_extent(), self.TOP_DOWN_SIZE
        return n / 2 + (x - cx) / half * n / 2, n / 2 - (y - cy) / half * n / 2

    def render_top_down(self, show_all_targets: bool = False) -> np.ndarray:
        """An RGB picture (H, W, 3) uint8 of the whole arena seen from above.

        With ``show_all_targets`` every candidate target's disc is drawn at its current
        position, not only the chosen one's.
        """
        hidden = []
        if show_all_targets:
            for t, (mover, entity) in enumerate(self._targets):
                if t != self._target_index:
                    p = entity.pose.p
                    hidden.append((entity, sapien.Pose(p)))
                    entity.set_pose(sapien.Pose([p[0], p[1], 0.0]))
        try:
            return self.render_rgb_array("top_down")[0].cpu().numpy()
        finally:
            for entity, pose in hidden:
                entity.set_pose(pose)
