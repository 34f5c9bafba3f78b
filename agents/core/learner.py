"""The DQN / Double DQN update for any Q-network module.

``DQNLearner`` holds the online network (a ``torch.nn.Module``), its target copy and Adam, and
makes one gradient step on a minibatch:

    y    = r + gamma * (1 - terminated) * Q_target(s', a*)
           a* = argmax_a Q_target(s', a)  (DQN, Alg. 1)   or   argmax_a Q(s', a)  (Double DQN, App. A)
    loss = mean of (Q(s, a) - y)^2  (mse)   or   smooth L1 with beta 1  (huber)

then optional clipping of the gradient's global norm and one Adam step (torch's fused Adam on the
CPU). With ``margin_weight`` > 0 (learning from demonstrations, DQfD) the loss adds, over the
minibatch rows that carry a teacher's label a_E (``Batch.labels`` >= 0), the large-margin loss

    margin_weight * mean of [ max_a (Q(s, a) + margin * [a != a_E]) - Q(s, a_E) ]

which is 0 once Q(s, a_E) leads every other action by ``margin``. The target network is copied every C steps (``update_target()``) or moved by ``tau``
(``update_target(tau)``).
A module takes the observation's inputs (one tensor for a state vector; frames and state parts
for pixel runs), each with a leading batch dimension, and returns (batch, actions).
"""

from __future__ import annotations

import copy

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

from agents.core.networks import q_values_of
from agents.core.replay import Batch

LOSSES = ("mse", "huber")


def make_adam(module: nn.Module, learning_rate: float) -> torch.optim.Adam:
    """Adam with its state created now (zero moments, step 0), so that it can be shared and saved
    before the first step; fused where every parameter is a float tensor on the CPU or a GPU."""
    params = list(module.parameters())
    fused = all(p.is_floating_point() and p.device.type in ("cpu", "cuda") for p in params)
    optimizer = torch.optim.Adam(params, lr=learning_rate, fused=fused)
    for p in params:
        optimizer.state[p] = dict(step=torch.zeros((), dtype=torch.float32, device=p.device),
                                  exp_avg=torch.zeros_like(p, memory_format=torch.preserve_format),
                                  exp_avg_sq=torch.zeros_like(p, memory_format=torch.preserve_format))
    return optimizer


class DQNLearner:
    """Online and target networks, Adam, and the (Double) DQN update on one ``Batch``."""

    def __init__(self, q_network: nn.Module, batch: Batch, gamma: float = 0.97, double: bool = False,
                 loss: str = "mse", max_grad_norm: float = 0.0, learning_rate: float = 1e-3,
                 device: str = "cpu", margin_weight: float = 0.0, margin: float = 0.8):
        if loss not in LOSSES:
            raise ValueError(f"unknown loss {loss!r}; valid losses: {', '.join(LOSSES)}")
        self.device = torch.device(device)
        self.q = q_network.to(self.device)
        self.target = copy.deepcopy(self.q).requires_grad_(False)
        self.optimizer = make_adam(self.q, learning_rate)
        self.gamma, self.double, self.loss, self.max_grad_norm = gamma, double, loss, max_grad_norm
        self.batch = batch
        self.margin_weight, self.margin = float(margin_weight), float(margin)

    @property
    def learning_rate(self) -> float:
        """Adam's current learning rate (set once per episode by the schedule)."""
        return float(self.optimizer.param_groups[0]["lr"])

    @learning_rate.setter
    def learning_rate(self, value: float) -> None:
        """Adam's current learning rate (set once per episode by the schedule)."""
        for group in self.optimizer.param_groups:
            group["lr"] = float(value)

    # ------------------------------------------------------------------ acting
    recurrent = False
    """whether the Q-network carries a hidden state through an episode (``agents.core.recurrent``)"""

    def reset(self) -> None:
        """An episode starts: nothing to forget for a feed-forward Q-network."""

    def q_values(self, x) -> np.ndarray:
        """Q-values (actions,) of one observation's input (an array, or a tuple of arrays)."""
        return q_values_of(self.q, x, self.device)

    def act(self, x) -> int:
        """The greedy action for one observation's input."""
        return int(np.argmax(self.q_values(x)))

    # ------------------------------------------------------------------ the update
    def _tensors(self):
        b = self.batch
        move = (lambda t: t.to(self.device, non_blocking=True)) if self.device.type != "cpu" else (lambda t: t)
        return ([move(t) for t in b.obs_t], [move(t) for t in b.next_obs_t], move(b.actions_t),
                move(b.rewards_t), move(b.not_done_t))

    def td_target(self, next_obs, rewards, not_done) -> torch.Tensor:
        """r + gamma * (1 - terminated) * Q_target(s', a*), without gradient."""
        with torch.no_grad():
            return self.bootstrap(self.target(*next_obs), self.q(*next_obs) if self.double else None, rewards, not_done)

    def bootstrap(self, q_next_target: torch.Tensor, q_next_online, rewards, not_done) -> torch.Tensor:
        """r + gamma * (1 - terminated) * Q_target(s', a*) from the next observations' Q-values (actions
        on the last axis, any leading shape); ``q_next_online`` chooses a* for Double DQN (None for DQN)."""
        if self.double:
            best = q_next_target.gather(-1, q_next_online.argmax(-1, keepdim=True)).squeeze(-1)
        else:
            best = q_next_target.max(-1).values
        return rewards + self.gamma * not_done * best

    def td_loss(self, q: torch.Tensor, y: torch.Tensor, mask: torch.Tensor | None = None) -> torch.Tensor:
        """The mean TD loss (mse or huber) of Q(s, a) against y, over the entries where ``mask`` is 1."""
        if mask is None:
            return F.mse_loss(q, y) if self.loss == "mse" else F.smooth_l1_loss(q, y)
        each = F.mse_loss(q, y, reduction="none") if self.loss == "mse" else F.smooth_l1_loss(q, y, reduction="none")
        return (each * mask).sum() / mask.sum().clamp(min=1.0)

    def step(self, loss: torch.Tensor) -> float:
        """One Adam step on ``loss`` (its gradient's global norm clipped to max_grad_norm if set); returns the loss."""
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        if self.max_grad_norm > 0:
            nn.utils.clip_grad_norm_(self.q.parameters(), self.max_grad_norm)
        self.optimizer.step()
        return float(loss.detach())

    def update(self) -> float:
        """One gradient step on ``self.batch`` (fill it first); returns the loss."""
        obs, next_obs, actions, rewards, not_done = self._tensors()
        if not self.q.training:  # training mode: e.g. the pixel network's random shifts
            self.q.train()
            self.target.train()
        y = self.td_target(next_obs, rewards, not_done)
        q_all = self.q(*obs)
        loss = self.td_loss(q_all.gather(1, actions[:, None]).squeeze(1), y)
        if self.margin_weight > 0:
            loss = loss + self.margin_weight * self.margin_loss(q_all, self.batch.labels_t.to(self.device))
        return self.step(loss)

    def margin_loss(self, q_all: torch.Tensor, labels: torch.Tensor) -> torch.Tensor:
        """DQfD's large-margin loss (module docstring), averaged over the rows with a label (0 if none)."""
        labelled = (labels >= 0).float()
        expert = labels.clamp(min=0)[:, None]
        margins = torch.full_like(q_all, self.margin).scatter_(1, expert, 0.0)
        each = (q_all + margins).max(1).values - q_all.gather(1, expert).squeeze(1)
        return (each * labelled).sum() / labelled.sum().clamp(min=1.0)

    def update_target(self, tau: float = 1.0) -> None:
        """Hard copy (tau = 1) or soft update theta- <- tau theta + (1 - tau) theta-."""
        with torch.no_grad():
            online, target = list(self.q.parameters()), list(self.target.parameters())
            if tau >= 1.0:
                torch._foreach_copy_(target, online)
            else:
                torch._foreach_lerp_(target, online, tau)
            for b_target, b_online in zip(self.target.buffers(), self.q.buffers()):
                b_target.copy_(b_online)

    # ------------------------------------------------------------------ checkpoints
    def state_dict(self) -> dict:
        """Online and target networks and Adam's state, for a checkpoint."""
        return dict(q=self.q.state_dict(), target=self.target.state_dict(), optimizer=self.optimizer.state_dict())

    def load_state_dict(self, state: dict) -> None:
        """Restore what ``state_dict`` saved; ValueError if the networks do not fit."""
        try:
            self.q.load_state_dict(state["q"])
            self.target.load_state_dict(state["target"])
        except RuntimeError as err:  # missing keys or other shapes
            raise ValueError(f"the checkpoint's Q-network does not fit this run's: {err}") from err
        self.optimizer.load_state_dict(state["optimizer"])
