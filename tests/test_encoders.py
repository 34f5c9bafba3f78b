"""The egocentric encoders: the obstacle encoder ignores the slots' order and the empty slots, the
laser convolution reads any ring with one filter bank, and a state of the wrong size is refused."""

import numpy as np
import pytest
import torch

from agents.core.encoders import EgocentricQNetwork, LaserConv


def state(rng, lasers=16, k=4, present=4) -> torch.Tensor:
    x = rng.uniform(-1, 1, size=lasers + 6 + 5 * k).astype(np.float32)  # lasers | target | way | slots
    slots = x[lasers + 6:].reshape(k, 5)
    slots[:, 4] = [1.0] * present + [-1.0] * (k - present)  # scaled "present": 1, absent: -1
    return torch.as_tensor(x)[None]


def test_pooled_obstacles_ignore_the_slots_order_and_the_empty_slots():
    torch.manual_seed(0)
    net = EgocentricQNetwork(16 + 6 + 20, 3, (32,), lasers=16, obstacle_k=4, obstacle_encoder="pooled").eval()
    x = state(np.random.default_rng(1), present=3)
    shuffled = x.clone()
    slots = shuffled[0, 22:].reshape(4, 5)
    slots[[0, 1, 2]] = slots[[2, 0, 1]].clone()  # the three boxes in another order
    torch.testing.assert_close(net(shuffled), net(x))
    other_empty = x.clone()
    other_empty[0, 22 + 15:22 + 19] = torch.tensor([0.3, -0.7, 0.2, 0.9])  # what an absent slot holds is ignored
    torch.testing.assert_close(net(other_empty), net(x))
    moved = x.clone()
    moved[0, 22] += 0.5  # a present box elsewhere changes the Q-values
    assert not torch.allclose(net(moved), net(x))


@pytest.mark.parametrize("rays", [16, 64, 180])
def test_the_laser_convolution_reads_any_ring_with_the_same_filters(rays):
    conv = LaserConv(rays)
    assert sum(p.numel() for p in conv.conv.parameters()) == sum(p.numel() for p in LaserConv(16).conv.parameters())
    net = EgocentricQNetwork(rays + 6 + 20, 3, (32,), lasers=rays, obstacle_k=4, laser_encoder="conv")
    assert net(state(np.random.default_rng(2), lasers=rays)).shape == (1, 3)


def test_a_state_that_cannot_hold_the_parts_is_refused():
    with pytest.raises(ValueError, match="laser_rays and obstacle_k"):
        EgocentricQNetwork(20, 3, (32,), lasers=16, obstacle_k=4, laser_encoder="conv")
