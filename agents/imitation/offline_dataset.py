"""Demonstrations as a Minari data set: the offline-RL format that Minari and d3rlpy read.

Minari (the Farama Foundation's data sets for offline RL, the successor of D4RL) stores
episodes of a gymnasium environment in HDF5 with their spaces and the environment's spec;
d3rlpy reads them (``d3rlpy.datasets.get_minari``) and so does any code that iterates them.
Each of our episodes keeps:

* ``observations`` (steps + 1, d): the task's egocentric state, unscaled, as the environment
  gave it (the student scales it with the observation space's bounds);
* ``actions`` (steps,): the actions *taken* (the teacher's in its own episodes, the student's
  or the teacher's in DAgger's), so that every transition is one the environment made;
* ``rewards``, ``terminations``, ``truncations``: as the task returned them;
* ``infos["label"]`` (steps + 1,): the teacher's action in each state, -1 in the last one.

A data set lives in a folder of its own: ``write_minari`` builds it in a temporary folder
beside ``folder`` and renames it into place, so a killed write never leaves half a data set.
Load it with ``load_minari(folder)`` or, in any program::

    MINARI_DATASETS_PATH=<folder> python -c "import minari; d = minari.load_dataset('dynnav/procedural/planner-v0')"
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
import warnings
from pathlib import Path

import gymnasium as gym
import numpy as np

from agents.core.demonstrations import Rollout
from agents.files import replace_folder

DATASET_ID = "dynnav/procedural/planner-v0"
"""the data set's Minari id: namespace dynnav, environment procedural, the planner's labels"""


@contextlib.contextmanager
def _datasets_root(folder: Path):
    """Minari reads its root folder from ``MINARI_DATASETS_PATH`` when called: point it at ``folder``
    (absolute: Minari 0.5.4 joins a relative root to itself when it measures the data set)."""
    before = os.environ.get("MINARI_DATASETS_PATH")
    os.environ["MINARI_DATASETS_PATH"] = str(Path(folder).resolve())
    try:
        yield
    finally:
        if before is None:
            os.environ.pop("MINARI_DATASETS_PATH", None)
        else:
            os.environ["MINARI_DATASETS_PATH"] = before


def write_minari(rollouts: list[Rollout], folder: str | Path, env_spec: gym.envs.registration.EnvSpec,
                 observation_space: gym.spaces.Box, action_space: gym.spaces.Discrete,
                 description: str) -> Path:
    """Write ``rollouts`` as the Minari data set ``DATASET_ID`` in ``folder`` (replacing what is
    there, atomically); returns ``folder``. ``env_spec``: the task as the episodes were made
    (id and options), so that ``recover_environment()`` makes it again (after ``import dynnav_tasks``)."""
    import minari
    from minari.data_collector.episode_buffer import EpisodeBuffer

    if not rollouts:
        raise ValueError("no episodes to write")
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.tmp-"))
    try:
        buffers = [EpisodeBuffer(
            id=i, seed=r.seed, observations=r.observations, actions=r.actions, rewards=r.rewards.tolist(),
            terminations=[False] * (r.steps - 1) + [r.terminated], truncations=[False] * (r.steps - 1) + [r.truncated],
            infos={"label": np.concatenate([r.labels, [-1]])},
        ) for i, r in enumerate(rollouts)]
        with _datasets_root(tmp), warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # author, e-mail and permalink are optional
            minari.create_dataset_from_buffers(
                DATASET_ID, buffers, env=env_spec, observation_space=observation_space, action_space=action_space,
                algorithm_name="dynnav_tasks.baselines.state_planner (teacher) and DAgger (agents.imitation)",
                description=description, data_format="hdf5", requirements=["dynnav"],
            )
        replace_folder(tmp, folder)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return folder


def load_minari(folder: str | Path):
    """The ``minari.MinariDataset`` that ``write_minari`` wrote in ``folder``."""
    import minari

    folder = Path(folder)
    if not (folder / DATASET_ID / "data").is_dir():
        raise ValueError(f"{str(folder)!r} holds no Minari data set {DATASET_ID!r} (write one with "
                         f"python -m agents.imitation)")
    with _datasets_root(folder):
        return minari.load_dataset(DATASET_ID)


def dataset_bytes(folder: str | Path) -> int:
    """Size (bytes) of every file of the data set in ``folder``."""
    return sum(p.stat().st_size for p in Path(folder).rglob("*") if p.is_file())
