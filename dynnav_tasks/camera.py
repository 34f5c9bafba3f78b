"""The robot's front RGB camera.

Mounted on the robot's ``camera_link`` (0.19 m ahead of the centre, 0.36 m up), looking
straight ahead and tilted down by ``pitch`` (0.45 rad, about 26 deg), with a field of view of
``fov`` (1.2 rad, about 69 deg, both ways: the image is square). It renders with SAPIEN's
minimal shader.

The tilt puts the pixels where the information is: everything the robot meets stands on the
floor and is at most 0.5 m high (walls, boxes) except the target's 1.2 m marker, so the image
spans from 0.15 rad above the horizon (the marker's top from 6 m away, the walls' tops from
1 m) down to 1.05 rad below it (the floor from 0.2 m ahead of the lens). At 32x32 that leaves
about three rows of sky above distant walls (at 0.2 rad of tilt it was ten).

By default it renders directly at the observation size (32x32), which is cheap. The thesis
rendered 640x640 and shrank the frames to 32x32; ``camera_render_size=640`` does that: the
frame is rendered at 640x640 and each 20x20 block is averaged into one pixel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import sapien
from mani_skill.sensors.camera import CameraConfig

FRONT_CAMERA = "front_camera"


@dataclass(frozen=True)
class CameraSpec:
    """Size and optics of the front camera."""

    size: int = 32
    """side of the square image in observations (pixels)"""
    render_size: Optional[int] = None
    """side rendered before averaging down to ``size`` (None: render at ``size``)"""
    fov: float = 1.2
    """vertical field of view (rad)"""
    pitch: float = 0.35
    """downward tilt (rad)"""

    MAX_SIZE = 512
    MAX_RENDER_SIZE = 2048

    def __post_init__(self):
        if isinstance(self.size, bool) or not isinstance(self.size, (int, np.integer)) or not 8 <= self.size <= self.MAX_SIZE:
            raise ValueError(f"camera_size must be an integer from 8 to {self.MAX_SIZE} (32 in the thesis), got {self.size!r}")
        if self.render_size is not None and (
            isinstance(self.render_size, bool) or not isinstance(self.render_size, (int, np.integer))
            or not self.size <= self.render_size <= self.MAX_RENDER_SIZE
        ):
            raise ValueError(
                f"camera_render_size must be an integer from camera_size ({self.size}) to "
                f"{self.MAX_RENDER_SIZE}, got {self.render_size!r}"
            )
        if self.render_size is not None and self.render_size % self.size:
            raise ValueError(
                f"camera_render_size ({self.render_size}) must be a multiple of camera_size ({self.size}), "
                "e.g. 640 for 32"
            )

    @property
    def rendered(self) -> int:
        return self.render_size or self.size

    def config(self, mount) -> CameraConfig:
        # rotation about the camera's y (left) axis by +pitch turns its x (forward) axis down
        half = self.pitch / 2
        pose = sapien.Pose([0, 0, 0], [math.cos(half), 0, math.sin(half), 0])
        n = self.rendered
        return CameraConfig(FRONT_CAMERA, pose=pose, width=n, height=n, fov=self.fov, near=0.01, far=20.0,
                            mount=mount, shader_pack="minimal")

    def pixel_rays(self) -> np.ndarray:
        """Direction of each pixel centre's ray in the robot's frame (forward, left, up): (size, size, 3).

        The pinhole model the renderer uses: row 0 is the top of the image, column 0 its left
        (the robot's left); the rays are not normalised (the optical axis has length 1)."""
        n = self.size
        t = math.tan(self.fov / 2)
        u = ((np.arange(n) + 0.5) / n * 2 - 1) * t  # image x, right positive
        v = (1 - (np.arange(n) + 0.5) / n * 2) * t  # image y, up positive
        c, s = math.cos(self.pitch), math.sin(self.pitch)
        rays = np.empty((n, n, 3))
        rays[..., 0] = c + s * v[:, None]  # the camera ray (1, -u, v) tilted down by the pitch
        rays[..., 1] = -u[None, :]
        rays[..., 2] = -s + c * v[:, None]
        return rays

    def shrink(self, rgb: np.ndarray) -> np.ndarray:
        """Average ``rendered`` x ``rendered`` down to ``size`` x ``size`` (uint8 in, uint8 out)."""
        k = self.rendered // self.size
        if k == 1:
            return rgb
        blocks = rgb.reshape(self.size, k, self.size, k, 3).astype(np.float32)
        return (blocks.mean(axis=(1, 3)) + 0.5).astype(np.uint8)
