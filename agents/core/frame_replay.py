"""The replay memory of the camera runs: every camera frame stored once, as uint8.

It is also the observation memory the auto-encoder trains on (thesis Alg. 2), so frames are
kept in one place. Like DQN's Atari replay, observations are stored in the order they arrive,
one slot per observation; slot i's transition is (frame i, action i, reward i, frame i + 1),
valid when the observation after slot i was stored there (``has_next``). An episode's
first observation starts a new slot without a transition leading to it, so an episode of
n steps takes n + 1 slots, not 2n frames.

Beside each frame a slot holds the scaled parts of the task's state vector that the
Q-network reads with the latent (Table 5.4: lasers, positions) and a cache of the frame's
latent vector. The cache is written when the frame is encoded to act on it and rewritten
for every stored frame after each auto-encoder update (``refresh_latents``), so replayed
transitions are always seen through the current encoder.

A recurrent Q-network's state-vector runs keep their scaled state vectors here as the state
parts, with frames of shape (0,): its sequences need the slots' episode order
(``agents.core.sequence_replay``).

Memory: one 32x32 RGB frame is 3,072 bytes (a stack of four gray frames 4,096), so the
default 100,000 slots hold 307 MB (410 MB) of frames; ``nbytes`` gives the total.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from agents.core.replay import Batch


class FrameReplay:
    """A ring buffer of ``capacity`` observations (frame, state parts, latent) and their transitions."""

    def __init__(self, capacity: int, frame_shape: tuple[int, ...], state_dim: int, latent_dim: int):
        if capacity < 2:
            raise ValueError(f"the frame replay memory needs at least 2 slots, got {capacity}")
        self.capacity, self.frame_shape = int(capacity), tuple(frame_shape)
        self.state_dim, self.latent_dim = int(state_dim), int(latent_dim)
        self.frames = np.zeros((capacity, *frame_shape), dtype=np.uint8)
        self.states = np.zeros((capacity, state_dim), dtype=np.float32)
        self.latents = np.zeros((capacity, latent_dim), dtype=np.float32)
        self.actions = np.zeros(capacity, dtype=np.int64)
        self.rewards = np.zeros(capacity, dtype=np.float32)
        self.not_done = np.zeros(capacity, dtype=np.float32)
        self.has_next = np.zeros(capacity, dtype=bool)
        self.pos = 0
        """slot the next observation is written to"""
        self.size = 0
        """slots holding an observation"""
        self.last = -1
        """slot of the newest observation (-1: none yet)"""

    def __len__(self) -> int:
        """Number of complete transitions held."""
        return int(np.count_nonzero(self.has_next[: self.size]))

    @property
    def nbytes(self) -> int:
        """Bytes held by the memory's arrays."""
        arrays = (self.frames, self.states, self.latents, self.actions, self.rewards, self.not_done, self.has_next)
        return int(sum(a.nbytes for a in arrays))

    # ------------------------------------------------------------------ writing
    def _put(self, frame: np.ndarray, state: np.ndarray) -> int:
        if frame.dtype != np.uint8 or frame.shape != self.frame_shape:
            raise ValueError(f"expected a uint8 frame of shape {self.frame_shape}, got {frame.dtype} {frame.shape}")
        i = self.pos
        self.frames[i] = frame
        self.states[i] = state
        self.latents[i] = 0.0
        self.has_next[i] = False  # the transition that started here belonged to an overwritten episode
        self.last = i
        self.pos = (i + 1) % self.capacity
        self.size = min(self.size + 1, self.capacity)
        return i

    def start(self, frame: np.ndarray, state: np.ndarray) -> int:
        """Store an episode's first observation; returns its slot."""
        return self._put(frame, state)

    def add(self, action: int, reward: float, frame: np.ndarray, state: np.ndarray, terminated: bool) -> int:
        """Complete the newest observation's transition with the observation after it; returns its slot.

        A truncated (timed-out) step is stored as not terminated, so it bootstraps."""
        if self.last < 0:
            raise RuntimeError("FrameReplay.add before start: store the episode's first observation first")
        i = self.last
        self.actions[i] = action
        self.rewards[i] = reward
        self.not_done[i] = 0.0 if terminated else 1.0
        j = self._put(frame, state)
        self.has_next[i] = True
        return j

    # ------------------------------------------------------------------ reading
    def valid_indices(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """``n`` slots drawn uniformly (with replacement) among those with a complete transition."""
        if not self.has_next[: self.size].any():
            raise ValueError("the frame replay memory holds no complete transition yet")
        idx = rng.integers(0, self.size, size=n)
        bad = ~self.has_next[idx]
        while bad.any():  # about one slot per episode has no transition: redraw those
            idx[bad] = rng.integers(0, self.size, size=int(bad.sum()))
            bad = ~self.has_next[idx]
        return idx

    def sample_into(self, batch: Batch, rng: np.random.Generator) -> None:
        """A minibatch of transitions as Q-network inputs [latent | state parts] into ``batch``."""
        idx, nxt = self._transitions(batch, rng)
        z = self.latent_dim
        batch.obs[0][:, :z], batch.obs[0][:, z:] = self.latents[idx], self.states[idx]
        batch.next_obs[0][:, :z], batch.next_obs[0][:, z:] = self.latents[nxt], self.states[nxt]

    def sample_frames_into(self, batch: Batch, rng: np.random.Generator) -> None:
        """A minibatch of transitions as (frames, state parts) into ``batch`` (pixel runs)."""
        idx, nxt = self._transitions(batch, rng)
        np.take(self.frames, idx, axis=0, out=batch.obs[0])
        np.take(self.frames, nxt, axis=0, out=batch.next_obs[0])
        np.take(self.states, idx, axis=0, out=batch.obs[1])
        np.take(self.states, nxt, axis=0, out=batch.next_obs[1])

    def _transitions(self, batch: Batch, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """Slots of a minibatch's transitions and of their next observations; fills actions, rewards, not_done."""
        idx = self.valid_indices(len(batch.actions), rng)
        np.take(self.actions, idx, out=batch.actions)
        np.take(self.rewards, idx, out=batch.rewards)
        np.take(self.not_done, idx, out=batch.not_done)
        return idx, (idx + 1) % self.capacity

    def sample_frames(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """``n`` stored frames drawn uniformly (with replacement), for the auto-encoder."""
        if self.size == 0:
            raise ValueError("the frame replay memory is empty")
        return self.frames[rng.integers(0, self.size, size=n)]

    def refresh_latents(self, encode: Callable[[np.ndarray], np.ndarray], chunk: int = 2048) -> None:
        """Re-encode every stored frame with ``encode`` (uint8 frames -> latents)."""
        for start in range(0, self.size, chunk):
            end = min(start + chunk, self.size)
            self.latents[start:end] = encode(self.frames[start:end])

    # ------------------------------------------------------------------ checkpoints
    def state_dict(self) -> dict:
        """The filled slots only (views: pickling copies them once)."""
        n = self.size
        arrays = {k: getattr(self, k)[:n] for k in ("frames", "states", "latents", "actions", "rewards",
                                                     "not_done", "has_next")}
        return dict(capacity=self.capacity, frame_shape=self.frame_shape, state_dim=self.state_dim,
                    latent_dim=self.latent_dim, pos=self.pos, size=n, last=self.last, **arrays)

    def load_state_dict(self, state: dict) -> None:
        """Restore what ``state_dict`` saved; ValueError if the sizes differ from this memory's."""
        theirs = (state["capacity"], tuple(state["frame_shape"]), state["state_dim"], state["latent_dim"])
        ours = (self.capacity, self.frame_shape, self.state_dim, self.latent_dim)
        if theirs != ours:
            raise ValueError(f"checkpoint frame replay is (capacity, frame, state, latent) = {theirs}, this one {ours}")
        n = int(state["size"])
        for k in ("frames", "states", "latents", "actions", "rewards", "not_done", "has_next"):
            getattr(self, k)[:n] = state[k]
        self.pos, self.size, self.last = int(state["pos"]), n, int(state["last"])
