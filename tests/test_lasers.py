"""Laser readings against distances to walls and boxes worked out for placed robot poses."""

import math

import numpy as np
import pytest


def test_axis_rays_hand_computed(make_env):
    """Robot at (1.1, -0.2) in world 5.2 (walls at x=-2, 4.5 and y=-2, 4.5; 0.5 m boxes
    centred at (1.1, 1.1) and (1.2, -0.8)). Facing east, ray 0 points east, 4 north,
    8 west and 12 south."""
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    base = env.unwrapped
    east, north, west, south = 4.5 - 1.1, 0.85 - (-0.2), 1.1 - (-2.0), -0.2 - (-0.55)
    assert (east, north, west, south) == pytest.approx((3.4, 1.05, 3.1, 0.35))

    obs = base.place_robot(1.1, -0.2, 0.0)
    np.testing.assert_allclose(obs[[0, 4, 8, 12]], [east, north, west, south], atol=1e-3)
    # ray 2 (45 deg) meets the east wall: 3.4 / cos 45
    np.testing.assert_allclose(obs[2], 3.4 * math.sqrt(2), atol=1e-3)

    obs = base.place_robot(1.1, -0.2, math.pi / 2)  # facing north: the ring turns with it
    np.testing.assert_allclose(obs[[0, 4, 8, 12]], [north, west, south, east], atol=1e-3)


def test_readings_are_capped_at_5m(make_env):
    env = make_env("DynNav-MovingTarget-v1")
    env.reset(seed=0)
    obs = env.unwrapped.place_robot(0.0, -1.5, math.pi / 2)  # north: 6 m of free floor
    assert obs[0] == pytest.approx(5.0)
    assert obs.max() <= 5.0


def _ray_box(origin, direction, center, half):
    """Entry distance of a ray into an axis-aligned rectangle (slab method), or inf."""
    t0, t1 = -math.inf, math.inf
    for k in range(2):
        lo, hi = center[k] - half[k], center[k] + half[k]
        if abs(direction[k]) < 1e-12:
            if not lo <= origin[k] <= hi:
                return math.inf
            continue
        a, b = (lo - origin[k]) / direction[k], (hi - origin[k]) / direction[k]
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    return t0 if t1 >= t0 >= 0 else math.inf


def test_all_rays_match_geometry_at_random_poses(make_env, task_id):
    """Every ray of random collision-free poses in every world, moving obstacles included,
    against an independent ray-rectangle intersection of the task's own geometry."""
    env = make_env(task_id)
    base = env.unwrapped
    rng = np.random.default_rng(7)
    (x0, x1), (y0, y1) = base.world.arena.x_range, base.world.arena.y_range
    checked = 0
    for seed in range(3):
        env.reset(seed=seed)
        for _ in range(3):
            env.step(1)  # spin in place while the obstacles move on
        walls = list(base.world.arena.walls().values())
        snap = base.snapshot
        obstacles = list(zip(snap.obstacle_xy, snap.obstacle_half))
        while True:
            x, y = rng.uniform(x0 + 0.3, x1 - 0.3), rng.uniform(y0 + 0.3, y1 - 0.3)
            if all(max(abs(x - c[0]) - h[0], abs(y - c[1]) - h[1]) > 0.35 for c, h in obstacles):
                break
        yaw = rng.uniform(-math.pi, math.pi)
        got = base.place_robot(x, y, yaw)[:16]
        for k in range(16):
            a = yaw + 2 * math.pi * k / 16
            d = (math.cos(a), math.sin(a))
            expected = min(min(_ray_box((x, y), d, c, h) for c, h in walls + obstacles), 5.0)
            assert got[k] == pytest.approx(expected, abs=2e-3), (seed, k, x, y, yaw)
            checked += 1
    assert checked == 48
