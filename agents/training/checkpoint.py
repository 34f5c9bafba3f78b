"""Checkpoints: everything a stopped run needs to continue, in files any tool can open.

A run's checkpoint is the folder ``<run>/checkpoint/``:

* ``meta.json``: the format and its version, the resolved config, the episode and step counts,
  the input shapes, the random generators' states and every setting of the optimizers;
* ``weights.pt``: a flat ``{name: tensor}`` dict (online and target networks, Adam's moments,
  the auto-encoder, torch's random state), read with ``torch.load(path, weights_only=True)``;
* ``memory.npz``: the replay memory's arrays (``numpy.load(path)``).

Loading never unpickles code (``weights_only=True``, ``allow_pickle=False``). A missing,
truncated or corrupt file, weights that are not finite, or another format version is a
``CheckpointError`` that names the file; so is a ``checkpoint.pkl`` of an older version.

Writes are atomic: the files go to ``<run>/.checkpoint.tmp-*/`` first, are flushed to disk,
then that folder is renamed to ``checkpoint`` (the previous one is moved aside first and
deleted after). A run killed at any moment keeps a complete checkpoint; what a killed write
left behind (temporary folders and files) is removed by the run's next write or resume;
reading never changes a run directory. A full disk is an ``agents.files.DiskFullError`` that
names the checkpoint, its size and the space free; the previous checkpoint stays in place.
"""

from __future__ import annotations

import io
import json
import os
import shutil
import tempfile
import zipfile
from pathlib import Path

import numpy as np
import torch

from agents.files import disk_full_error, is_disk_full, umask, write_synced

FORMAT = "dynnav-dqn-checkpoint"
VERSION = 2
FILENAME = "checkpoint"
"""the checkpoint folder inside a run directory"""
META, WEIGHTS, MEMORY = "meta.json", "weights.pt", "memory.npz"
OLD_PICKLE = "checkpoint.pkl"


class CheckpointError(ValueError):
    """A checkpoint is missing, truncated, corrupt, or not a checkpoint of this agent's format."""


def clean_leftovers(run_dir: str | Path) -> None:
    """Remove what killed writes left in ``run_dir``: temporary checkpoint folders and ``.*.tmp`` files.

    A checkpoint moved aside while the new one was renamed into place is put back if the new one
    never arrived."""
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        return
    for old in sorted(run_dir.glob(".checkpoint.old-*")):
        if not (run_dir / FILENAME).exists() and (old / META).is_file():
            os.replace(old, run_dir / FILENAME)
        else:
            shutil.rmtree(old, ignore_errors=True)
    for tmp in run_dir.glob(".checkpoint.tmp-*"):
        shutil.rmtree(tmp, ignore_errors=True)
    for tmp in run_dir.glob(".*.tmp"):
        tmp.unlink(missing_ok=True)


# ---------------------------------------------------------------------------------------- (de)composing
def _split(value, tensors: dict, arrays: dict | None, key: str):
    """JSON-able ``value`` with tensors (and numpy arrays) replaced by references to ``tensors`` /
    ``arrays`` (``arrays`` None: numpy arrays are stored as tensors too)."""
    if isinstance(value, torch.Tensor):
        tensors[key] = value.detach().cpu().clone().contiguous()
        return {"$tensor": key}
    if isinstance(value, np.ndarray):
        if arrays is not None:
            arrays[key] = value
            return {"$array": key}
        tensors[key] = torch.from_numpy(np.ascontiguousarray(value).copy())
        return {"$ndarray": key}
    if isinstance(value, dict):
        if all(isinstance(k, str) for k in value):
            return {k: _split(v, tensors, arrays, f"{key}.{k}") for k, v in value.items()}
        return {"$items": [[k, _split(v, tensors, arrays, f"{key}.{k}")] for k, v in value.items()]}
    if isinstance(value, (list, tuple)):
        return [_split(v, tensors, arrays, f"{key}.{i}") for i, v in enumerate(value)]
    if isinstance(value, (np.integer, np.floating, np.bool_)):
        return value.item()
    return value


def _join(value, tensors: dict, arrays: dict):
    if isinstance(value, dict):
        if "$tensor" in value:
            return tensors[value["$tensor"]]
        if "$ndarray" in value:
            return tensors[value["$ndarray"]].numpy()
        if "$array" in value:
            return arrays[value["$array"]]
        if "$items" in value:
            return {k: _join(v, tensors, arrays) for k, v in value["$items"]}
        return {k: _join(v, tensors, arrays) for k, v in value.items()}
    if isinstance(value, list):
        return [_join(v, tensors, arrays) for v in value]
    return value


# ---------------------------------------------------------------------------------------- saving
def save(run_dir: str | Path, state: dict) -> Path:
    """Write ``state`` (its ``memory`` entry to memory.npz, tensors to weights.pt, the rest to
    meta.json) as ``run_dir``/checkpoint, atomically; returns the checkpoint folder."""
    run_dir = Path(run_dir)
    clean_leftovers(run_dir)
    tensors, arrays = {}, {}
    meta = {k: _split(v, tensors, arrays if k == "memory" else None, k) for k, v in state.items()}
    meta = {"format": FORMAT, "version": VERSION, **meta}
    buffer = io.BytesIO()
    torch.save(tensors, buffer)
    npz = io.BytesIO()
    np.savez(npz, **arrays)
    files = ((WEIGHTS, buffer.getvalue()), (MEMORY, npz.getvalue()), (META, json.dumps(meta, indent=1).encode()))
    target = run_dir / FILENAME
    tmp = None
    try:
        tmp = Path(tempfile.mkdtemp(dir=run_dir, prefix=".checkpoint.tmp-"))
        os.chmod(tmp, 0o777 & ~umask())
        for name, data in files:
            write_synced(tmp / name, data)
        if target.exists():
            aside = run_dir / f".checkpoint.old-{os.urandom(4).hex()}"
            os.replace(target, aside)  # a kill from here to the next line: clean_leftovers puts it back
            os.replace(tmp, target)
            shutil.rmtree(aside, ignore_errors=True)
        else:
            os.replace(tmp, target)
    except BaseException as err:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        if is_disk_full(err):
            kept = (f"the previous checkpoint is intact: continue with --resume {run_dir}" if exists(run_dir)
                    else "no checkpoint was written yet")
            raise disk_full_error(err, target, sum(len(data) for _, data in files), kept) from err
        raise
    return target


# ---------------------------------------------------------------------------------------- loading
def _in_run_dir(run_dir: Path) -> Path | None:
    """The complete checkpoint folder of a run directory: ``checkpoint/``, or the previous one a
    write killed between its two renames left aside (without moving anything)."""
    if (run_dir / FILENAME / META).is_file():
        return run_dir / FILENAME
    aside = sorted(p for p in run_dir.glob(".checkpoint.old-*") if (p / META).is_file())
    return aside[-1] if aside else None


def resolve(path: str | Path) -> Path:
    """The checkpoint folder: given as itself, as the run directory holding it, or as a file in it."""
    path = Path(path)
    if path.is_file() and path.name in (META, WEIGHTS, MEMORY):
        path = path.parent
    if (path / META).is_file():
        return path
    old = path if path.suffix == ".pkl" else path / OLD_PICKLE
    if old.is_file():
        raise CheckpointError(
            f"{str(old)!r} is a checkpoint of an older dynnav version (a Python pickle). This version reads "
            f"only checkpoint folders (meta.json, weights.pt, memory.npz) and never unpickles, since a pickle "
            f"can run any code; train the run again with this version")
    found = _in_run_dir(path) if path.is_dir() else None
    if found is None:
        raise CheckpointError(f"no checkpoint at {str(path)!r} (expected a run directory or its checkpoint folder)")
    return found


def load(path: str | Path, memory: bool = True) -> dict:
    """The state saved by ``save``; CheckpointError naming the file if anything is wrong.

    ``memory=False`` skips the replay memory (testing a policy does not need it)."""
    folder = resolve(path)
    try:
        meta = json.loads((folder / META).read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise CheckpointError(f"{str(folder / META)!r} is corrupt or unreadable ({err})") from err
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise CheckpointError(f"{str(folder / META)!r} is not a dynnav DQN checkpoint")
    if meta.get("version") != VERSION:
        raise CheckpointError(f"{str(folder / META)!r} has format version {meta.get('version')}; this version of "
                              f"dynnav reads version {VERSION}")
    try:
        tensors = torch.load(folder / WEIGHTS, map_location="cpu", weights_only=True)
    except Exception as err:  # truncated or overwritten files raise many kinds of errors
        raise CheckpointError(f"{str(folder / WEIGHTS)!r} is corrupt or unreadable ({type(err).__name__}: {err})") from err
    if not isinstance(tensors, dict) or not all(isinstance(t, torch.Tensor) for t in tensors.values()):
        raise CheckpointError(f"{str(folder / WEIGHTS)!r} is not a dict of tensors")
    for name, t in tensors.items():
        if t.is_floating_point() and not torch.isfinite(t).all():
            raise CheckpointError(f"{str(folder / WEIGHTS)!r}: {name!r} holds non-finite values (NaN or inf); "
                                  f"the run diverged before this checkpoint")
    arrays = {}
    if memory:
        try:
            with np.load(folder / MEMORY, allow_pickle=False) as npz:
                arrays = {k: npz[k] for k in npz.files}
        except (OSError, ValueError, zipfile.BadZipFile, EOFError) as err:
            raise CheckpointError(f"{str(folder / MEMORY)!r} is corrupt or unreadable ({err})") from err
    try:
        state = {k: _join(v, tensors, arrays) for k, v in meta.items() if memory or k != "memory"}
    except KeyError as err:
        raise CheckpointError(f"{str(folder)!r}: meta.json names {err} but the weights or memory file lacks it") from err
    return state


def exists(run_dir: str | Path) -> bool:
    """Whether ``run_dir`` holds a complete checkpoint (reading only: safe while the run writes)."""
    return Path(run_dir).is_dir() and _in_run_dir(Path(run_dir)) is not None
