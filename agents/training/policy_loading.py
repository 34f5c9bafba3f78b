"""A trained policy loaded from a checkpoint, on its own task and settings (for the test phase
and recordings)."""

from __future__ import annotations

from typing import Optional

from agents.core.policy import Policy, build_q_network
from agents.training import checkpoint as ckpt
from agents.training.config_io import config_from_dict
from agents.training.envs import make_env_from
from agents.training.experience import make_features, new_state_representation


def load_policy(checkpoint_path, device: Optional[str] = None, **task_kwargs) -> Policy:
    """The greedy policy of a checkpoint (a run directory or its checkpoint folder), with its own
    task and settings (``task_kwargs`` are added to the task's own, e.g. obs_mode for recordings)."""
    path = ckpt.resolve(checkpoint_path)
    state = ckpt.load(path, memory=False)
    config = config_from_dict(state["config"], source=f"config in {path / ckpt.META}")
    env = make_env_from(config, **task_kwargs)
    srl = None
    if config.camera.camera_frames and config.camera.camera_input == "latent":
        srl = new_state_representation(env, config)
        srl.load_state_dict(state["srl"])
    features = make_features(env, config, srl)
    net = build_q_network(config, features.input_specs, int(env.action_space.n))
    try:
        net.load_state_dict(state["learner"]["q"])
    except RuntimeError as err:
        env.close()
        raise ckpt.CheckpointError(f"{path}: the saved Q-network does not fit the one its config builds: {err}") from err
    net.to(device or config.run.device).eval()
    return Policy(config, env, features, net, path, state)
