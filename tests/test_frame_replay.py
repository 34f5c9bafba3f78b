"""The camera runs' replay memory: one stored frame per observation, transitions by slot."""

import numpy as np
import pytest

from agents.core.frame_replay import FrameReplay
from agents.core.replay import Batch


def frame(v: int) -> np.ndarray:
    return np.full((4, 4, 3), v, np.uint8)


def fill(memory: FrameReplay, episodes: list[int]) -> list[tuple[int, int]]:
    """Store episodes of the given lengths; frame value = running observation number.
    Returns the (obs value, next obs value) pairs of every transition stored."""
    pairs, v = [], 0
    for length in episodes:
        memory.start(frame(v), np.array([v], np.float32))
        for t in range(length):
            memory.add(action=t % 3, reward=float(v), frame=frame(v + 1), state=np.array([v + 1], np.float32),
                       terminated=t == length - 1)
            pairs.append((v, v + 1))
            v += 1
        v += 1  # the next episode's first observation
    return pairs


def test_one_frame_per_observation_and_no_transition_across_episodes():
    memory = FrameReplay(100, (4, 4, 3), state_dim=1, latent_dim=2)
    pairs = fill(memory, [3, 2])
    assert memory.size == 3 + 1 + 2 + 1  # n steps take n + 1 slots
    assert len(memory) == 5
    # the first episode's last observation (slot 3) starts no transition
    assert memory.has_next[:7].tolist() == [True, True, True, False, True, True, False]
    rng = np.random.default_rng(0)
    memory.latents[:7] = np.arange(14, dtype=np.float32).reshape(7, 2)
    batch = Batch(64, [((3,), np.float32)])
    memory.sample_into(batch, rng)
    seen = {(int(o), int(n)) for o, n in zip(batch.obs[0][:, 2], batch.next_obs[0][:, 2])}
    assert seen <= set(pairs) and len(seen) == 5
    # [latent | state]: the latent of the slot the state came from
    slot = batch.obs[0][:, 2].astype(int)
    np.testing.assert_array_equal(batch.obs[0][:, :2], memory.latents[slot])
    np.testing.assert_array_equal(batch.rewards, batch.obs[0][:, 2])
    terminal = batch.next_obs[0][:, 2] == 3  # the first episode ended on observation 3
    assert np.all(batch.not_done[terminal] == 0) and np.all(batch.not_done[~terminal & (slot != 5)] == 1)


def test_wrapping_drops_the_overwritten_transitions():
    memory = FrameReplay(5, (4, 4, 3), state_dim=1, latent_dim=1)
    pairs = fill(memory, [3, 3])  # 8 observations in 5 slots: the last 5 survive (values 3..7)
    assert memory.size == 5
    assert sorted(int(f[0, 0, 0]) for f in memory.frames) == [3, 4, 5, 6, 7]
    batch = Batch(200, [((2,), np.float32)])
    memory.sample_into(batch, np.random.default_rng(1))
    seen = {(int(o), int(n)) for o, n in zip(batch.obs[0][:, 1], batch.next_obs[0][:, 1])}
    assert seen == {p for p in pairs if p[0] >= 4}  # 3 ended episode 1; (4,5), (5,6), (6,7) remain


def test_pixel_minibatches_hold_frames_and_state_parts():
    memory = FrameReplay(20, (4, 4, 3), state_dim=1, latent_dim=0)
    pairs = fill(memory, [3, 2])
    batch = Batch(64, [((4, 4, 3), np.uint8), ((1,), np.float32)])
    memory.sample_frames_into(batch, np.random.default_rng(0))
    frames, next_frames = batch.obs[0][:, 0, 0, 0].astype(int), batch.next_obs[0][:, 0, 0, 0].astype(int)
    assert set(zip(frames.tolist(), next_frames.tolist())) == set(pairs)  # every transition, none across episodes
    np.testing.assert_array_equal(batch.obs[1][:, 0], frames)  # the state parts of the same slot
    np.testing.assert_array_equal(batch.rewards, frames)


def test_refresh_latents_and_checkpoint_round_trip():
    memory = FrameReplay(10, (4, 4, 3), state_dim=1, latent_dim=1)
    fill(memory, [4])
    memory.refresh_latents(lambda frames: frames[:, 0, 0, :1].astype(np.float32) * 2, chunk=2)
    np.testing.assert_array_equal(memory.latents[:5, 0], [0, 2, 4, 6, 8])
    restored = FrameReplay(10, (4, 4, 3), state_dim=1, latent_dim=1)
    restored.load_state_dict(memory.state_dict())
    for name in ("frames", "states", "latents", "actions", "rewards", "not_done", "has_next"):
        np.testing.assert_array_equal(getattr(restored, name), getattr(memory, name), err_msg=name)
    assert (restored.pos, restored.size, restored.last) == (memory.pos, memory.size, memory.last)
    with pytest.raises(ValueError, match="frame replay is"):
        FrameReplay(11, (4, 4, 3), 1, 1).load_state_dict(memory.state_dict())


def test_bad_input_is_a_clear_error():
    memory = FrameReplay(10, (4, 4, 3), state_dim=1, latent_dim=1)
    with pytest.raises(RuntimeError, match="before start"):
        memory.add(0, 0.0, frame(1), np.zeros(1), False)
    with pytest.raises(ValueError, match="uint8 frame of shape"):
        memory.start(np.zeros((4, 4, 3), np.float32), np.zeros(1))
    with pytest.raises(ValueError, match="no complete transition"):
        memory.start(frame(0), np.zeros(1))
        memory.sample_into(Batch(2, [((2,), np.float32)]), np.random.default_rng(0))
    assert memory.nbytes >= 10 * 4 * 4 * 3
