"""The DQN update of ``MLPQNetwork`` written directly in numpy, on the module's own parameters.

An acceleration of ``DQNLearner.update`` for the default Q-network on the CPU, nothing more:
it computes the same loss, gradient, clipping and Adam step as the torch path, on the same
tensors. At the study's sizes (24-128-128-3, batch 128) the per-call overhead of autograd and
the optimizer costs more than the arithmetic, and this update takes about half the time
(``benchmarks/dqn_update.py`` measures both; ``tests/test_agent_learner.py`` checks that the two
paths give the same parameters and Adam state, step after step).

How the sharing works: ``bind`` makes every parameter of the online and target networks and
both Adam moments views into one flat float32 tensor each (``p.data = flat[i:j].view(...)``);
numpy views of those tensors are what this code reads and writes. The module, ``state_dict``,
``torch.optim.Adam`` and a checkpoint see the result with no copy. Adam's step counters stay
torch's own per-parameter ``step`` tensors.

Conventions follow torch: ``nn.Linear`` computes x @ W.T + b; huber is ``smooth_l1_loss`` with
beta 1; clipping is ``clip_grad_norm_`` (eps 1e-6); Adam is ``torch.optim.Adam`` without weight decay.
"""

from __future__ import annotations

import math

import numpy as np
import torch


def _flatten(tensors: list[torch.Tensor]) -> torch.Tensor:
    """One flat tensor holding ``tensors``' values; each tensor's ``data`` becomes a view into it."""
    flat = torch.empty(sum(t.numel() for t in tensors), dtype=torch.float32)
    offset = 0
    for t in tensors:
        n = t.numel()
        flat[offset : offset + n].copy_(t.detach().reshape(-1))
        t.data = flat[offset : offset + n].view(t.shape)
        offset += n
    return flat


class NumpyMLPUpdate:
    """``DQNLearner.update`` and ``q_values`` for an ``MLPQNetwork`` on the CPU, in numpy."""

    @staticmethod
    def supports(learner) -> bool:
        from .networks import MLPQNetwork

        q = learner.q
        group = learner.optimizer.param_groups[0]
        return (type(q) is MLPQNetwork and learner.device.type == "cpu"
                and all(p.dtype == torch.float32 for p in q.parameters())
                and len(learner.batch.inputs) == 1 and learner.batch.inputs[0][1] == np.float32
                and group["weight_decay"] == 0 and not group["amsgrad"] and not group["maximize"])

    def __init__(self, learner):
        self.learner = learner
        n = learner.batch.size
        sizes = learner.q.sizes
        self._h = [np.empty((n, k), dtype=np.float32) for k in sizes[1:]]
        self._h_next = [np.empty((n, k), dtype=np.float32) for k in sizes[1:]]
        self._h_next_online = [np.empty((n, k), dtype=np.float32) for k in sizes[1:]]
        self._dh = [np.empty((n, k), dtype=np.float32) for k in sizes[1:]]
        self._rows = np.arange(n)
        self.bind()

    def bind(self) -> None:
        """Share the networks' parameters and Adam's moments as flat arrays (again after loading)."""
        learner = self.learner
        params = list(learner.q.parameters())
        self.flat = _flatten(params).numpy()
        self.target_flat = _flatten(list(learner.target.parameters())).numpy()
        states = [learner.optimizer.state[p] for p in params]
        self.m = _flatten([s["exp_avg"] for s in states]).numpy()
        self.v = _flatten([s["exp_avg_sq"] for s in states]).numpy()
        for s in states:  # Adam reads its moments through these names
            s["exp_avg"], s["exp_avg_sq"] = s["exp_avg"].data, s["exp_avg_sq"].data
        self.steps = [s["step"] for s in states]
        self.grad = np.zeros_like(self.flat)
        self._tmp = np.zeros_like(self.flat)
        self.layers = self._views(learner.q, self.flat)
        self.target_layers = self._views(learner.target, self.target_flat)
        self.grad_layers = []
        offset = 0
        for w, b in self.layers:
            gw = self.grad[offset : offset + w.size].reshape(w.shape)
            offset += w.size
            gb = self.grad[offset : offset + b.size]
            offset += b.size
            self.grad_layers.append((gw, gb))

    @staticmethod
    def _views(module, flat: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        views, offset = [], 0
        for lin in module.linears:
            w = flat[offset : offset + lin.weight.numel()].reshape(lin.weight.shape)  # (out, in)
            offset += w.size
            b = flat[offset : offset + lin.bias.numel()]
            offset += b.size
            views.append((w, b))
        return views

    # ------------------------------------------------------------------ forward
    @staticmethod
    def _forward(layers, x: np.ndarray, hs: list[np.ndarray]) -> np.ndarray:
        last = len(layers) - 1
        for i, ((w, b), h) in enumerate(zip(layers, hs)):
            np.matmul(x, w.T, out=h)
            h += b
            if i < last:
                np.maximum(h, 0, out=h)
            x = h
        return hs[-1]

    def q_values(self, x) -> np.ndarray:
        h = np.asarray(x[0] if isinstance(x, tuple) else x, dtype=np.float32)
        last = len(self.layers) - 1
        for i, (w, b) in enumerate(self.layers):
            h = h @ w.T + b
            if i < last:
                np.maximum(h, 0, out=h)
        return h

    # ------------------------------------------------------------------ the update
    def _loss_and_gradient(self) -> float:
        learner, b = self.learner, self.learner.batch
        obs, next_obs = b.obs[0], b.next_obs[0]
        q_next = self._forward(self.target_layers, next_obs, self._h_next)
        if learner.double:
            a_star = self._forward(self.layers, next_obs, self._h_next_online).argmax(axis=1)
            best = q_next[self._rows, a_star]
        else:
            best = q_next.max(axis=1)
        y = b.rewards + learner.gamma * b.not_done * best
        q = self._forward(self.layers, obs, self._h)
        diff = q[self._rows, b.actions] - y
        n = len(diff)
        if learner.loss == "mse":
            loss = float(np.dot(diff, diff)) / n
            d_q = diff * (2.0 / n)
        else:  # smooth L1, beta 1
            absd = np.abs(diff)
            loss = float(np.where(absd < 1.0, 0.5 * diff * diff, absd - 0.5).sum()) / n
            d_q = np.clip(diff, -1.0, 1.0) * (1.0 / n)
        dh = self._dh[-1]
        dh.fill(0.0)
        dh[self._rows, b.actions] = d_q  # only the taken action's output has a gradient
        for i in range(len(self.layers) - 1, -1, -1):
            below = self._h[i - 1] if i > 0 else obs
            gw, gb = self.grad_layers[i]
            np.matmul(dh.T, below, out=gw)
            np.sum(dh, axis=0, out=gb)
            if i > 0:
                prev = self._dh[i - 1]
                np.matmul(dh, self.layers[i][0], out=prev)
                prev *= self._h[i - 1] > 0
                dh = prev
        if learner.max_grad_norm > 0:
            coef = learner.max_grad_norm / (math.sqrt(float(np.dot(self.grad, self.grad))) + 1e-6)
            if coef < 1.0:
                self.grad *= coef
        return loss

    def _adam_step(self) -> None:
        group = self.learner.optimizer.param_groups[0]
        lr, (beta1, beta2), eps = group["lr"], group["betas"], group["eps"]
        for s in self.steps:
            s += 1
        t = float(self.steps[0])
        g, m, v, tmp = self.grad, self.m, self.v, self._tmp
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
        tmp *= lr / (1.0 - beta1**t)
        self.flat -= tmp

    def update(self) -> float:
        loss = self._loss_and_gradient()
        self._adam_step()
        return loss
