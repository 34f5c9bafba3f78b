"""The DQN update on torch modules: it is the textbook (Double) DQN step with Adam, and any
module with the right shapes trains."""

import copy

import numpy as np
import pytest
import torch
from torch import nn

from agents.core.learner import DQNLearner
from agents.core.networks import MLPQNetwork, PixelQNetwork, check_q_network, dueling_mlp, random_shift
from agents.core.replay import Batch, ReplayMemory

OBS, ACTIONS, BATCH = 24, 3, 128


def learner(module=None, **kwargs) -> DQNLearner:
    torch.manual_seed(0)
    module = module if module is not None else MLPQNetwork(OBS, ACTIONS, (128, 128))
    out = DQNLearner(module, Batch(BATCH, [((OBS,), np.float32)]), learning_rate=3e-3, **kwargs)
    with torch.no_grad():  # a target that differs from the online network
        for p in out.target.parameters():
            p.add_(0.05 * torch.randn_like(p))
    return out


def fill(batch: Batch, seed: int) -> None:
    rng = np.random.default_rng(seed)
    batch.obs[0][:] = rng.normal(0, 2, batch.obs[0].shape)
    batch.next_obs[0][:] = rng.normal(0, 2, batch.obs[0].shape)
    batch.actions[:] = rng.integers(0, ACTIONS, BATCH)
    batch.rewards[:] = rng.normal(0, 5, BATCH)
    batch.not_done[:] = rng.random(BATCH) > 0.2


def textbook_update(dqn: DQNLearner, double: bool, loss: str, max_grad_norm: float):
    """The update of Alg. 1 / App. A written out on copies of the networks, with plain
    ``torch.optim.Adam``: what ``DQNLearner.update`` must compute."""
    q, target = copy.deepcopy(dqn.q), copy.deepcopy(dqn.target)
    adam = torch.optim.Adam(q.parameters(), lr=dqn.learning_rate)
    adam.load_state_dict(copy.deepcopy(dqn.optimizer.state_dict()))  # Adam would share its tensors
    b = dqn.batch
    s, s2 = torch.tensor(b.obs[0]), torch.tensor(b.next_obs[0])
    a, r, nd = torch.tensor(b.actions), torch.tensor(b.rewards), torch.tensor(b.not_done)
    with torch.no_grad():
        a_star = (q(s2) if double else target(s2)).argmax(1)
        y = r + dqn.gamma * nd * target(s2)[torch.arange(BATCH), a_star]
    pred = q(s)[torch.arange(BATCH), a]
    err = pred - y
    value = (err**2).mean() if loss == "mse" else torch.where(err.abs() < 1, 0.5 * err**2, err.abs() - 0.5).mean()
    adam.zero_grad()
    value.backward()
    if max_grad_norm > 0:
        nn.utils.clip_grad_norm_(q.parameters(), max_grad_norm)
    adam.step()
    return float(value.detach()), [p.detach() for p in q.parameters()]


@pytest.mark.parametrize("double,loss,max_grad_norm", [(False, "mse", 0.0), (True, "mse", 0.0), (False, "huber", 0.0),
                                                      (True, "huber", 1.0), (False, "mse", 0.5)])
def test_the_update_is_the_textbook_dqn_step(double, loss, max_grad_norm):
    dqn = learner(double=double, loss=loss, max_grad_norm=max_grad_norm)
    for step in range(5):  # several steps exercise Adam's moments and bias correction
        fill(dqn.batch, 10 + step)
        expected_loss, expected_params = textbook_update(dqn, double, loss, max_grad_norm)
        assert dqn.update() == pytest.approx(expected_loss, rel=1e-5)
        for got, want in zip(dqn.q.parameters(), expected_params):
            torch.testing.assert_close(got.detach(), want, rtol=1e-4, atol=1e-6)
    x = np.random.default_rng(2).normal(size=OBS).astype(np.float32)
    with torch.no_grad():  # acting reads the same module
        np.testing.assert_allclose(dqn.q_values(x), dqn.q(torch.from_numpy(x)[None])[0].numpy(), rtol=1e-6)
    other = learner(double=double, loss=loss, max_grad_norm=max_grad_norm)  # a checkpoint round trip: the same next step
    other.load_state_dict(dqn.state_dict())
    fill(dqn.batch, 3)
    fill(other.batch, 3)
    assert other.update() == dqn.update()


def test_target_updates():
    dqn = learner()
    online = [p.detach().clone() for p in dqn.q.parameters()]
    before = [p.detach().clone() for p in dqn.target.parameters()]
    dqn.update_target(tau=0.25)
    for t, b, o in zip(dqn.target.parameters(), before, online):
        torch.testing.assert_close(t, 0.75 * b + 0.25 * o)
    dqn.update_target()
    for t, o in zip(dqn.target.parameters(), online):
        torch.testing.assert_close(t, o, rtol=0, atol=0)


def test_a_dueling_module_trains_with_the_same_update():
    module = dueling_mlp([(OBS,)], ACTIONS)
    dqn = learner(module=module)
    fill(dqn.batch, 0)
    dqn.batch.not_done[:] = 0.0  # fixed targets y = r: the loss must fall
    losses = [dqn.update() for _ in range(200)]
    assert losses[-1] < 0.1 * losses[0]
    q = dqn.q_values(np.zeros(OBS, np.float32))
    assert q.shape == (ACTIONS,)


def test_modules_with_wrong_shapes_are_clear_errors():
    with pytest.raises(ValueError, match=r"expected Q-values of shape \(batch, 3\), got \(2, 4\)"):
        check_q_network(nn.Linear(OBS, 4), [(OBS,)], [torch.float32], 3, "q_network 'x:y'")
    with pytest.raises(ValueError, match="calling it on inputs of shapes"):
        check_q_network(nn.Linear(7, 3), [(OBS,)], [torch.float32], 3, "q_network 'x:y'")
    with pytest.raises(ValueError, match="dueling_mlp reads one state vector"):
        dueling_mlp([(32, 32, 3), (0,)], 3)


def test_pixel_network_and_random_shift():
    frames = torch.arange(2 * 8 * 8, dtype=torch.float32).reshape(2, 1, 8, 8)
    torch.manual_seed(0)
    shifted = random_shift(frames, 2)
    assert shifted.shape == frames.shape
    for i in range(2):  # every shifted image is a window of the border-padded original
        padded = nn.functional.pad(frames[i : i + 1], (2, 2, 2, 2), mode="replicate")[0, 0]
        windows = [padded[y : y + 8, x : x + 8] for y in range(5) for x in range(5)]
        assert any(torch.equal(shifted[i, 0], w) for w in windows)
    net = PixelQNetwork((32, 32, 4), 5, 3, shift=2)
    x = torch.randint(0, 256, (6, 32, 32, 4), dtype=torch.uint8)
    s = torch.randn(6, 5)
    net.eval()
    torch.testing.assert_close(net(x, s), net(x, s))  # no augmentation when acting
    net.train()
    assert not torch.equal(net(x, s), net(x, s))  # random shifts in the update
    assert net(x, s).shape == (6, 3)


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
    batch = Batch(16, [((2,), np.float32)])
    memory.sample_into(batch, np.random.default_rng(0))
    assert set(batch.rewards.tolist()) <= {2.0, 3.0, 4.0, 5.0, 6.0}
    np.testing.assert_array_equal(batch.next_obs[0], batch.obs[0] + 1)
    with pytest.raises(ValueError, match="3 x 2"):
        ReplayMemory(4, 2).load_state_dict(ReplayMemory(3, 2).state_dict())


@pytest.mark.skipif(torch.cuda.is_available(), reason="this machine has a GPU")
def test_asking_for_a_missing_gpu_is_a_clear_error():
    from agents.training.config_io import parse_args

    with pytest.raises(ValueError, match="torch finds no GPU here"):
        parse_args(["--device", "cuda"])
    with pytest.raises(ValueError, match="use cpu, cuda or cuda:N"):
        parse_args(["--device", "tpu"])
