"""Encoders for the egocentric state's parts: a 1-D convolution over the laser scan, and an
encoder of the tracked obstacles that ignores their order.

The egocentric state (``dynnav_tasks/egocentric.py``) is ``lasers (n) | target (3) [| way (3)] |
k obstacle slots of 5 (x, y, vx, vy, present)``. A flat MLP reads it as one vector: it must learn
the same lesson at every ray (a wall 0.4 m ahead is as near as one 0.4 m to the left) and at every
slot (the nearest box is slot 0 only by the order of the distances). ``EgocentricQNetwork``
gives it the structure instead:

* ``laser_encoder="conv"``: two 1-D convolutions (kernel 5, circular padding, since ray n - 1
  neighbours ray 0 on a full ring; the second with stride 2) slide one filter bank round the
  ring, then a linear layer; the same weights read 16, 64 or 180 rays;
* ``obstacle_encoder="pooled"``: each slot through one shared MLP, then the maximum over the
  present slots (Deep Sets, Zaheer et al. 2017; SARL pools its humans with attention): the same
  boxes in any order give the same features, and an empty slot counts for nothing;
* the features of the parts and the target and way values go through the MLP head
  (``hidden_sizes``) to one Q-value per action. A part left ``"flat"`` enters the head as it is.
"""

from __future__ import annotations

from typing import Sequence

import torch
from torch import nn

LASER_ENCODERS = ("flat", "conv")
OBSTACLE_ENCODERS = ("flat", "pooled")
SLOT = 5
"""values per obstacle slot (x, y, vx, vy, present)"""
CONV_CHANNELS = 16
FEATURES = 64
"""width of each encoder's output"""


class LaserConv(nn.Module):
    """A laser ring (batch, n) -> (batch, FEATURES): two circular 1-D convolutions and a linear layer."""

    def __init__(self, rays: int):
        super().__init__()
        self.conv = nn.Sequential(
            nn.Conv1d(1, CONV_CHANNELS, 5, padding=2, padding_mode="circular"), nn.ReLU(),
            nn.Conv1d(CONV_CHANNELS, CONV_CHANNELS, 5, stride=2, padding=2, padding_mode="circular"), nn.ReLU(),
        )
        out = (rays + 2 * 2 - 5) // 2 + 1
        self.linear = nn.Sequential(nn.Linear(CONV_CHANNELS * out, FEATURES), nn.ReLU())

    def forward(self, lasers: torch.Tensor) -> torch.Tensor:
        return self.linear(self.conv(lasers[:, None, :]).flatten(1))


class PooledObstacles(nn.Module):
    """k obstacle slots (batch, k * SLOT) -> (batch, FEATURES): a shared MLP per slot, max over the present ones."""

    def __init__(self):
        super().__init__()
        self.each = nn.Sequential(nn.Linear(SLOT, FEATURES), nn.ReLU(), nn.Linear(FEATURES, FEATURES), nn.ReLU())

    def forward(self, slots: torch.Tensor) -> torch.Tensor:
        slots = slots.reshape(slots.shape[0], -1, SLOT)
        present = slots[..., -1:] > 0  # the scaled "present" flag: 1 -> 1, 0 -> -1
        features = self.each(slots) * present  # ReLU features are >= 0: an absent slot's zeros never win the max
        return features.max(dim=1).values


class EgocentricQNetwork(nn.Module):
    """Q-values from the egocentric state's parts (see the module docstring)."""

    def __init__(self, in_dim: int, n_actions: int, hidden_sizes: Sequence[int], lasers: int, obstacle_k: int,
                 laser_encoder: str = "flat", obstacle_encoder: str = "flat"):
        super().__init__()
        if laser_encoder not in LASER_ENCODERS or obstacle_encoder not in OBSTACLE_ENCODERS:
            raise ValueError(f"laser_encoder must be one of {LASER_ENCODERS} and obstacle_encoder one of "
                             f"{OBSTACLE_ENCODERS}; got {laser_encoder!r}, {obstacle_encoder!r}")
        self.lasers, self.slots = int(lasers), int(obstacle_k) * SLOT
        self.middle = int(in_dim) - self.lasers - self.slots  # target (and way)
        if self.middle < 3:
            raise ValueError(f"a state of {in_dim} values cannot hold {lasers} lasers, the target (3) and "
                             f"{obstacle_k} obstacle slots of {SLOT}: the egocentric state's laser_rays and "
                             f"obstacle_k must be the task's")
        self.laser_net = LaserConv(self.lasers) if laser_encoder == "conv" else None
        self.obstacle_net = PooledObstacles() if obstacle_encoder == "pooled" and self.slots else None
        width = ((FEATURES if self.laser_net is not None else self.lasers) + self.middle
                 + (FEATURES if self.obstacle_net is not None else self.slots))
        sizes = [width, *map(int, hidden_sizes)]
        layers: list[nn.Module] = []
        for fan_in, fan_out in zip(sizes[:-1], sizes[1:]):
            layers += [nn.Linear(fan_in, fan_out), nn.ReLU()]
        self.head = nn.Sequential(*layers, nn.Linear(sizes[-1], int(n_actions)))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """Q-values (batch, actions) of a batch of scaled egocentric states."""
        lasers, middle, slots = x.split([self.lasers, self.middle, self.slots], dim=1)
        parts = [self.laser_net(lasers) if self.laser_net is not None else lasers, middle]
        if self.slots:
            parts.append(self.obstacle_net(slots) if self.obstacle_net is not None else slots)
        return self.head(torch.cat(parts, dim=1))
