"""The robot as a ManiSkill agent: ``DiffBot``, loaded from ``assets/diffbot/diffbot.urdf``,
with the control modes of ``drive.py`` (the discrete drive of ``robot.py`` and the velocity
drive). Tasks name it by ``DiffBot.uid``."""

from __future__ import annotations

import numpy as np
from mani_skill.agents.base_agent import BaseAgent
from mani_skill.agents.registration import register_agent

from .drive import controller_configs
from .maniskill_adapter import sapien_object
from .robot import ASSET_DIR, DriveConfig


@register_agent()
class DiffBot(BaseAgent):
    """A Pioneer-like differential-drive robot with a laser ring (16 rays unless the task
    says otherwise, ``lasers.py``) and a front camera."""

    uid = "dynnav_diffbot"
    urdf_path = str(ASSET_DIR / "diffbot.urdf")
    fix_root_link = True
    disable_self_collisions = True
    drive_config: DriveConfig = DriveConfig()

    @property
    def _controller_configs(self):
        return controller_configs(self.drive_config)

    def pose2d(self) -> np.ndarray:
        """(x, y, yaw) of the chassis in the world, as numpy."""
        return np.asarray(sapien_object(self.robot).get_qpos()[:3], dtype=np.float64)

    def set_pose2d(self, x: float, y: float, yaw: float) -> None:
        """Place the robot at (x, y) facing ``yaw`` (radians), at rest."""
        art = sapien_object(self.robot)
        art.set_qpos(np.array([x, y, yaw], dtype=np.float32))
        art.set_qvel(np.zeros(3, dtype=np.float32))
