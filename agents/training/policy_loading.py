"""A trained policy loaded from a checkpoint or a pretrained model, on its own task and
settings (for the test phase and recordings).

A checkpoint argument is a run directory, its checkpoint folder, or ``pretrained:<name>`` for
a pretrained navigator of ``pretrained/`` (``agents.training.pretrained_files``)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

from agents.core.policy import Policy, build_q_network
from agents.training import checkpoint as ckpt
from agents.training import pretrained_files
from agents.training.config_io import config_from_dict
from agents.training.envs import make_env_from
from agents.training.experience import make_features, new_state_representation


def read_state(checkpoint_path) -> tuple[Path, dict]:
    """The folder and the saved state (without a replay memory) of a checkpoint or a pretrained model."""
    if pretrained_files.is_pretrained(checkpoint_path):
        return pretrained_files.read_model(str(checkpoint_path))
    path = ckpt.resolve(checkpoint_path)
    return path, ckpt.load(path, memory=False)


def results_dir(checkpoint_path) -> Path:
    """Where a test of ``checkpoint_path`` writes unless told: the run directory of a checkpoint,
    runs/pretrained-<name>/ for a pretrained model."""
    if pretrained_files.is_pretrained(checkpoint_path):
        return pretrained_files.results_dir(str(checkpoint_path))
    return ckpt.resolve(checkpoint_path).parent


def load_policy(checkpoint_path, device: Optional[str] = None, **task_kwargs) -> Policy:
    """The greedy policy of a checkpoint (a run directory or its checkpoint folder) or of a
    pretrained model (``pretrained:5.3``), with its own task and settings (``task_kwargs`` are
    added to the task's own, e.g. obs_mode for recordings)."""
    path, state = read_state(checkpoint_path)
    return policy_from_state(path, state, device, **task_kwargs)


def policy_from_state(path: Path, state: dict, device: Optional[str] = None, **task_kwargs) -> Policy:
    """The greedy policy of a saved ``state`` (``read_state``'s, or a pretrained model's read from
    ``path``), on its own task with ``task_kwargs`` added."""
    config = config_from_dict(state["config"], source=f"config of {path}")
    env = make_env_from(config, **task_kwargs)
    try:
        srl = None
        if config.camera.camera_frames and config.camera.camera_input == "latent":
            srl = new_state_representation(env, config)
            if "srl" in state:
                srl.load_state_dict(state["srl"])
            elif "autoencoder" in state:
                srl.load_encoder_weights(state["autoencoder"])
            else:
                raise ckpt.CheckpointError(f"{path}: the run reads the auto-encoder's latent, but no auto-encoder "
                                           f"was saved with it")
        features = make_features(env, config, srl)
        net = build_q_network(config, features.input_specs, int(env.action_space.n))
        try:
            net.load_state_dict(state["learner"]["q"])
        except RuntimeError as err:
            raise ckpt.CheckpointError(f"{path}: the saved Q-network does not fit the one its config builds: "
                                       f"{err}") from err
    except BaseException:
        env.close()
        raise
    net.to(device or config.run.device).eval()
    return Policy(config, env, features, net, path, state)
