"""Fitting the student to the teacher's labels: a classifier over the three actions.

The student's network is a DQN Q-network (``agents.core.policy.build_q_network``): its outputs
are read as the logits of the teacher's action, trained with the cross-entropy, so its greedy
action (the argmax) is the action it imitates. ``fit`` runs ``epochs`` passes over the data in
shuffled minibatches (Adam) and reports the loss and the accuracy on the states it fitted and
on held-out ones. Given held-out states, it keeps the weights of the epoch that agreed best
with their labels (early stopping): the last epochs of a long fit learn the fitted states by
heart and agree less with new ones. A student with memory (``RecurrentQNetwork``) learns from whole episodes
instead (``fit_sequences``): minibatches of episodes, padded to the longest, each unrolled from
a zero hidden state as the student will act, the loss averaged over the real steps.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

from agents.core.recurrent import RecurrentQNetwork


@dataclass
class FitReport:
    """How a fit went: the last epoch's mean loss, and accuracies (share of states whose argmax
    is the teacher's label) on the fitted and the held-out states (None without held-out states)."""

    loss: float
    train_accuracy: float
    validation_accuracy: Optional[float]
    updates: int
    best_epoch: Optional[int] = None
    """the epoch (from 1) whose weights were kept, by held-out accuracy (None without held-out states)"""


class _BestEpoch:
    """The weights of the epoch with the best held-out accuracy so far (early stopping)."""

    def __init__(self, net: nn.Module, score: Optional[Callable[[], float]]):
        self.net, self.score = net, score
        self.best, self.epoch, self.weights = -1.0, None, None

    def seen(self, epoch: int) -> None:
        if self.score is None:
            return
        value = self.score()
        if value > self.best:
            self.best, self.epoch = value, epoch
            self.weights = {k: v.detach().clone() for k, v in self.net.state_dict().items()}

    def restore(self) -> Optional[float]:
        """Load the best epoch's weights; its held-out accuracy (None without held-out states)."""
        if self.weights is None:
            return None
        self.net.load_state_dict(self.weights)
        return self.best


def accuracy(net: nn.Module, x: np.ndarray, labels: np.ndarray, batch: int = 4096) -> float:
    """Share of the states ``x`` (network inputs) where ``net``'s argmax is the label."""
    if len(x) == 0:
        return float("nan")
    net.eval()
    hits = 0
    with torch.inference_mode():
        for i in range(0, len(x), batch):
            out = net(torch.as_tensor(x[i:i + batch]))
            hits += int((out.argmax(1).numpy() == labels[i:i + batch]).sum())
    return hits / len(x)


def fit(net: nn.Module, x: np.ndarray, labels: np.ndarray, epochs: int, batch_size: int, learning_rate: float,
        rng: np.random.Generator, held_out: Optional[tuple[np.ndarray, np.ndarray]] = None,
        on_epoch: Optional[Callable[[float], None]] = None) -> FitReport:
    """Train ``net`` to give the teacher's ``labels`` for inputs ``x`` (float32, already scaled);
    ``on_epoch(mean loss)`` is called after every epoch."""
    xt, yt = torch.as_tensor(x), torch.as_tensor(labels)

    def batches(order):
        for i in range(0, len(order), batch_size):
            idx = torch.as_tensor(order[i:i + batch_size])
            yield F.cross_entropy(net(xt[idx]), yt[idx])

    score = (lambda: accuracy(net, *held_out)) if held_out is not None and len(held_out[0]) else None
    loss, updates, best = _epochs(net, len(x), batches, epochs, learning_rate, rng, score, on_epoch)
    return FitReport(loss, accuracy(net, x, labels), best.restore(), updates, best.epoch)


def _epochs(net: nn.Module, n: int, batches, epochs: int, learning_rate: float, rng: np.random.Generator,
            score: Optional[Callable[[], float]], on_epoch: Optional[Callable[[float], None]]):
    """The loop both fits share: per epoch, Adam steps on the losses ``batches(shuffled order)`` yields,
    then ``on_epoch`` and the early-stopping check; returns (last epoch's mean loss, updates, the best epoch)."""
    optimizer = torch.optim.Adam(net.parameters(), lr=learning_rate)
    best, updates, mean = _BestEpoch(net, score), 0, 0.0
    for epoch in range(1, epochs + 1):
        net.train()
        total, count = 0.0, 0
        for loss in batches(rng.permutation(n)):
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            optimizer.step()
            total, count, updates = total + loss.item(), count + 1, updates + 1
        mean = total / max(count, 1)
        if on_epoch is not None:
            on_epoch(mean)
        best.seen(epoch)
    return mean, updates, best


def _padded(episodes: list[np.ndarray], labels: list[np.ndarray]):
    """(x (b, t, d), labels (b, t), mask (b, t)) of episodes padded to the longest."""
    t = max(len(e) for e in episodes)
    x = np.zeros((len(episodes), t, episodes[0].shape[1]), dtype=np.float32)
    y = np.zeros((len(episodes), t), dtype=np.int64)
    mask = np.zeros((len(episodes), t), dtype=np.float32)
    for i, (e, lab) in enumerate(zip(episodes, labels)):
        x[i, :len(e)], y[i, :len(e)], mask[i, :len(e)] = e, lab, 1.0
    return torch.as_tensor(x), torch.as_tensor(y), torch.as_tensor(mask)


def sequence_accuracy(net: nn.Module, episodes: list[np.ndarray], labels: list[np.ndarray], batch: int = 64) -> float:
    """Share of the steps where the recurrent ``net``, unrolled over each episode, picks the label."""
    if not episodes:
        return float("nan")
    net.eval()
    hits = total = 0
    with torch.inference_mode():
        for i in range(0, len(episodes), batch):
            x, y, mask = _padded(episodes[i:i + batch], labels[i:i + batch])
            q, _ = net(x)
            hits += int(((q.argmax(-1) == y).float() * mask).sum())
            total += int(mask.sum())
    return hits / total


def fit_sequences(net: nn.Module, episodes: list[np.ndarray], labels: list[np.ndarray], epochs: int, batch_size: int,
                  learning_rate: float, rng: np.random.Generator,
                  held_out: Optional[tuple[list[np.ndarray], list[np.ndarray]]] = None,
                  on_epoch: Optional[Callable[[float], None]] = None) -> FitReport:
    """``fit`` for a recurrent student: ``episodes`` (each (steps, d), scaled) and their labels;
    ``batch_size`` counts states, so a minibatch holds about batch_size / mean length episodes."""
    per_batch = max(1, int(round(batch_size / np.mean([len(e) for e in episodes]))))

    def batches(order):
        for i in range(0, len(order), per_batch):
            pick = order[i:i + per_batch]
            x, y, mask = _padded([episodes[j] for j in pick], [labels[j] for j in pick])
            q, _ = net(x)
            each = F.cross_entropy(q.reshape(-1, q.shape[-1]), y.reshape(-1), reduction="none")
            yield (each * mask.reshape(-1)).sum() / mask.sum()

    score = (lambda: sequence_accuracy(net, *held_out)) if held_out is not None and held_out[0] else None
    loss, updates, best = _epochs(net, len(episodes), batches, epochs, learning_rate, rng, score, on_epoch)
    return FitReport(loss, sequence_accuracy(net, episodes, labels), best.restore(), updates, best.epoch)


def fit_rollouts(net: nn.Module, features, rollouts: list, held_out: list, epochs: int, batch_size: int,
                 learning_rate: float, rng: np.random.Generator,
                 on_epoch: Optional[Callable[[float], None]] = None) -> FitReport:
    """Fit ``net`` to the labels of ``rollouts`` (``Rollout``s), their observations scaled by
    ``features``: state by state, or episode by episode for a recurrent network; ``held_out``:
    rollouts to report the accuracy on (may be empty)."""
    def scaled(r):
        return features(r.observations[:-1]).astype(np.float32)

    if isinstance(net, RecurrentQNetwork):
        held = ([scaled(r) for r in held_out], [r.labels for r in held_out]) if held_out else None
        return fit_sequences(net, [scaled(r) for r in rollouts], [r.labels for r in rollouts], epochs, batch_size,
                             learning_rate, rng, held, on_epoch)
    x, y = np.concatenate([scaled(r) for r in rollouts]), np.concatenate([r.labels for r in rollouts])
    held = (np.concatenate([scaled(r) for r in held_out]), np.concatenate([r.labels for r in held_out])) if held_out \
        else None
    return fit(net, x, y, epochs, batch_size, learning_rate, rng, held, on_epoch)
