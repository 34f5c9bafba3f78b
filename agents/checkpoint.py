"""Checkpoints: everything a stopped run needs to continue, written atomically.

A checkpoint is one pickle file holding the resolved config, the Q-network, the target
network and Adam's state, the replay memory, the exploration/sampling generator's state and
the number of finished episodes. It is written to a temporary file in the same directory,
flushed to disk, then renamed over the old one (``os.replace``), so a run killed at any
moment leaves either the previous checkpoint or the new one, never a partial file.
"""

from __future__ import annotations

import os
import pickle
import tempfile
from pathlib import Path

FORMAT = "dynnav-dqn-checkpoint"
VERSION = 1
FILENAME = "checkpoint.pkl"


class CheckpointError(ValueError):
    """A checkpoint is missing, truncated, or not a checkpoint of this agent."""


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` so that readers see the old or the new content, nothing else."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, 0o666 & ~_umask())  # mkstemp makes 0600; give the file the usual mode
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def save(path: str | Path, state: dict) -> None:
    atomic_write_bytes(path, pickle.dumps({"format": FORMAT, "version": VERSION, **state}, protocol=5))


def resolve(path: str | Path) -> Path:
    """A checkpoint file, or the checkpoint inside a run directory."""
    path = Path(path)
    if path.is_dir():
        path = path / FILENAME
    if not path.is_file():
        raise CheckpointError(f"no checkpoint at {str(path)!r}")
    return path


def load(path: str | Path) -> dict:
    """The state saved by ``save``; CheckpointError if missing, corrupt or of another format."""
    path = resolve(path)
    try:
        with open(path, "rb") as f:
            state = pickle.load(f)
    except Exception as err:  # truncated or overwritten files raise many kinds of errors
        raise CheckpointError(f"checkpoint {str(path)!r} is corrupt or unreadable ({type(err).__name__}: {err})") from err
    if not isinstance(state, dict) or state.get("format") != FORMAT:
        raise CheckpointError(f"{str(path)!r} is not a dynnav DQN checkpoint")
    if state.get("version") != VERSION:
        raise CheckpointError(f"checkpoint {str(path)!r} has format version {state.get('version')}, expected {VERSION}")
    return state
