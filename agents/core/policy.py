"""Q-networks built from a run's config, and a trained policy: a Q-network with the features
that turn observations into its inputs (``agents.training.policy_loading.load_policy`` loads
one from a checkpoint)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from torch import nn

from agents.core.networks import MLPQNetwork, PixelQNetwork, check_q_network, load_factory, q_values_of


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
    """the run's resolved config"""
    env: object
    features: object
    q_network: nn.Module
    path: Path
    """the checkpoint folder"""
    state: dict
    """the checkpoint's state without its replay memory"""

    @property
    def device(self) -> torch.device:
        """Where the Q-network's parameters live."""
        return next(self.q_network.parameters()).device

    def q_values(self, obs) -> np.ndarray:
        """Q-values (actions,) of an environment observation."""
        return q_values_of(self.q_network, self.features(obs), self.device)

    @property
    def views(self):
        """obs -> the auto-encoder's latent and reconstruction (camera latent runs), else None."""
        return getattr(self.features, "views", None)
