"""Sequences of stored episodes for a recurrent Q-network (see docs/memory.md).

The sequences are read from a ``FrameReplay``: it stores every observation once, in the order
they arrive, so an episode is a run of consecutive slots and slot i's transition leads to
slot i + 1 (``has_next``). A state-vector run keeps its scaled state vectors there as the
state parts, without frames (``frame_shape`` (0,)); a camera run keeps its frames, state parts
and latents, which each auto-encoder update re-encodes (``FrameReplay.refresh_latents``), so a
replayed sequence is always seen through the current encoder. The Q-network's input at a slot
is [latent | state parts].

A minibatch row is a window of ``burn_in + length`` transitions:

1. a slot u with a complete transition is drawn uniformly: the first step that carries the loss;
2. the window starts up to ``burn_in`` slots earlier, never before u's episode started (nor
   before the oldest slot held): b = min(burn_in, steps of u's episode before u);
3. step t of the window (slot start + t) carries the loss when b <= t < b + length and the
   episode has not ended before it (every slot from the window's start to t has a transition);
   later steps are padding (mask 0).

Both networks start every window from a zero state (R2D2's "zero start state" with a burn-in,
Kapturowski et al. 2019, rather than a stored state): a window that starts at its episode's
first step starts from exactly the state the agent had, the others get up to ``burn_in`` steps
to warm up; no stored state goes stale when the network or the auto-encoder changes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch


class SequenceBatch:
    """Preallocated minibatch of windows; ``*_t`` are torch tensors sharing memory with the numpy arrays.

    ``obs`` (size, window + 1, inputs) holds the inputs of the window's observations (the last one is
    the observation after its last transition); ``actions``, ``rewards``, ``not_done`` and ``mask``
    (size, window) its transitions."""

    def __init__(self, size: int, length: int, burn_in: int, input_dim: int):
        if size < 1 or length < 1 or burn_in < 0 or input_dim < 1:
            raise ValueError(f"a sequence batch needs size >= 1, length >= 1, burn_in >= 0 and inputs >= 1; "
                             f"got {size}, {length}, {burn_in}, {input_dim}")
        self.size, self.length, self.burn_in, self.input_dim = int(size), int(length), int(burn_in), int(input_dim)
        self.window = self.burn_in + self.length
        """transitions per row"""

        def new(shape, dtype):
            return torch.from_numpy(np.zeros(shape, dtype=dtype))

        self.obs_t = new((self.size, self.window + 1, self.input_dim), np.float32)
        self.actions_t = new((self.size, self.window), np.int64)
        self.rewards_t = new((self.size, self.window), np.float32)
        self.not_done_t = new((self.size, self.window), np.float32)
        self.mask_t = new((self.size, self.window), np.float32)
        self.obs, self.actions, self.rewards = self.obs_t.numpy(), self.actions_t.numpy(), self.rewards_t.numpy()
        self.not_done, self.mask = self.not_done_t.numpy(), self.mask_t.numpy()


@dataclass
class Windows:
    """Where a minibatch's windows lie in the memory."""

    slots: np.ndarray
    """(rows, window + 1) the slot of every observation of each window"""
    burn: np.ndarray
    """(rows,) burn-in steps of each window (from 0 to burn_in)"""
    mask: np.ndarray
    """(rows, window) bool: the transition carries the loss"""


def draw_windows(memory, rows: int, length: int, burn_in: int, rng: np.random.Generator) -> Windows:
    """``rows`` windows of ``burn_in + length`` transitions in ``memory`` (a ``FrameReplay``), as the
    module's docstring says; ValueError if it holds no complete transition."""
    first = memory.valid_indices(rows, rng)  # the first step with loss of each window
    cap = memory.capacity
    oldest = memory.pos if memory.size == cap else 0
    held_before = (first - oldest) % cap  # slots held before ``first``
    back = np.arange(1, burn_in + 1)
    earlier = (first[:, None] - back[None]) % cap
    same_episode = memory.has_next[earlier] & (back[None] <= held_before[:, None])
    burn = np.cumprod(same_episode, axis=1).sum(axis=1) if burn_in else np.zeros(rows, dtype=np.int64)
    window = burn_in + length
    slots = ((first - burn)[:, None] + np.arange(window + 1)[None]) % cap
    running = np.cumprod(memory.has_next[slots[:, :-1]], axis=1).astype(bool)  # the episode goes on
    steps = np.arange(window)[None]
    mask = running & (steps >= burn[:, None]) & (steps < burn[:, None] + length)
    return Windows(slots, burn.astype(np.int64), mask)


def sample_sequences_into(memory, batch: SequenceBatch, rng: np.random.Generator) -> Windows:
    """Fill ``batch`` with windows drawn from ``memory`` (inputs [latent | state parts]); returns them."""
    w = draw_windows(memory, batch.size, batch.length, batch.burn_in, rng)
    z = memory.latent_dim
    if z + memory.state_dim != batch.input_dim:
        raise ValueError(f"the memory's inputs have {z + memory.state_dim} values, the batch's {batch.input_dim}")
    batch.obs[:, :, :z] = memory.latents[w.slots]
    batch.obs[:, :, z:] = memory.states[w.slots]
    transitions = w.slots[:, :-1]
    np.take(memory.actions, transitions, out=batch.actions)
    np.take(memory.rewards, transitions, out=batch.rewards)
    np.take(memory.not_done, transitions, out=batch.not_done)
    batch.mask[:] = w.mask
    return w
