"""The tasks render themselves from above (one process: lavapipe's first frame is slow)."""

import numpy as np

from dynnav_tasks.world import WALL_COLORS


def _is_red(pixel):
    r, g, b = (int(c) for c in pixel)
    return r > 150 and g < 90 and b < 90


def _pixel(img, base, x, y):
    col, row = base.top_down_pixel(x, y)
    return img[int(round(row)), int(round(col))]


def test_top_down_shows_the_chosen_target_walls_and_robot(make_env):
    env = make_env("DynNav-MovingObstacles-v1", render_mode="rgb_array")
    obs, _ = env.reset(seed=5)
    base = env.unwrapped
    img = env.render()
    assert img.shape == (512, 512, 3) and img.dtype == np.uint8

    chosen = obs[18:20]
    other = [t.at for t in base.world.targets if not np.allclose(t.at, chosen)][0]
    assert _is_red(_pixel(img, base, *chosen))
    assert not _is_red(_pixel(img, base, *other))  # only the chosen target is shown

    all_targets = base.render_top_down(show_all_targets=True)
    assert _is_red(_pixel(all_targets, base, *other))
    assert not _is_red(_pixel(base.render_top_down(), base, *other))  # and hidden again

    # each wall in its own colour: the dominant channel of the middle of each wall's top
    (x0, x1), (y0, y1) = base.world.arena.x_range, base.world.arena.y_range
    mid_x, mid_y = (x0 + x1) / 2, (y0 + y1) / 2
    for side, (x, y) in {"north": (mid_x, y1 + 0.05), "south": (mid_x, y0 - 0.05),
                         "east": (x1 + 0.05, mid_y), "west": (x0 - 0.05, mid_y)}.items():
        got = _pixel(img, base, x, y).astype(float)
        want = np.array(WALL_COLORS[side][:3])
        assert np.corrcoef(got, want)[0, 1] > 0.9, (side, got, want)

    # the robot (dark grey) covers its own position; the floor around it is light
    x, y, _ = base.agent.pose2d()
    assert _pixel(img, base, x, y).mean() < 140
    assert _pixel(img, base, x + 0.6, y + 0.6).mean() > 170


def test_top_down_follows_a_moving_target(make_env):
    env = make_env("DynNav-MovingTarget-v1")
    obs, _ = env.reset(seed=1)
    base = env.unwrapped
    for _ in range(10):
        obs, *_ = env.step(1)
    img = base.render_top_down()
    assert _is_red(_pixel(img, base, *obs[18:20]))
