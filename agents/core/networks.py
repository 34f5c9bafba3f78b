"""Q-networks: torch modules that map observations to one Q-value per action.

The DQN update (``agents.core.learner``) works with any ``torch.nn.Module`` whose ``forward`` takes
the observation's input tensors (a batch of each) and returns a (batch, actions) tensor:

* ``MLPQNetwork``: a ReLU MLP on a state vector (the study's 2 x 128), and on the auto-encoder's
  latent beside parts of the state vector for the study's camera runs;
* ``PixelQNetwork``: a small convolutional encoder on camera frames (one RGB frame or a stack of
  gray frames), trained end to end by the TD loss, with DrQ's random-shift augmentation in
  training mode, optionally beside parts of the state vector;
* your own: ``q_network: "package.module:factory"`` in a config names a function
  ``factory(input_shapes, n_actions) -> nn.Module``, e.g. ``agents.core.networks:dueling_mlp``.
"""

from __future__ import annotations

import importlib
from typing import Callable, Sequence

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F


class MLPQNetwork(nn.Module):
    """Linear layers with ReLU between them: in_dim -> hidden... -> n_actions."""

    def __init__(self, in_dim: int, n_actions: int, hidden_sizes: Sequence[int] = (128, 128)):
        super().__init__()
        sizes = [int(in_dim), *map(int, hidden_sizes), int(n_actions)]
        if min(sizes) < 1:
            raise ValueError(f"layer sizes must be positive, got {sizes}")
        self.sizes = sizes
        layers: list[nn.Module] = []
        for i, (fan_in, fan_out) in enumerate(zip(sizes[:-1], sizes[1:])):
            layers.append(nn.Linear(fan_in, fan_out))
            if i < len(sizes) - 2:
                layers.append(nn.ReLU())
        self.layers = nn.Sequential(*layers)

    @property
    def linears(self) -> list[nn.Linear]:
        """The linear layers, input to output."""
        return [m for m in self.layers if isinstance(m, nn.Linear)]

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """Q-values (batch, actions) of a batch of inputs."""
        return self.layers(x)


class DuelingMLP(nn.Module):
    """Dueling head (Wang et al. 2016): Q(s, a) = V(s) + A(s, a) - mean_a A(s, a), on a ReLU trunk.

    An example of a user's own Q-network: ``q_network: agents.core.networks:dueling_mlp``."""

    def __init__(self, in_dim: int, n_actions: int, hidden: int = 128):
        super().__init__()
        self.trunk = nn.Sequential(nn.Linear(in_dim, hidden), nn.ReLU(), nn.LayerNorm(hidden))
        self.value = nn.Sequential(nn.Linear(hidden, hidden), nn.ReLU(), nn.Linear(hidden, 1))
        self.advantage = nn.Sequential(nn.Linear(hidden, hidden), nn.ReLU(), nn.Linear(hidden, n_actions))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """Q-values (batch, actions) of a batch of inputs."""
        h = self.trunk(x)
        a = self.advantage(h)
        return self.value(h) + a - a.mean(dim=1, keepdim=True)


def dueling_mlp(input_shapes: list[tuple[int, ...]], n_actions: int) -> nn.Module:
    """Factory for ``q_network: agents.core.networks:dueling_mlp`` (state vectors)."""
    if len(input_shapes) != 1 or len(input_shapes[0]) != 1:
        raise ValueError(f"dueling_mlp reads one state vector, got inputs of shapes {input_shapes}")
    return DuelingMLP(input_shapes[0][0], n_actions)


def random_shift(frames: torch.Tensor, pad: int) -> torch.Tensor:
    """DrQ's augmentation: pad each (B, C, H, W) image by repeating its border, crop it back at a
    random offset of up to ``pad`` pixels (one offset per image, from torch's generator)."""
    b, _, h, w = frames.shape
    padded = F.pad(frames, (pad, pad, pad, pad), mode="replicate")
    dx = torch.randint(0, 2 * pad + 1, (b,), device=frames.device)
    dy = torch.randint(0, 2 * pad + 1, (b,), device=frames.device)
    rows = (dy[:, None] + torch.arange(h, device=frames.device)[None])  # (B, H)
    cols = (dx[:, None] + torch.arange(w, device=frames.device)[None])  # (B, W)
    index = torch.arange(b, device=frames.device)[:, None, None]
    out = padded.permute(0, 2, 3, 1)[index, rows[:, :, None], cols[:, None, :]]  # (B, H, W, C)
    return out.permute(0, 3, 1, 2)


class PixelQNetwork(nn.Module):
    """Camera frames (uint8, (B, H, W, C)) [+ state parts (B, S)] -> Q-values, learned from the TD loss.

    Three 3x3 convolutions of stride 2 (32 -> 16 -> 8 -> 4 pixels), a dense layer, then an MLP
    head on the encoding beside the state parts. In training mode (the update) each frame is
    randomly shifted by up to ``shift`` pixels (DrQ, Kostrikov et al. 2020); acting uses eval mode."""

    def __init__(self, frame_shape: Sequence[int], state_dim: int, n_actions: int,
                 channels: Sequence[int] = (16, 32, 32), dense: int = 128, hidden: int = 128, shift: int = 2):
        super().__init__()
        h, w, c = (int(v) for v in frame_shape)
        if h % 8 or w % 8:
            raise ValueError(f"frames must have sides divisible by 8 (three stride-2 convolutions), got {h}x{w}")
        self.shift = int(shift)
        convs: list[nn.Module] = []
        for c_in, c_out in zip([c, *channels[:-1]], channels):
            convs += [nn.Conv2d(c_in, c_out, 3, stride=2, padding=1), nn.ReLU()]
        flat = channels[-1] * (h // 8) * (w // 8)
        self.encoder = nn.Sequential(*convs, nn.Flatten(), nn.Linear(flat, dense), nn.ReLU())
        self.head = MLPQNetwork(dense + int(state_dim), n_actions, (hidden,))

    def forward(self, frames: torch.Tensor, state: torch.Tensor | None = None) -> torch.Tensor:
        """Q-values (batch, actions) of a batch of inputs."""
        x = frames.permute(0, 3, 1, 2).float().div(255.0)
        if self.training and self.shift > 0:
            x = random_shift(x, self.shift)
        z = self.encoder(x)
        if state is not None and state.shape[1] > 0:
            z = torch.cat([z, state.float()], dim=1)
        return self.head(z)


def load_factory(spec: str) -> Callable[[list[tuple[int, ...]], int], nn.Module]:
    """The function named by ``"package.module:function"``; ValueError naming what is missing."""
    module_name, _, attr = spec.partition(":")
    if not module_name or not attr:
        raise ValueError(f"q_network {spec!r}: expected 'package.module:function'")
    try:
        module = importlib.import_module(module_name)
    except ImportError as err:
        raise ValueError(f"q_network {spec!r}: cannot import {module_name!r} ({err})") from err
    factory = getattr(module, attr, None)
    if not callable(factory):
        raise ValueError(f"q_network {spec!r}: {module_name} has no function {attr!r}")
    return factory


def check_q_network(module: nn.Module, input_shapes: list[tuple[int, ...]], input_dtypes: list[torch.dtype],
                    n_actions: int, source: str) -> nn.Module:
    """Call ``module`` on a batch of two zero inputs; ValueError unless it returns (2, n_actions)."""
    if not isinstance(module, nn.Module):
        raise ValueError(f"{source} returned {type(module).__name__}, not a torch.nn.Module")
    inputs = [torch.zeros((2, *s), dtype=d) for s, d in zip(input_shapes, input_dtypes)]
    was_training = module.training
    module.eval()
    with torch.no_grad():
        try:
            out = module(*inputs)
        except Exception as err:  # a shape mismatch inside the user's layers
            raise ValueError(f"{source}: calling it on inputs of shapes {input_shapes} failed: {err}") from err
    module.train(was_training)
    if not isinstance(out, torch.Tensor) or tuple(out.shape) != (2, n_actions):
        shape = tuple(out.shape) if isinstance(out, torch.Tensor) else type(out).__name__
        raise ValueError(f"{source}: expected Q-values of shape (batch, {n_actions}), got {shape}")
    return module


def q_values_of(module: nn.Module, x, device: torch.device | str = "cpu") -> np.ndarray:
    """Q-values (actions,) of one observation's input ``x`` (an array, or a tuple of arrays for a
    network with several inputs), as a numpy array; ``module`` is switched to evaluation mode (no
    random shifts). The one way the learner and trained policies compute them."""
    inputs = x if isinstance(x, tuple) else (x,)
    if module.training:
        module.eval()
    with torch.inference_mode():
        tensors = [torch.as_tensor(np.asarray(v))[None].to(device) for v in inputs]
        return module(*tensors)[0].float().cpu().numpy()
