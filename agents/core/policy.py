"""Q-networks built from a run's config, and trained policies loaded from checkpoints."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
import torch
from torch import nn

from agents.training import checkpoint as ckpt
from agents.training.config_io import config_from_dict
from agents.training.envs import make_env_from
from agents.core.networks import MLPQNetwork, PixelQNetwork, check_q_network, load_factory


def build_q_network(config, input_specs, n_actions: int) -> nn.Module:
    """The run's Q-network, initialised from torch's generator seeded with ``config.seed``: the
    config's ``q_network`` factory, the conv net for pixel runs, or the MLP."""
    torch.manual_seed(config.seed)
    shapes = [tuple(shape) for shape, _ in input_specs]
    dtypes = [torch.from_numpy(np.zeros(0, dtype=d)).dtype for _, d in input_specs]
    if config.dqn.q_network:
        module = load_factory(config.dqn.q_network)(shapes, n_actions)
        source = f"q_network {config.dqn.q_network!r}"
    elif config.camera.camera_frames and config.camera.camera_input == "pixels":
        module = PixelQNetwork(shapes[0], shapes[1][0], n_actions, shift=config.camera.pixel_shift)
        source = "the pixel Q-network"
    else:
        if len(shapes) != 1 or len(shapes[0]) != 1:
            raise ValueError(f"the MLP Q-network reads one vector; this run's inputs have shapes {shapes}")
        module = MLPQNetwork(shapes[0][0], n_actions, config.dqn.hidden_sizes)
        source = "the MLP Q-network"
    return check_q_network(module, shapes, dtypes, n_actions, source)


@dataclass
class Policy:
    """A trained Q-network with the features that turn observations into its inputs."""

    config: object
    env: object
    features: object
    q_network: nn.Module
    path: Path
    state: dict

    @property
    def device(self) -> torch.device:
        return next(self.q_network.parameters()).device

    def q_values(self, obs) -> np.ndarray:
        x = self.features(obs)
        inputs = x if isinstance(x, tuple) else (x,)
        with torch.no_grad():
            tensors = [torch.as_tensor(np.asarray(v))[None].to(self.device) for v in inputs]
            return self.q_network(*tensors)[0].float().cpu().numpy()

    @property
    def views(self):
        """obs -> the auto-encoder's latent and reconstruction (camera latent runs), else None."""
        return getattr(self.features, "views", None)


def load_policy(checkpoint_path, device: Optional[str] = None, **task_kwargs) -> Policy:
    """The greedy policy of a checkpoint, with its own task and settings (``task_kwargs`` are
    added to the task's own, e.g. obs_mode for recordings)."""
    from agents.training.experience import make_features, new_state_representation

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
        raise ckpt.CheckpointError(f"{path}: the saved Q-network does not fit the one its config builds: {err}") from err
    net.to(device or config.run.device).eval()
    return Policy(config, env, features, net, path, state)
