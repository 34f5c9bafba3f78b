"""The Q-network and its update, written directly in numpy.

An MLP of ReLU layers (default 2 x 128) maps a state to one Q-value per action. Its
parameters live in one flat float32 vector (with per-layer views into it), so Adam, the
target-network copy and a checkpoint are single array operations. The forward pass, the
backward pass of the TD loss and the Adam step are written out by hand into preallocated
buffers: at this size (24-128-128-3, batch 128) the per-call overhead of a framework costs
more than the arithmetic, and this update takes about half the time of the same update
written with ``torch.nn`` + ``torch.optim.Adam`` (``benchmarks/dqn_update.py`` measures both). ``tests/test_agent_qnetwork.py`` checks that it computes what PyTorch
computes on the same batch: the loss, every gradient and the parameters after Adam.

Conventions match PyTorch: a layer is ``y = x @ W + b`` with ``W`` of shape (in, out) (the
transpose of ``nn.Linear.weight``); initialisation is ``nn.Linear``'s default (uniform in
+-1/sqrt(fan_in) for weights and biases); "huber" is ``smooth_l1_loss`` with beta 1; gradient
clipping is ``clip_grad_norm_``; Adam is ``torch.optim.Adam`` (betas 0.9/0.999, eps 1e-8).
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

LOSSES = ("mse", "huber")


class MLP:
    """A ReLU MLP whose parameters are views into one flat float32 vector ``self.flat``."""

    def __init__(self, sizes: Sequence[int], rng: np.random.Generator | None = None):
        if len(sizes) < 2 or any(int(s) < 1 for s in sizes):
            raise ValueError(f"layer sizes must be at least two positive integers, got {list(sizes)}")
        self.sizes = [int(s) for s in sizes]
        shapes = []
        for fan_in, fan_out in zip(self.sizes[:-1], self.sizes[1:]):
            shapes += [(fan_in, fan_out), (fan_out,)]
        self.shapes = shapes
        self.flat = np.zeros(sum(math.prod(s) for s in shapes), dtype=np.float32)
        self.params = split(self.flat, shapes)  # W0, b0, W1, b1, ...
        if rng is not None:
            for i in range(0, len(self.params), 2):
                bound = 1.0 / math.sqrt(self.params[i].shape[0])
                for p in self.params[i : i + 2]:
                    p[...] = rng.uniform(-bound, bound, p.shape)

    @property
    def weights(self) -> list[np.ndarray]:
        return self.params[0::2]

    @property
    def biases(self) -> list[np.ndarray]:
        return self.params[1::2]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Q-values of a batch (B, in) or of one state (in,)."""
        h = np.asarray(x, dtype=np.float32)
        last = len(self.weights) - 1
        for i, (w, b) in enumerate(zip(self.weights, self.biases)):
            h = h @ w + b
            if i < last:
                np.maximum(h, 0, out=h)
        return h


def split(flat: np.ndarray, shapes) -> list[np.ndarray]:
    """Views of ``flat`` with the given shapes, in order."""
    out, offset = [], 0
    for shape in shapes:
        n = math.prod(shape)
        out.append(flat[offset : offset + n].reshape(shape))
        offset += n
    return out


class Batch:
    """Preallocated arrays one minibatch is copied into (see ``ReplayMemory.sample_into``)."""

    def __init__(self, batch_size: int, obs_dim: int):
        self.obs = np.empty((batch_size, obs_dim), dtype=np.float32)
        self.next_obs = np.empty((batch_size, obs_dim), dtype=np.float32)
        self.actions = np.empty(batch_size, dtype=np.int64)
        self.rewards = np.empty(batch_size, dtype=np.float32)
        self.not_done = np.empty(batch_size, dtype=np.float32)
        """1 - terminated: a truncated (timed-out) transition still bootstraps"""


class QLearner:
    """Online and target networks, Adam state and the (Double) DQN update on one batch."""

    def __init__(
        self,
        obs_dim: int,
        n_actions: int,
        hidden_sizes: Sequence[int] = (128, 128),
        batch_size: int = 128,
        gamma: float = 0.97,
        double: bool = False,
        loss: str = "mse",
        max_grad_norm: float = 0.0,
        learning_rate: float = 1e-3,
        rng: np.random.Generator | None = None,
    ):
        if loss not in LOSSES:
            raise ValueError(f"unknown loss {loss!r}; valid losses: {', '.join(LOSSES)}")
        sizes = [obs_dim, *hidden_sizes, n_actions]
        self.q = MLP(sizes, rng if rng is not None else np.random.default_rng())
        self.target = MLP(sizes)
        self.target.flat[:] = self.q.flat
        self.grad = MLP(sizes)  # gradient, same layout
        self.adam_m = np.zeros_like(self.q.flat)
        self.adam_v = np.zeros_like(self.q.flat)
        self.adam_step = 0
        self._tmp = np.zeros_like(self.q.flat)
        self.gamma, self.double, self.loss, self.max_grad_norm = gamma, double, loss, max_grad_norm
        self.learning_rate = learning_rate
        self.batch = Batch(batch_size, obs_dim)
        # activations of the online net (kept for the backward pass) and of the target pass
        width = sizes[1:]
        self._h = [np.empty((batch_size, n), dtype=np.float32) for n in width]
        self._h_next = [np.empty((batch_size, n), dtype=np.float32) for n in width]
        self._h_next_online = [np.empty((batch_size, n), dtype=np.float32) for n in width] if double else None
        self._dh = [np.empty((batch_size, n), dtype=np.float32) for n in width]
        self._rows = np.arange(batch_size)

    # ------------------------------------------------------------------ forward / backward
    @staticmethod
    def _forward(net: MLP, x: np.ndarray, hs: list[np.ndarray]) -> np.ndarray:
        last = len(hs) - 1
        for i, (w, b, h) in enumerate(zip(net.weights, net.biases, hs)):
            np.matmul(x, w, out=h)
            h += b
            if i < last:
                np.maximum(h, 0, out=h)
            x = h
        return hs[-1]

    def td_target(self) -> np.ndarray:
        """r + gamma * (1 - terminated) * Q_target(s', a*), a* from the target (DQN) or online net (DDQN)."""
        b = self.batch
        q_next = self._forward(self.target, b.next_obs, self._h_next)
        if self.double:
            a_star = self._forward(self.q, b.next_obs, self._h_next_online).argmax(axis=1)
            best = q_next[self._rows, a_star]
        else:
            best = q_next.max(axis=1)
        return b.rewards + self.gamma * b.not_done * best

    def compute_gradient(self) -> float:
        """Fill ``self.grad`` with d(loss)/d(params) on ``self.batch``; return the loss."""
        b = self.batch
        y = self.td_target()
        q = self._forward(self.q, b.obs, self._h)
        diff = q[self._rows, b.actions] - y
        n = len(diff)
        if self.loss == "mse":
            loss = float(np.dot(diff, diff)) / n
            d_q = diff * (2.0 / n)
        else:  # huber (smooth L1, beta 1)
            absd = np.abs(diff)
            loss = float(np.where(absd < 1.0, 0.5 * diff * diff, absd - 0.5).sum()) / n
            d_q = np.clip(diff, -1.0, 1.0) * (1.0 / n)
        # backward: only the taken action's output has a gradient
        dh = self._dh[-1]
        dh.fill(0.0)
        dh[self._rows, b.actions] = d_q
        weights, gw, gb = self.q.weights, self.grad.weights, self.grad.biases
        for i in range(len(weights) - 1, -1, -1):
            below = self._h[i - 1] if i > 0 else b.obs
            np.matmul(below.T, dh, out=gw[i])
            np.sum(dh, axis=0, out=gb[i])
            if i > 0:
                prev = self._dh[i - 1]
                np.matmul(dh, weights[i].T, out=prev)
                prev *= self._h[i - 1] > 0
                dh = prev
        if self.max_grad_norm > 0:
            norm = float(np.sqrt(np.dot(self.grad.flat, self.grad.flat)))
            coef = self.max_grad_norm / (norm + 1e-6)
            if coef < 1.0:
                self.grad.flat *= coef
        return loss

    # ------------------------------------------------------------------ optimisation
    def adam_step_(self, beta1: float = 0.9, beta2: float = 0.999, eps: float = 1e-8) -> None:
        """One ``torch.optim.Adam`` step of the online parameters with ``self.grad``."""
        g, m, v, tmp = self.grad.flat, self.adam_m, self.adam_v, self._tmp
        self.adam_step += 1
        t = self.adam_step
        m *= beta1
        np.multiply(g, 1.0 - beta1, out=tmp)
        m += tmp
        v *= beta2
        np.multiply(g, g, out=tmp)
        tmp *= 1.0 - beta2
        v += tmp
        np.sqrt(v, out=tmp)
        tmp *= 1.0 / math.sqrt(1.0 - beta2**t)
        tmp += eps
        np.divide(m, tmp, out=tmp)
        tmp *= self.learning_rate / (1.0 - beta1**t)
        self.q.flat -= tmp

    def update(self) -> float:
        """One gradient step on ``self.batch`` (fill it first); returns the loss."""
        loss = self.compute_gradient()
        self.adam_step_()
        return loss

    def update_target(self, tau: float = 1.0) -> None:
        """Hard copy (tau = 1) or soft update theta- <- tau theta + (1 - tau) theta-."""
        if tau >= 1.0:
            self.target.flat[:] = self.q.flat
        else:
            self.target.flat *= 1.0 - tau
            self.target.flat += tau * self.q.flat

    def act(self, obs: np.ndarray) -> int:
        """The greedy action for one state."""
        return int(np.argmax(self.q(obs)))

    # ------------------------------------------------------------------ checkpoints
    def state_dict(self) -> dict:
        return dict(
            sizes=list(self.q.sizes),
            q=self.q.flat.copy(),
            target=self.target.flat.copy(),
            adam_m=self.adam_m.copy(),
            adam_v=self.adam_v.copy(),
            adam_step=self.adam_step,
        )

    def load_state_dict(self, state: dict) -> None:
        if list(state["sizes"]) != self.q.sizes:
            raise ValueError(f"checkpoint network has layer sizes {state['sizes']}, this one {self.q.sizes}")
        self.q.flat[:] = state["q"]
        self.target.flat[:] = state["target"]
        self.adam_m[:] = state["adam_m"]
        self.adam_v[:] = state["adam_v"]
        self.adam_step = int(state["adam_step"])
