"""Replay memory: preallocated numpy arrays used as a ring buffer of transitions, and the
minibatch (``Batch``) that the replay memories fill and the learner (``agents.core.learner``)
trains on. The learner uses the buffers; the buffers never use the learner."""

from __future__ import annotations

from typing import Sequence

import numpy as np
import torch


class Batch:
    """Preallocated minibatch tensors, with numpy views (``obs``, ``actions``, ...) that the replay
    memories fill in place.

    ``inputs`` lists each input's (shape, numpy dtype) without the batch dimension: one float32
    vector for state runs, a uint8 frame and float32 state parts for pixel runs."""

    def __init__(self, batch_size: int, inputs: Sequence[tuple[tuple[int, ...], type]]):
        self.size = int(batch_size)
        self.inputs = [(tuple(int(v) for v in shape), np.dtype(dtype)) for shape, dtype in inputs]

        def new(shape, dtype):
            return torch.from_numpy(np.zeros((self.size, *shape), dtype=dtype))

        self.obs_t = [new(s, d) for s, d in self.inputs]
        self.next_obs_t = [new(s, d) for s, d in self.inputs]
        self.actions_t, self.rewards_t, self.not_done_t = new((), np.int64), new((), np.float32), new((), np.float32)
        self.obs = [t.numpy() for t in self.obs_t]
        self.next_obs = [t.numpy() for t in self.next_obs_t]
        self.actions, self.rewards = self.actions_t.numpy(), self.rewards_t.numpy()
        self.not_done = self.not_done_t.numpy()
        """1 - terminated: a truncated (timed-out) transition still bootstraps"""
        self.labels_t = torch.full((self.size,), -1, dtype=torch.int64)
        self.labels = self.labels_t.numpy()
        """a teacher's action for the rows drawn from demonstrations (``demo_replay.DemoReplay``), -1
        for the others; only a learner with a ``margin_weight`` reads them"""


class ReplayMemory:
    """Holds the last ``capacity`` transitions (s, a, r, s', 1 - terminated)."""

    def __init__(self, capacity: int, obs_dim: int):
        if capacity < 1:
            raise ValueError(f"replay memory capacity must be positive, got {capacity}")
        self.capacity, self.obs_dim = int(capacity), int(obs_dim)
        self.obs = np.zeros((capacity, obs_dim), dtype=np.float32)
        self.next_obs = np.zeros((capacity, obs_dim), dtype=np.float32)
        self.actions = np.zeros(capacity, dtype=np.int64)
        self.rewards = np.zeros(capacity, dtype=np.float32)
        self.not_done = np.zeros(capacity, dtype=np.float32)
        self.pos = 0
        """index the next transition is written to"""
        self.size = 0
        """number of transitions held"""

    def __len__(self) -> int:
        return self.size

    def add(self, obs, action: int, reward: float, next_obs, terminated: bool) -> None:
        """Store one transition; a truncated (timed-out) step is stored as not terminated."""
        i = self.pos
        self.obs[i] = obs
        self.next_obs[i] = next_obs
        self.actions[i] = action
        self.rewards[i] = reward
        self.not_done[i] = 0.0 if terminated else 1.0
        self.pos = (i + 1) % self.capacity
        self.size = min(self.size + 1, self.capacity)

    def sample_into(self, batch: Batch, rng: np.random.Generator) -> None:
        """Copy a uniformly drawn minibatch (with replacement) into ``batch``'s arrays."""
        idx = rng.integers(0, self.size, size=len(batch.actions))
        np.take(self.obs, idx, axis=0, out=batch.obs[0])
        np.take(self.next_obs, idx, axis=0, out=batch.next_obs[0])
        np.take(self.actions, idx, out=batch.actions)
        np.take(self.rewards, idx, out=batch.rewards)
        np.take(self.not_done, idx, out=batch.not_done)

    # ------------------------------------------------------------------ checkpoints
    def state_dict(self) -> dict:
        """The filled part only (a checkpoint early in training stays small)."""
        n = self.size
        return dict(
            capacity=self.capacity, obs_dim=self.obs_dim, pos=self.pos, size=n,
            obs=self.obs[:n].copy(), next_obs=self.next_obs[:n].copy(), actions=self.actions[:n].copy(),
            rewards=self.rewards[:n].copy(), not_done=self.not_done[:n].copy(),
        )

    def load_state_dict(self, state: dict) -> None:
        """Restore what ``state_dict`` saved; ValueError if the sizes differ from this memory's."""
        if (state["capacity"], state["obs_dim"]) != (self.capacity, self.obs_dim):
            raise ValueError(
                f"checkpoint replay memory holds {state['capacity']} x {state['obs_dim']} transitions, "
                f"this one {self.capacity} x {self.obs_dim}"
            )
        n = int(state["size"])
        for name in ("obs", "next_obs", "actions", "rewards", "not_done"):
            getattr(self, name)[:n] = state[name]
        self.size, self.pos = n, int(state["pos"])
