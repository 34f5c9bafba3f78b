"""The files of a pretrained navigator, and how a name finds them: ``pretrained:5.3`` is the
folder ``pretrained/5.3/`` of the repository (``DYNNAV_PRETRAINED`` names another folder of
models).

A model's folder holds

* ``model.safetensors``: the Q-network's weights (its ``state_dict``, float32), and in the
  file's metadata the format, its version and the number of training episodes;
* ``autoencoder.safetensors`` (camera runs with ``camera_input: latent``): the auto-encoder's
  encoder (float16; the decoder serves training and pictures only, and is left out) and the
  latent standardisation (``StateRepresentation.encoder_weights``);
* ``config.yaml``: the run's fully resolved config, from which the task, the features (the
  observation scaling is the task's, ``agents.core.obs_scaling.ObsScaler``) and the networks are
  built again;
* ``card.md``: what the model is and what it measured (``agents.pretrained.card``).

Nothing here unpickles: safetensors holds tensors only, the config is plain YAML.
``agents.training.policy_loading.load_policy`` accepts a name wherever it accepts a
checkpoint; ``agents.pretrained`` writes the folders.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import torch
import yaml

from agents.files import atomic_write_bytes

PREFIX = "pretrained:"
"""how a checkpoint argument names a pretrained model: pretrained:<name>"""
ROOT_VARIABLE = "DYNNAV_PRETRAINED"
"""environment variable naming the folder of models (default: pretrained/ of the repository)"""
MODEL, AUTOENCODER, CONFIG, CARD = "model.safetensors", "autoencoder.safetensors", "config.yaml", "card.md"
ENCODER_DTYPE = torch.float16
"""the encoder's weights are stored at half precision (1.1-2.4 MB each instead of twice that: the 14
models fit in 10 MB); they are read back into float32 and the card's test measures the model as read"""
FORMAT, VERSION = "dynnav-pretrained", 1
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")


class PretrainedError(ValueError):
    """An unknown model name, or a model folder that is incomplete or unreadable."""


def models_root() -> Path:
    """The folder of the pretrained models: ``$DYNNAV_PRETRAINED``, else ``pretrained/`` of the repository."""
    return Path(os.environ.get(ROOT_VARIABLE) or Path(__file__).resolve().parents[2] / "pretrained")


def is_pretrained(checkpoint) -> bool:
    """Whether a checkpoint argument names a pretrained model (``pretrained:<name>``)."""
    return str(checkpoint).startswith(PREFIX)


def check_name(name: str) -> str:
    """``name`` (without ``pretrained:``) if it can be a model's folder name, else PretrainedError."""
    if not _NAME.match(name) or ".." in name:
        raise PretrainedError(f"{name!r} cannot name a pretrained model: use letters, digits, '.', '-' and '_' "
                              f"(e.g. 5.3 or 5.5b-laser-pos)")
    return name


def _natural(name: str) -> list:
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name)]


def available(root: str | Path | None = None) -> list[str]:
    """The names of the models in ``root`` (default ``models_root()``), in natural order."""
    root = Path(root) if root is not None else models_root()
    if not root.is_dir():
        return []
    return sorted((p.name for p in root.iterdir() if (p / MODEL).is_file() and _NAME.match(p.name)), key=_natural)


def model_folder(name: str, root: str | Path | None = None) -> Path:
    """The folder of model ``name`` (``5.3`` or ``pretrained:5.3``); an unknown name is a
    PretrainedError listing the models there are."""
    name = check_name(str(name).removeprefix(PREFIX))
    root = Path(root) if root is not None else models_root()
    folder = root / name
    if not (folder / MODEL).is_file():
        there = available(root)
        listing = ", ".join(there) if there else "none"
        raise PretrainedError(f"no pretrained model {name!r} in {root} (the models there: {listing}); "
                              f"`python -m agents.pretrained list` shows them with their success")
    return folder


def results_dir(name: str) -> Path:
    """Where ``--eval --checkpoint pretrained:<name>`` writes its results unless told: runs/pretrained-<name>/
    (the model's own folder is part of the repository and stays as it is)."""
    return Path("runs") / f"pretrained-{check_name(str(name).removeprefix(PREFIX))}"


# ---------------------------------------------------------------------------------------- writing
def tensor_file(tensors: dict[str, torch.Tensor], metadata: dict[str, str]) -> bytes:
    """The bytes of a safetensors file holding ``tensors`` (contiguous CPU copies) and ``metadata``."""
    from safetensors.torch import save

    plain = {k: v.detach().to("cpu").contiguous().clone() for k, v in tensors.items()}
    return save(plain, metadata={k: str(v) for k, v in metadata.items()})


def write_model(folder: str | Path, q_network: dict[str, torch.Tensor], config: dict, trained_episodes: int,
                autoencoder: dict[str, torch.Tensor] | None = None) -> None:
    """Write a model's weights and its resolved ``config`` (grouped mapping) into ``folder``
    (created if needed), each file atomically."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    meta = dict(format=FORMAT, version=VERSION, trained_episodes=int(trained_episodes))
    atomic_write_bytes(folder / CONFIG, yaml.safe_dump(config, sort_keys=False).encode())
    if autoencoder is not None:
        encoder = {k: v.to(ENCODER_DTYPE) if k.startswith("encoder.") else v.float() for k, v in autoencoder.items()}
        atomic_write_bytes(folder / AUTOENCODER, tensor_file(encoder, dict(meta, part="encoder")))
    atomic_write_bytes(folder / MODEL, tensor_file({k: v.float() for k, v in q_network.items()},
                                                   dict(meta, part="q_network")))


# ---------------------------------------------------------------------------------------- reading
def read_tensors(path: Path) -> tuple[dict[str, torch.Tensor], dict[str, str]]:
    """The tensors and metadata of a safetensors file; PretrainedError naming the file if it is
    missing, corrupt or of another format."""
    from safetensors import SafetensorError, safe_open

    try:
        with safe_open(str(path), framework="pt") as f:
            metadata = f.metadata() or {}
            tensors = {k: f.get_tensor(k) for k in f.keys()}
    except (OSError, SafetensorError, ValueError) as err:
        raise PretrainedError(f"{path} is missing, corrupt or not a safetensors file ({err})") from err
    if metadata.get("format") != FORMAT or metadata.get("version") != str(VERSION):
        raise PretrainedError(f"{path} is not a dynnav pretrained model of format version {VERSION} "
                              f"(its metadata: {json.dumps(metadata)})")
    return tensors, metadata


def read_model(name: str, root: str | Path | None = None) -> tuple[Path, dict]:
    """The folder of model ``name`` and its state in the shape of a checkpoint's (``config``,
    ``episode``, ``learner: {q: ...}``, and ``autoencoder`` for camera latent runs)."""
    folder = model_folder(name, root)
    q_network, meta = read_tensors(folder / MODEL)
    try:
        config = yaml.safe_load((folder / CONFIG).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as err:
        raise PretrainedError(f"{folder / CONFIG} is missing or not YAML ({err})") from err
    if not isinstance(config, dict):
        raise PretrainedError(f"{folder / CONFIG} does not hold a config mapping")
    state = dict(config=config, episode=int(meta.get("trained_episodes", 0)), learner=dict(q=q_network))
    if (folder / AUTOENCODER).is_file():
        state["autoencoder"] = read_tensors(folder / AUTOENCODER)[0]
    return folder, state
