"""DQN update speed: the agent's update (``agents.core.learner.DQNLearner``) beside a naive PyTorch
update loop and two tuned variants of it, measured in the same run on the same batch size and
network.

    python benchmarks/dqn_update.py [--updates 3000] [--obs-dim 24] [--batch 128] [--double]

One update = sample a minibatch from the replay memory, compute the TD target with the
target network, forward and backward the loss, one Adam step. The naive loop is what one
writes first: ``nn.Sequential`` of ``nn.Linear``/``nn.ReLU``, ``torch.optim.Adam``,
``F.mse_loss``, new tensors for every batch (``torch.tensor(array[idx])``), one torch thread.
Two more PyTorch variants show how far the usual tricks take torch: preallocated batch
tensors filled in place through ``torch.from_numpy`` views, and ``Adam(fused=True)``. The
agent's update is the latter.
The process is pinned to one core; torch and numpy's BLAS run one thread each.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
import torch
import torch.nn as nn

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from agents.core.learner import DQNLearner  # noqa: E402
from agents.core.networks import MLPQNetwork  # noqa: E402
from agents.core.replay import Batch, ReplayMemory  # noqa: E402
from agents.training.threads import limit_threads  # noqa: E402
from machine import describe, pin_one_core  # noqa: E402

N_ACTIONS, HIDDEN, GAMMA, MEMORY = 3, 128, 0.97, 50_000


def filled_memory(obs_dim: int) -> ReplayMemory:
    rng = np.random.default_rng(0)
    memory = ReplayMemory(MEMORY, obs_dim)
    for _ in range(MEMORY):
        memory.add(rng.normal(size=obs_dim), int(rng.integers(N_ACTIONS)), float(rng.normal()),
                   rng.normal(size=obs_dim), bool(rng.random() < 0.05))
    return memory


def timed(update, n: int) -> float:
    """Seconds per update (after a warm-up)."""
    for _ in range(min(200, n)):
        update()
    t0 = time.perf_counter()
    for _ in range(n):
        update()
    return (time.perf_counter() - t0) / n


def mlp(obs_dim: int) -> nn.Sequential:
    return nn.Sequential(nn.Linear(obs_dim, HIDDEN), nn.ReLU(), nn.Linear(HIDDEN, HIDDEN), nn.ReLU(),
                         nn.Linear(HIDDEN, N_ACTIONS))


def naive_torch(memory: ReplayMemory, batch: int, rng):
    q, qt = mlp(memory.obs_dim), mlp(memory.obs_dim)
    qt.load_state_dict(q.state_dict())
    opt = torch.optim.Adam(q.parameters(), lr=1e-3)

    def update():
        idx = rng.integers(0, memory.size, batch)
        s, s2 = torch.tensor(memory.obs[idx]), torch.tensor(memory.next_obs[idx])
        a, r = torch.tensor(memory.actions[idx]), torch.tensor(memory.rewards[idx])
        nd = torch.tensor(memory.not_done[idx])
        with torch.no_grad():
            y = r + GAMMA * nd * qt(s2).max(1).values
        loss = nn.functional.mse_loss(q(s).gather(1, a[:, None]).squeeze(1), y)
        opt.zero_grad()
        loss.backward()
        opt.step()

    return update


def tuned_torch(memory: ReplayMemory, batch: int, rng, fused: bool):
    q, qt = mlp(memory.obs_dim), mlp(memory.obs_dim)
    qt.load_state_dict(q.state_dict())
    opt = torch.optim.Adam(q.parameters(), lr=1e-3, **({"fused": True} if fused else {"foreach": True}))
    s, s2 = torch.empty(batch, memory.obs_dim), torch.empty(batch, memory.obs_dim)
    a, r, nd = torch.empty(batch, 1, dtype=torch.int64), torch.empty(batch), torch.empty(batch)
    views = [t.numpy() for t in (s, s2, a, r, nd)]

    def update():
        idx = rng.integers(0, memory.size, batch)
        np.take(memory.obs, idx, axis=0, out=views[0])
        np.take(memory.next_obs, idx, axis=0, out=views[1])
        views[2][:, 0] = memory.actions[idx]
        np.take(memory.rewards, idx, out=views[3])
        np.take(memory.not_done, idx, out=views[4])
        with torch.no_grad():
            y = r + GAMMA * nd * qt(s2).max(1).values
        loss = nn.functional.mse_loss(q(s).gather(1, a).squeeze(1), y)
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()

    return update


def agent(memory: ReplayMemory, batch: int, rng, double: bool):
    torch.manual_seed(0)
    learner = DQNLearner(MLPQNetwork(memory.obs_dim, N_ACTIONS, (HIDDEN, HIDDEN)),
                         Batch(batch, [((memory.obs_dim,), np.float32)]), GAMMA, double=double, learning_rate=1e-3)

    def update():
        memory.sample_into(learner.batch, rng)
        learner.update()

    return update


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--updates", type=int, default=3000, help="timed updates per variant")
    parser.add_argument("--obs-dim", type=int, default=24, help="state size (24: world 5.3)")
    parser.add_argument("--batch", type=int, default=128, help="minibatch size")
    parser.add_argument("--double", action="store_true", help="time the agent's update as Double DQN")
    args = parser.parse_args()
    limit_threads(1)  # torch and numpy's OpenBLAS: one thread each
    print(describe(pin_one_core()))
    print(f"numpy {np.__version__}, torch {torch.__version__} ({torch.get_num_threads()} thread)")
    print(f"network {args.obs_dim}-{HIDDEN}-{HIDDEN}-{N_ACTIONS}, batch {args.batch}, Adam, MSE, "
          f"{args.updates} timed updates each\n")
    memory = filled_memory(args.obs_dim)
    dd = " (Double DQN)" if args.double else ""
    variants = [
        ("naive PyTorch (nn.Sequential + Adam + new tensors)", naive_torch(memory, args.batch, np.random.default_rng(1))),
        ("PyTorch, preallocated batch + Adam(foreach)", tuned_torch(memory, args.batch, np.random.default_rng(1), False)),
        ("PyTorch, preallocated batch + Adam(fused)", tuned_torch(memory, args.batch, np.random.default_rng(1), True)),
        (f"agent (DQNLearner){dd}", agent(memory, args.batch, np.random.default_rng(1), args.double)),
    ]
    results = []
    print(f"{'update':<55} {'updates/s':>10} {'ms/update':>10}")
    for name, update in variants:
        sec = timed(update, args.updates)
        results.append(sec)
        print(f"{name:<55} {1 / sec:>10.0f} {sec * 1e3:>10.3f}")
    print(f"\nthe agent's update takes {results[-1] / results[0]:.2f}x the time of the naive loop "
          f"({results[0] / results[-1]:.1f}x as many updates per second)")


if __name__ == "__main__":
    main()
