"""Write ``golden_steps.npz``: the exact results of a fixed set of episodes of every task.

The file pins what a step computes (observations, rewards, terminated / truncated, the
outcome and the snapshot's fields), so that work on the step's speed cannot change any of
it: ``tests/test_step_golden.py`` replays the same episodes and asserts bit-for-bit
equality. Regenerate it only for a deliberate change of behaviour::

    python tests/data/make_golden_steps.py

Episodes, for every task of ``dynnav_tasks.TASK_IDS`` (state observations, through
``gym.make`` + ``NumpyWrapper``):

* seeded resets driven by one fixed random action sequence (these mostly end in collisions),
* seeded resets driven by a greedy pilot that turns towards the target and drives at it
  (these often end in success), each followed by an unseeded reset (the generator goes on),
* on one task, an episode of turning in place that runs into the 200-step limit.

The reward of every reward mode is computed from the snapshots before and after each step
with ``rewards.compute_reward``, beside the reward the task returned (default mode).
"""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path

import numpy as np

os.environ.setdefault("MS_RENDERER_LOG_LEVEL", "error")

GOLDEN = Path(__file__).resolve().parent / "golden_steps.npz"
RANDOM_SEEDS = (0, 1)
PILOT_SEEDS = (10, 11)
TURNING_TASKS = ("DynNav-OneObstacle-v1",)
MAX_STEPS = 200
FLAGS = ("terminated", "truncated", "success", "fail", "collision", "timeout", "contact")
"""the columns of each episode's ``flags``; the outcome's other entries (elapsed_steps,
distance_to_target, path_length) are the snapshot's step, d1 and path_length"""


def random_actions() -> np.ndarray:
    return np.random.default_rng(1234).integers(0, 3, size=MAX_STEPS)


def pilot_action(snapshot, step: int) -> int:
    """Turn towards the target while it is more than a turn away from ahead, else forward;
    every seventh step a turn to the left, so the path is not a straight line."""
    if step % 7 == 6:
        return 1
    if abs(snapshot.bearing) > math.pi / 12:
        return 1 if snapshot.bearing > 0 else 2
    return 0


def make_env(task_id: str):
    import gymnasium as gym

    import dynnav_tasks

    return dynnav_tasks.NumpyWrapper(gym.make(task_id, obs_mode="state"))


def _snapshot_row(s) -> dict:
    """The snapshot's fields but ``lasers`` (the observation's first 16 entries hold them)."""
    return dict(
        step=np.array(s.step, dtype=np.int16),
        pose=np.array(s.pose, dtype=np.float64),
        target_xy=np.array(s.target_xy),
        moving_xy=np.array(s.moving_obstacle_xy).reshape(-1),
        scalars=np.array([s.d1, s.d2, s.bearing, s.path_length], dtype=np.float64),
    )


def run_episode(env, seed, policy) -> dict:
    """One episode; ``seed`` None resets without a seed. Returns per-row arrays (row 0 is
    the reset, then one row per step)."""
    from dynnav_tasks import rewards as R

    base = env.unwrapped
    obs, info = env.reset(seed=seed)
    rows = []

    def record(obs, terminated, truncated, info, mode_rewards):
        snapshot = base.snapshot
        assert np.array_equal(snapshot.lasers, np.asarray(obs)[: len(snapshot.lasers)])
        assert info["elapsed_steps"] == snapshot.step and info["distance_to_target"] == snapshot.d1
        assert info["path_length"] == snapshot.path_length
        row = _snapshot_row(snapshot)
        row.update(
            obs=np.array(obs, dtype=np.float32),
            mode_rewards=np.array(mode_rewards, dtype=np.float64),
            flags=np.array(
                [terminated, truncated, info["success"], info["fail"], info["collision"], info["timeout"], snapshot.contact],
                dtype=np.int8,
            ),
        )
        rows.append(row)

    record(obs, False, False, info, [0.0] * len(R.REWARD_MODES))
    for step in range(MAX_STEPS):
        prev = base.snapshot
        obs, reward, terminated, truncated, info = env.step(policy(prev, step))
        cur = base.snapshot
        modes = [
            R.compute_reward(m, prev, cur, base.reward_params, reached=info["success"], collided=info["collision"])
            for m in R.REWARD_MODES
        ]
        assert reward == modes[R.REWARD_MODES.index(R.DEFAULT_REWARD_MODE)]  # the task's own mode
        record(obs, terminated, truncated, info, modes)
        if terminated or truncated:
            break
    return {k: np.stack([r[k] for r in rows]) for k in rows[0]}


def episodes(task_id: str):
    """(name, seed, policy) of every episode of ``task_id``, in the order they run."""
    actions = random_actions()
    for seed in RANDOM_SEEDS:
        yield f"random, seed {seed}", seed, lambda s, k: int(actions[k])
    for seed in PILOT_SEEDS:
        yield f"pilot, seed {seed}", seed, pilot_action
        yield f"pilot, unseeded after seed {seed}", None, pilot_action
    if task_id in TURNING_TASKS:
        yield "turning, seed 5", 5, lambda s, k: 1


def collect(task_ids) -> dict[str, np.ndarray]:
    """Every episode of every task: ``{"<task>/<field>": rows of its episodes, in order}``
    and ``"<task>/episode_ends"``, the row after each episode's last."""
    out = {}
    for task_id in task_ids:
        env = make_env(task_id)
        try:
            runs = [run_episode(env, seed, policy) for _, seed, policy in episodes(task_id)]
        finally:
            env.close()
        for field in runs[0]:
            out[f"{task_id}/{field}"] = np.concatenate([run[field] for run in runs])
        out[f"{task_id}/episode_ends"] = np.cumsum([len(run["obs"]) for run in runs])
    return out


def main() -> None:
    import dynnav_tasks

    data = collect(dynnav_tasks.TASK_IDS)
    np.savez_compressed(GOLDEN, **data)
    ends = {name: 0 for name in ("success", "collision", "timeout")}
    for task_id in dynnav_tasks.TASK_IDS:
        last = data[f"{task_id}/flags"][data[f"{task_id}/episode_ends"] - 1]
        for name in ends:
            ends[name] += int(last[:, FLAGS.index(name)].sum())
    steps = sum(len(a) for k, a in data.items() if k.endswith("/obs")) - sum(
        len(a) for k, a in data.items() if k.endswith("/episode_ends")
    )
    print(f"{GOLDEN}: {steps} steps, episodes ending in {ends}, {GOLDEN.stat().st_size / 1024:.0f} KB")


if __name__ == "__main__":
    sys.exit(main())
