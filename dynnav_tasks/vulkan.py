"""Is there a Vulkan device SAPIEN can render with? If not, say how to get one.

SAPIEN (and ManiSkill, which creates render materials even with rendering off) needs a
Vulkan driver. With no GPU, Mesa's lavapipe renders on the CPU, but Debian 12's stock Mesa
(22.3) is too old; the one in bookworm-backports (25.x) works.

    python -m dynnav_tasks.vulkan     # renders one tiny frame; exit code 0 if it worked
"""

from __future__ import annotations

import sys

INSTALL_HINT = """\
SAPIEN found no working Vulkan device. On Debian 12 with no GPU, install Mesa's CPU
renderer (lavapipe) from bookworm-backports, as root:

    echo 'deb http://deb.debian.org/debian bookworm-backports main' > /etc/apt/sources.list.d/bookworm-backports.list
    apt-get update
    apt-get install -y -t bookworm-backports mesa-vulkan-drivers libvulkan1

(`make test` and `make demo` do this themselves when run as root.)"""


_PIPELINE_KEEPERS: dict[str, object] = {}


def keep_render_pipelines(device) -> None:
    """Keep SAPIEN's compiled render pipelines for the rest of the process.

    SAPIEN frees its render context, and with it every compiled pipeline, when the last
    ``RenderSystem`` of the process is gone; lavapipe then spends about 20 s compiling them
    again for the next camera task (an evaluation after training, the next test in a suite).
    One empty ``RenderSystem`` on ``device``, kept here, keeps them."""
    import sapien

    key = str(device)
    if key not in _PIPELINE_KEEPERS:
        _PIPELINE_KEEPERS[key] = sapien.render.RenderSystem(device)


class VulkanUnavailableError(RuntimeError):
    """Raised when no Vulkan device can be created; the message says how to install one."""


def explain(err: BaseException) -> VulkanUnavailableError:
    return VulkanUnavailableError(f"{INSTALL_HINT}\n\nThe renderer said: {err}")


def is_vulkan_error(err: BaseException) -> bool:
    text = str(err)
    return any(key in text for key in ("vk::", "Vulkan", "ErrorFeatureNotPresent", "ErrorIncompatibleDriver", "ErrorInitializationFailed"))


def render_test_frame(device: str = "cpu") -> tuple[float, float, float]:
    """Render an 8x8 frame of a red box under white light; return the centre pixel's RGB."""
    import sapien

    sapien.render.set_camera_shader_dir("minimal")
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem(), sapien.render.RenderSystem(device)])
    builder = scene.create_actor_builder()
    builder.add_box_visual(half_size=[0.5, 0.5, 0.5], material=sapien.render.RenderMaterial(base_color=[1, 0, 0, 1]))
    builder.build_static()
    scene.set_ambient_light([1, 1, 1])
    camera = scene.add_camera("check", 8, 8, 1.0, 0.01, 10.0)
    camera.entity.set_pose(sapien.Pose([-3, 0, 0]))
    scene.update_render()
    camera.take_picture()
    rgb = camera.get_picture("Color")[4, 4, :3]
    return tuple(float(c) for c in rgb)


def main(argv: list[str] | None = None) -> int:
    try:
        rgb = render_test_frame()
    except RuntimeError as err:
        print(explain(err), file=sys.stderr)
        return 1
    if not (rgb[0] > 0.5 and rgb[1] < 0.2 and rgb[2] < 0.2):
        print(f"{INSTALL_HINT}\n\nA test frame rendered, but wrongly: centre pixel {rgb}, expected red.", file=sys.stderr)
        return 1
    print("Vulkan rendering works (SAPIEN device 'cpu').")
    return 0


if __name__ == "__main__":
    sys.exit(main())
