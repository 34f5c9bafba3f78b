"""Every task's step gives the results pinned in ``data/golden_steps.npz``.

The episodes (``data/make_golden_steps.py``) cover seeded and unseeded resets, collisions,
successes and a timeout; terminated / truncated, the outcome, the episode lengths and every
other discrete field must be exactly equal, and observations, rewards of every reward mode
and poses equal to within ``FLOAT_ATOL``. On the machine that pinned them they are equal bit
for bit; on another CPU, PhysX's contact solver can resolve a collision step differently in
the fifth decimal (seen: one terminal row of 245 in DynNav-OverlappingAreas-v1, 9e-6 m in the
pose, 4e-5 in a laser reading), while a change to the step's logic moves them by far more.
"""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import dynnav_tasks

DATA = Path(__file__).resolve().parent / "data"
FLOAT_ATOL = 1e-3
"""the largest difference allowed in a float field (metres, radians, laser ranges, rewards)"""
_spec = importlib.util.spec_from_file_location("make_golden_steps", DATA / "make_golden_steps.py")
golden = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(golden)


@pytest.fixture(scope="module")
def pinned():
    with np.load(golden.GOLDEN) as data:
        return {key: data[key] for key in data.files}


def _first_difference(expected: np.ndarray, got: np.ndarray, ends: np.ndarray) -> str:
    if expected.shape != got.shape:
        return f"shape {got.shape}, pinned {expected.shape}"
    rows = np.nonzero((expected != got).reshape(len(expected), -1).any(axis=1))[0]
    row = int(rows[0])
    episode = int(np.searchsorted(ends, row, side="right"))
    start = int(ends[episode - 1]) if episode else 0
    return f"episode {episode}, row {row - start}: got {got[row]!r}, pinned {expected[row]!r}"


@pytest.mark.parametrize("task_id", dynnav_tasks.TASK_IDS)
def test_steps_match_the_pinned_results(pinned, task_id):
    got = golden.collect([task_id])
    expected = {key: value for key, value in pinned.items() if key.startswith(f"{task_id}/")}
    assert sorted(got) == sorted(expected)
    ends = expected[f"{task_id}/episode_ends"]
    for key, value in sorted(expected.items(), key=lambda item: item[0].endswith("/episode_ends")):
        assert got[key].dtype == value.dtype, key
        if value.dtype.kind == "f" and got[key].shape == value.shape:
            worst = float(np.max(np.abs(got[key] - value), initial=0.0))
            assert worst <= FLOAT_ATOL, f"{key}: off by {worst:.3g}; {_first_difference(value, got[key], ends)}"
        else:
            assert np.array_equal(got[key], value), f"{key}: {_first_difference(value, got[key], ends)}"


def test_the_pinned_episodes_end_every_way(pinned):
    flags = golden.FLAGS
    ends = {name: 0 for name in ("success", "collision", "timeout")}
    for task_id in dynnav_tasks.TASK_IDS:
        last = pinned[f"{task_id}/flags"][pinned[f"{task_id}/episode_ends"] - 1]
        for name in ends:
            ends[name] += int(last[:, flags.index(name)].sum())
    assert all(count > 0 for count in ends.values()), ends
