"""Fitting the student to the teacher's labels: a classifier over the three actions.

The student's network is a DQN Q-network (``agents.core.policy.build_q_network``): its outputs
are read as the logits of the teacher's action, trained with the cross-entropy, so its greedy
action (the argmax) is the action it imitates. ``fit`` runs ``epochs`` passes over the data in
shuffled minibatches (Adam) and reports the loss and the accuracy on the states it fitted and
on held-out ones.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F


@dataclass
class FitReport:
    """How a fit went: the last epoch's mean loss, and accuracies (share of states whose argmax
    is the teacher's label) on the fitted and the held-out states (None without held-out states)."""

    loss: float
    train_accuracy: float
    validation_accuracy: Optional[float]
    updates: int


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
    optimizer = torch.optim.Adam(net.parameters(), lr=learning_rate)
    xt, yt = torch.as_tensor(x), torch.as_tensor(labels)
    updates, loss_sum, batches = 0, 0.0, 0
    for _ in range(epochs):
        net.train()
        order = torch.as_tensor(rng.permutation(len(x)))
        loss_sum, batches = 0.0, 0
        for i in range(0, len(x), batch_size):
            idx = order[i:i + batch_size]
            loss = F.cross_entropy(net(xt[idx]), yt[idx])
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            optimizer.step()
            loss_sum, batches, updates = loss_sum + loss.item(), batches + 1, updates + 1
        if on_epoch is not None:
            on_epoch(loss_sum / max(batches, 1))
    validation = accuracy(net, *held_out) if held_out is not None and len(held_out[0]) else None
    return FitReport(loss_sum / max(batches, 1), accuracy(net, x, labels), validation, updates)
