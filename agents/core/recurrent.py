"""Memory: a recurrent Q-network (DRQN, Hausknecht and Stone 2015) and its (Double) DQN update on
stored sequences (see docs/memory.md).

``RecurrentQNetwork`` reads one input vector per step (a state vector, or the auto-encoder's
latent beside state parts) through an MLP encoder, a GRU or an LSTM, and a linear Q head::

    q, state = net(x, state)        # x (batch, steps, inputs) -> q (batch, steps, actions)
    q, state = net.step(x, state)   # one observation's input (inputs,) -> Q-values (actions,)

``state`` is None at an episode's start (a zero hidden state). ``RecurrentLearner`` is a
``DQNLearner`` (the same target network, Adam, target updates, TD target and loss) whose
Q-values carry the hidden state from step to step while acting (``reset()`` at every episode's
start) and whose update runs on a ``SequenceBatch`` (``agents.core.sequence_replay``): both
networks unroll every window from a zero state, the first steps of a window only warm the
hidden state up (burn-in), and the loss is the masked mean over the steps that carry it::

    y_t  = r_t + gamma * (1 - terminated_t) * Q_target(h'_{t+1}, a*)
           a* = argmax_a Q_target(h'_{t+1}, a)  (DQN)   or   argmax_a Q(h_{t+1}, a)  (Double DQN)
    loss = sum_t mask_t * l(Q(h_t, a_t) - y_t) / sum_t mask_t

The gradient flows through the whole window (burn-in included, as truncated backpropagation
through time); only the loss leaves the burn-in steps out.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
import torch
from torch import nn

from agents.core.learner import DQNLearner
from agents.core.sequence_replay import SequenceBatch

CELLS = ("gru", "lstm")


class RecurrentQNetwork(nn.Module):
    """in_dim -> ReLU MLP encoder (``encoder_sizes``) -> GRU or LSTM (``hidden``) -> linear Q head."""

    def __init__(self, in_dim: int, n_actions: int, encoder_sizes: Sequence[int] = (128,), hidden: int = 128,
                 cell: str = "gru"):
        super().__init__()
        if cell not in CELLS:
            raise ValueError(f"unknown recurrent cell {cell!r}; valid cells: {', '.join(CELLS)}")
        sizes = [int(in_dim), *map(int, encoder_sizes)]
        if min(sizes + [int(hidden), int(n_actions)]) < 1:
            raise ValueError(f"layer sizes must be positive, got inputs {in_dim}, encoder {list(encoder_sizes)}, "
                             f"hidden {hidden}, actions {n_actions}")
        layers: list[nn.Module] = []
        for fan_in, fan_out in zip(sizes[:-1], sizes[1:]):
            layers += [nn.Linear(fan_in, fan_out), nn.ReLU()]
        self.encoder = nn.Sequential(*layers)
        self.cell = cell
        self.rnn = (nn.GRU if cell == "gru" else nn.LSTM)(sizes[-1], int(hidden), batch_first=True)
        self.head = nn.Linear(int(hidden), int(n_actions))

    def forward(self, x: torch.Tensor, state=None):
        """Q-values (batch, steps, actions) of a batch of input sequences (batch, steps, inputs), from
        ``state`` (None: zero), and the state after the last step."""
        out, state = self.rnn(self.encoder(x), state)
        return self.head(out), state

    def step(self, x, state=None, device: torch.device | str = "cpu"):
        """Q-values (actions,) of one observation's input after the inputs that led to ``state``, and
        the state to pass with the next one (None: the episode's first step)."""
        with torch.inference_mode():
            q, state = self(torch.as_tensor(np.asarray(x), dtype=torch.float32).to(device)[None, None], state)
        return q[0, 0].float().cpu().numpy(), state


class RecurrentLearner(DQNLearner):
    """A ``DQNLearner`` for a ``RecurrentQNetwork``: hidden state while acting, the update on sequences."""

    recurrent = True

    def __init__(self, q_network: RecurrentQNetwork, batch: SequenceBatch, **settings):
        super().__init__(q_network, batch, **settings)
        self.hidden = None
        """the acting network's state in the current episode (None: its start)"""

    def reset(self) -> None:
        """An episode starts: the hidden state is zero again."""
        self.hidden = None

    def q_values(self, x) -> np.ndarray:
        """Q-values (actions,) of the episode's next input; the hidden state moves one step on."""
        q, self.hidden = self.q.step(x, self.hidden, self.device)
        return q

    def update(self) -> float:
        """One gradient step on ``self.batch`` (a ``SequenceBatch``; fill it first); returns the loss."""
        b = self.batch
        obs, actions, rewards, not_done, mask = (t.to(self.device) for t in (b.obs_t, b.actions_t, b.rewards_t,
                                                                           b.not_done_t, b.mask_t))
        q_all, _ = self.q(obs)  # (batch, window + 1, actions)
        with torch.no_grad():
            q_target, _ = self.target(obs)
            y = self.bootstrap(q_target[:, 1:], q_all[:, 1:].detach() if self.double else None, rewards, not_done)
        q = q_all[:, :-1].gather(-1, actions[..., None]).squeeze(-1)
        return self.step(self.td_loss(q, y, mask))
