"""ManiSkill's reward modes on the tasks: "dense" is the task's default reward, "normalized_dense"
is it divided by a bound that holds, "sparse" is ManiSkill's sparse reward but for the
per-step cost, "none" is no reward."""

import math

import gymnasium as gym
import numpy as np
import pytest
from mani_skill.envs.sapien_env import BaseEnv

import dynnav_tasks
from dynnav_tasks import rewards as R
from dynnav_tasks.robot import FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH
from dynnav_tasks.snapshot import take_snapshot
from dynnav_tasks.motion import Static
from dynnav_tasks.world import STANDARD_ARENA, Arena, StartArea, World

CLEARANCE = min(FOOTPRINT_HALF_LENGTH, FOOTPRINT_HALF_WIDTH)


def _pilot(snapshot, step: int) -> int:
    """Turn towards the target, else drive at it (reaches it in most episodes)."""
    if abs(snapshot.bearing) > math.pi / 12:
        return 1 if snapshot.bearing > 0 else 2
    return 0


def _random(seed):
    actions = np.random.default_rng(seed).integers(0, 3, size=200)
    return lambda snapshot, step: int(actions[step])


TASKS = ("DynNav-OneObstacle-v1", "DynNav-MovingObstacles-v1", "DynNav-OverlappingAreas-v1", "DynNav-VisualTargets-v1")
"""static, routed and wandering obstacles, and a camera world (every world's bound is the same)"""


def _episode_pairs(task_id, episodes):
    """Each (seed, policy) episode in "dense" and the same in "normalized_dense": per step, the
    dense reward, the default mode's reward of the same snapshots and the normalised reward;
    with the bound and the episode's outcome."""
    dense = dynnav_tasks.NumpyWrapper(gym.make(task_id, reward_mode="dense"))
    normalized = dynnav_tasks.NumpyWrapper(gym.make(task_id, reward_mode="normalized_dense"))
    base = dense.unwrapped
    assert normalized.unwrapped.reward_bound == base.reward_bound
    try:
        for seed, policy in episodes:
            rows, outcome = [], None
            dense.reset(seed=seed)
            normalized.reset(seed=seed)
            for step in range(200):
                prev = base.snapshot
                action = policy(prev, step)
                _, d, terminated, truncated, info = dense.step(action)
                _, n, *_ = normalized.step(action)
                default = R.compute_reward(R.DEFAULT_REWARD_MODE, prev, base.snapshot, base.reward_params,
                                           reached=info["success"], collided=info["collision"])
                rows.append((d, default, n))
                if terminated or truncated:
                    outcome = dynnav_tasks.outcome_of(info, terminated)
                    break
            yield np.array(rows), base.reward_bound, outcome
    finally:
        dense.close()
        normalized.close()


def test_dense_and_normalized_dense_step_by_step():
    """Episodes that end in success and in collision: "dense" is the default reward on every
    step, "normalized_dense" is it divided by the bound, and within [-1, 1]."""
    outcomes = set()
    for task_id in TASKS:
        for rows, bound, outcome in _episode_pairs(task_id, [(10, _pilot), (0, _random(1234))]):
            outcomes.add(outcome)
            assert bound == 20.0  # the +-20 of reaching and colliding dominate (rewards.py)
            dense, default, normalized = rows.T
            np.testing.assert_array_equal(dense, default)
            np.testing.assert_array_equal(normalized, dense / bound)
            assert np.all(np.abs(normalized) <= 1.0), (task_id, normalized.min(), normalized.max())
            if outcome in ("success", "collision"):
                assert normalized[-1] == (1.0 if outcome == "success" else -1.0)
    assert {"success", "collision"} <= outcomes, outcomes


@pytest.mark.parametrize("params", [
    {},
    dict(distance_gamma=0.5, obstacle_scale=2.0, orientation_scale=3.0, reach_reward=5.0, collision_reward=-1.0),
    dict(distance_gamma=-0.3, obstacle_scale=-1.0, obstacle_threshold=0.1),
])
def test_the_bound_holds_at_the_extremes_of_every_term(params):
    """Every step that neither reaches nor collides has d1 <= the world's span, d2 >= the
    footprint's inner radius and bearings in [-pi, pi): the bound covers all of them."""
    p = R.RewardParams(**params)
    span = World(targets=(Static((3.0, 3.0)),)).span()
    assert span == pytest.approx(math.hypot(*STANDARD_ARENA.size))
    bound = R.dense_bound(p, span, CLEARANCE)
    worst = 0.0
    rng = np.random.default_rng(0)
    extremes = [(d1, d2) for d1 in (0.0, span) for d2 in (CLEARANCE, max(p.obstacle_threshold, CLEARANCE), math.inf)]
    drawn = zip(rng.uniform(0, span, 200), rng.uniform(CLEARANCE, 3.0, 200))
    for d1, d2 in [*extremes, *drawn]:
        for before, after in ((math.pi - 1e-12, 0.0), (0.0, -math.pi), tuple(rng.uniform(-math.pi, math.pi, 2))):
            prev = _snap(d1=1.0, d2=d2, bearing=before)
            cur = _snap(d1=d1, d2=d2, bearing=after)
            for reached, collided in ((False, False), (True, False), (False, True)):
                r = R.compute_reward("dense", prev, cur, p, reached=reached, collided=collided)
                worst = max(worst, abs(r))
                n = R.compute_reward("normalized_dense", prev, cur, p, reached=reached, collided=collided, bound=bound)
                assert abs(n) <= 1.0 and n == r / bound
    assert worst <= bound
    assert worst >= 0.9 * bound  # the bound is close to what a step can give, not a loose guess


def _snap(d1, d2, bearing):
    """Robot at the origin facing +x; the target d1 away at ``bearing``; one 0.5 m box behind,
    its face d2 away (none when d2 is infinite)."""
    boxes = [] if math.isinf(d2) else [(-d2 - 0.25, 0.0)]
    return take_snapshot(step=1, pose=(0.0, 0.0, 0.0), lasers=[5.0] * 16,
                         target_xy=(d1 * math.cos(bearing), d1 * math.sin(bearing)), static_xy=boxes,
                         moving_xy=np.zeros((0, 2)), obstacle_half=[(0.25, 0.25)] * len(boxes), contact=False)


def test_the_bound_is_derived_from_the_terms():
    p = R.RewardParams()
    shaping = abs(1 - math.exp(0.2 * 15.0)) + math.pi + 0.5 / CLEARANCE  # 24.9
    assert R.dense_bound(p, 15.0, CLEARANCE) == pytest.approx(shaping)  # a larger arena: shaping dominates
    assert R.dense_bound(p, 9.2, CLEARANCE) == 20.0
    assert R.dense_bound(R.RewardParams(obstacle_threshold=0.1), 5.0, CLEARANCE) == 20.0
    with pytest.raises(ValueError, match="'normalized_dense' needs the task's bound"):
        R.compute_reward("normalized_dense", _snap(1, 1, 0), _snap(1, 1, 0), p, reached=False, collided=False)


def test_a_larger_world_gets_a_larger_bound():
    world = World(targets=(Static((9.0, 9.0)),), arena=Arena((-10.0, 10.0), (-10.0, 10.0)),
                  start=StartArea((-5.0, -4.0), (-5.0, -4.0)))
    assert world.span() == pytest.approx(math.hypot(20, 20))
    assert R.dense_bound(R.RewardParams(), world.span(), CLEARANCE) > 200


def test_sparse_is_maniskills_sparse_reward_but_for_the_step_cost(make_env):
    """With sparse_step 0 the study's sparse reward is ManiSkill's own (success - fail)."""
    env = make_env("DynNav-OneObstacle-v1", reward_mode="sparse", reward_params={"sparse_step": 0.0})
    base = env.unwrapped
    rng = np.random.default_rng(3)
    ends = set()
    for seed in range(6):
        env.reset(seed=seed)
        done = False
        while not done:
            _, reward, terminated, truncated, info = env.step(int(rng.integers(3)))
            maniskill = float(BaseEnv.compute_sparse_reward(base, obs=None, action=None, info=base.evaluate())[0])
            assert reward == maniskill
            done = terminated or truncated
        ends.add(dynnav_tasks.outcome_of(info, terminated))
    assert "collision" in ends


def test_reward_mode_none_gives_nothing(make_env):
    env = make_env("DynNav-MovingTarget-v1", reward_mode="none")
    env.reset(seed=0)
    rewards = [env.step(a)[1] for a in (0, 1, 0, 2, 0)]
    assert rewards == [0.0] * 5


def test_an_unknown_reward_mode_lists_maniskills_modes_too():
    with pytest.raises(ValueError, match=r"Unknown reward_mode 'normalised_dense'.*normalized_dense.*Did you mean"):
        gym.make("DynNav-MovingTarget-v1", reward_mode="normalised_dense")
