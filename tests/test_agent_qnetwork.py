"""The numpy Q-network update computes what the same update written in PyTorch computes."""

import numpy as np
import pytest
import torch
import torch.nn as nn

from agents.qnetwork import MLP, QLearner
from agents.replay import ReplayMemory

OBS, ACTIONS, BATCH = 24, 3, 128


def torch_twin(net: MLP) -> nn.Sequential:
    """An nn.Sequential with the same parameters (nn.Linear stores W transposed)."""
    layers = []
    for i, (w, b) in enumerate(zip(net.weights, net.biases)):
        lin = nn.Linear(*w.shape)
        with torch.no_grad():
            lin.weight.copy_(torch.from_numpy(w.T.copy()))
            lin.bias.copy_(torch.from_numpy(b.copy()))
        layers += [lin, nn.ReLU()] if i < len(net.weights) - 1 else [lin]
    return nn.Sequential(*layers)


def fill_batch(learner: QLearner, seed: int):
    rng = np.random.default_rng(seed)
    b = learner.batch
    b.obs[:] = rng.normal(0, 2, b.obs.shape)
    b.next_obs[:] = rng.normal(0, 2, b.obs.shape)
    b.actions[:] = rng.integers(0, ACTIONS, BATCH)
    b.rewards[:] = rng.normal(0, 5, BATCH)
    b.not_done[:] = rng.random(BATCH) > 0.2


def torch_reference_step(q, qt, opt, b, gamma, double, loss, max_grad_norm):
    s, s2 = torch.from_numpy(b.obs.copy()), torch.from_numpy(b.next_obs.copy())
    a, r, nd = torch.from_numpy(b.actions.copy()), torch.from_numpy(b.rewards.copy()), torch.from_numpy(b.not_done.copy())
    with torch.no_grad():
        q_next = qt(s2)
        if double:
            best = q_next.gather(1, q(s2).argmax(1, keepdim=True)).squeeze(1)
        else:
            best = q_next.max(1).values
        y = r + gamma * nd * best
    pred = q(s).gather(1, a[:, None]).squeeze(1)
    value = nn.functional.mse_loss(pred, y) if loss == "mse" else nn.functional.smooth_l1_loss(pred, y)
    opt.zero_grad()
    value.backward()
    if max_grad_norm > 0:
        nn.utils.clip_grad_norm_(q.parameters(), max_grad_norm)
    grads = [p.grad.detach().clone() for p in q.parameters()]
    opt.step()
    return float(value.detach()), grads


@pytest.mark.parametrize(
    "double,loss,max_grad_norm",
    [(False, "mse", 0.0), (True, "mse", 0.0), (False, "huber", 0.0), (True, "huber", 1.0), (False, "mse", 0.5)],
)
def test_update_matches_pytorch(double, loss, max_grad_norm):
    torch.manual_seed(0)
    learner = QLearner(OBS, ACTIONS, (128, 128), BATCH, gamma=0.97, double=double, loss=loss,
                       max_grad_norm=max_grad_norm, learning_rate=3e-3, rng=np.random.default_rng(1))
    learner.target.flat[:] = MLP(learner.q.sizes, np.random.default_rng(2)).flat  # target differs from online
    q, qt = torch_twin(learner.q), torch_twin(learner.target)
    opt = torch.optim.Adam(q.parameters(), lr=3e-3)
    for step in range(5):  # several steps exercise Adam's moments and bias correction
        fill_batch(learner, seed=10 + step)
        ref_loss, ref_grads = torch_reference_step(q, qt, opt, learner.batch, 0.97, double, loss, max_grad_norm)
        ours = learner.compute_gradient()
        assert ours == pytest.approx(ref_loss, rel=1e-5)
        ours_grads = [learner.grad.params[i] for i in range(len(learner.grad.params))]
        for mine, ref in zip(ours_grads, ref_grads):
            ref = ref.numpy().T if ref.ndim == 2 else ref.numpy()
            np.testing.assert_allclose(mine, ref, rtol=1e-4, atol=1e-6)
        learner.adam_step_()
        for mine, ref in zip(learner.q.params, q.parameters()):
            ref = ref.detach().numpy()
            np.testing.assert_allclose(mine, ref.T if ref.ndim == 2 else ref, rtol=1e-4, atol=1e-6)


def test_forward_matches_pytorch_and_init_bounds():
    net = MLP([20, 64, 32, 3], np.random.default_rng(0))
    for w in net.weights:
        assert np.abs(w).max() <= 1 / np.sqrt(w.shape[0])
    x = np.random.default_rng(1).normal(size=(7, 20)).astype(np.float32)
    np.testing.assert_allclose(net(x), torch_twin(net)(torch.from_numpy(x)).detach().numpy(), rtol=1e-5, atol=1e-6)
    assert net(x[0]).shape == (3,)


def test_target_updates():
    learner = QLearner(4, 2, (8,), batch_size=4, rng=np.random.default_rng(0))
    learner.q.flat += 1.0
    before = learner.target.flat.copy()
    learner.update_target(tau=0.25)
    np.testing.assert_allclose(learner.target.flat, 0.75 * before + 0.25 * learner.q.flat, rtol=1e-6)
    learner.update_target()
    np.testing.assert_array_equal(learner.target.flat, learner.q.flat)


def test_replay_ring_buffer_and_state_round_trip():
    memory = ReplayMemory(5, 2)
    for i in range(7):
        memory.add([i, i], i % 3, float(i), [i + 1, i + 1], terminated=(i == 6))
    assert len(memory) == 5 and memory.pos == 2
    assert sorted(memory.rewards.tolist()) == [2, 3, 4, 5, 6]
    assert memory.not_done[1] == 0.0 and memory.not_done[0] == 1.0  # the terminated step at index 1
    copy = ReplayMemory(5, 2)
    copy.load_state_dict(memory.state_dict())
    for name in ("obs", "next_obs", "actions", "rewards", "not_done"):
        np.testing.assert_array_equal(getattr(copy, name), getattr(memory, name))
    assert (copy.pos, copy.size) == (memory.pos, memory.size)
    learner = QLearner(2, 3, (8,), batch_size=16, rng=np.random.default_rng(0))
    memory.sample_into(learner.batch, np.random.default_rng(0))
    assert set(learner.batch.rewards.tolist()) <= {2.0, 3.0, 4.0, 5.0, 6.0}
    np.testing.assert_array_equal(learner.batch.next_obs, learner.batch.obs + 1)
    with pytest.raises(ValueError, match="3 x 2"):
        ReplayMemory(4, 2).load_state_dict(ReplayMemory(3, 2).state_dict())
