"""Replay memories in shared memory, for the fast mode: the collecting process adds transitions,
the learner process (``agents.training.learner_process``) samples them, both on the same arrays.

``SharedReplayMemory`` is a ``ReplayMemory`` (state-vector runs) and ``SharedFrameReplay`` a
``FrameReplay`` (pixel runs) whose arrays and counters are torch tensors in shared memory, seen
through numpy; they cross into a ``torch.multiprocessing`` child without copying. A transition's
data is written before the counters that make it visible, so the learner never samples a slot
that holds nothing yet (it may rarely draw a slot the collector is overwriting: Ape-X's trade).
"""

from __future__ import annotations

import numpy as np
import torch

from agents.core.frame_replay import FrameReplay
from agents.core.replay import ReplayMemory


def shared_arrays(specs: dict) -> dict:
    """Zeroed tensors in shared memory: ``specs`` maps a name to (shape, numpy dtype)."""
    out = {}
    for name, (shape, dtype) in specs.items():
        out[name] = torch.from_numpy(np.zeros(shape, dtype=dtype)).share_memory_()
    return out


def counter(index: int, doc: str) -> property:
    """An integer attribute kept in slot ``index`` of the shared ``_counters`` array."""

    def set_value(self, value: int) -> None:
        self._counters[index] = value

    return property(lambda self: int(self._counters[index]), set_value, doc=doc)


def attach(memory, tensors: dict) -> None:
    """Give ``memory`` numpy views of the shared ``tensors`` under their names (``counters``: ``_counters``)."""
    memory.tensors = tensors
    for name, t in tensors.items():
        setattr(memory, "_counters" if name == "counters" else name, t.numpy())


class SharedReplayMemory(ReplayMemory):
    """A ``ReplayMemory`` in shared memory: one process adds, another samples."""

    pos = counter(0, "index the next transition is written to")
    size = counter(1, "number of transitions held")

    def __init__(self, capacity: int, obs_dim: int, tensors: dict | None = None):
        if capacity < 1:
            raise ValueError(f"replay memory capacity must be positive, got {capacity}")
        self.capacity, self.obs_dim = int(capacity), int(obs_dim)
        attach(self, tensors or shared_arrays(dict(
            obs=((capacity, obs_dim), np.float32), next_obs=((capacity, obs_dim), np.float32),
            actions=((capacity,), np.int64), rewards=((capacity,), np.float32), not_done=((capacity,), np.float32),
            counters=((2,), np.int64))))

    def __reduce__(self):
        return SharedReplayMemory, (self.capacity, self.obs_dim, self.tensors)


class SharedFrameReplay(FrameReplay):
    """A ``FrameReplay`` in shared memory (pixel runs): one process adds frames, another samples."""

    pos = counter(0, "slot the next observation is written to")
    size = counter(1, "slots holding an observation")
    last = counter(2, "slot of the newest observation (-1: none yet)")

    def __init__(self, capacity: int, frame_shape: tuple[int, ...], state_dim: int, latent_dim: int = 0,
                 tensors: dict | None = None):
        if capacity < 2:
            raise ValueError(f"the frame replay memory needs at least 2 slots, got {capacity}")
        self.capacity, self.frame_shape = int(capacity), tuple(int(v) for v in frame_shape)
        self.state_dim, self.latent_dim = int(state_dim), int(latent_dim)
        if tensors is None:
            tensors = shared_arrays(dict(
                frames=((capacity, *self.frame_shape), np.uint8), states=((capacity, state_dim), np.float32),
                latents=((capacity, latent_dim), np.float32), actions=((capacity,), np.int64),
                rewards=((capacity,), np.float32), not_done=((capacity,), np.float32),
                has_next=((capacity,), np.bool_), counters=((3,), np.int64)))
            tensors["counters"][2] = -1  # last: no observation yet
        attach(self, tensors)

    def __reduce__(self):
        return SharedFrameReplay, (self.capacity, self.frame_shape, self.state_dim, self.latent_dim, self.tensors)
