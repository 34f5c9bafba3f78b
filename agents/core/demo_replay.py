"""Demonstrations kept in the replay, as in DQfD (Hester et al. 2018): a share of every minibatch.

``DemoReplay`` holds a teacher's transitions (``Demonstrations.transitions()``, their
observations already turned into network inputs) for the whole run: the agent's own replay
memory fills a minibatch, then ``sample_into`` overwrites its first ``share`` of rows with
demonstration transitions and their labels (the teacher's action in that state; -1 in the
agent's own rows). The learner's large-margin loss (``DQNLearner.margin_weight``) reads the
labels: it pushes Q(s, label) above every other action's Q(s, a) by ``margin``, on the
demonstrations only, while the TD loss learns from every row.
"""

from __future__ import annotations

import numpy as np

from agents.core.replay import Batch


class DemoReplay:
    """A fixed store of demonstration transitions that fills part of each minibatch."""

    def __init__(self, obs: np.ndarray, next_obs: np.ndarray, actions: np.ndarray, rewards: np.ndarray,
                 not_done: np.ndarray, labels: np.ndarray, share: float):
        n = len(actions)
        if n == 0:
            raise ValueError("the demonstrations hold no transition")
        if not all(len(a) == n for a in (obs, next_obs, rewards, not_done, labels)):
            raise ValueError("every array of the demonstrations must have one row per transition")
        if not 0.0 < share <= 1.0:
            raise ValueError(f"the demonstrations' share of a minibatch must be in (0, 1]; got {share!r}")
        self.obs, self.next_obs = np.ascontiguousarray(obs, np.float32), np.ascontiguousarray(next_obs, np.float32)
        self.actions, self.labels = np.asarray(actions, np.int64), np.asarray(labels, np.int64)
        self.rewards, self.not_done = np.asarray(rewards, np.float32), np.asarray(not_done, np.float32)
        self.share = float(share)

    def __len__(self) -> int:
        return len(self.actions)

    def rows(self, batch: Batch) -> int:
        """How many rows of ``batch`` the demonstrations fill."""
        return max(1, int(round(self.share * batch.size)))

    def sample_into(self, batch: Batch, rng: np.random.Generator, rows: int | None = None) -> None:
        """Overwrite the first ``rows`` (default ``rows(batch)``) rows of ``batch`` with uniformly drawn
        demonstration transitions and their labels; mark every other row unlabelled (-1)."""
        k = self.rows(batch) if rows is None else int(rows)
        idx = rng.integers(0, len(self), size=k)
        np.take(self.obs, idx, axis=0, out=batch.obs[0][:k])
        np.take(self.next_obs, idx, axis=0, out=batch.next_obs[0][:k])
        np.take(self.actions, idx, out=batch.actions[:k])
        np.take(self.rewards, idx, out=batch.rewards[:k])
        np.take(self.not_done, idx, out=batch.not_done[:k])
        np.take(self.labels, idx, out=batch.labels[:k])
        batch.labels[k:] = -1
