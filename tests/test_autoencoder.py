"""The camera auto-encoder: shapes, the loss of Eq. 4.10, and learning on rendered frames."""

import numpy as np
import pytest
import torch

from agents.srl.autoencoder import (
    SINGLE_RGB,
    STACKED_GRAY,
    AutoEncoderSpec,
    AutoEncoderTrainer,
    ConvAutoEncoder,
    RareColourWeights,
    reconstruction_loss,
)


@pytest.mark.parametrize("spec, shape", [(SINGLE_RGB, (32, 32, 3)), (STACKED_GRAY, (32, 32, 4))])
def test_shapes(spec, shape):
    torch.manual_seed(0)
    ae = ConvAutoEncoder(spec)
    frames = np.random.default_rng(0).integers(0, 256, size=(5, *shape), dtype=np.uint8)
    assert ae.encode(frames).shape == (5, spec.latent)
    assert ae.encode(frames[0]).shape == (spec.latent,)
    rec = ae.reconstruct(frames)
    assert rec.shape == frames.shape and rec.dtype == np.uint8
    assert ae.reconstruct(frames[0]).shape == shape
    with pytest.raises(ValueError, match=r"expected frames of shape"):
        ae.encode(np.zeros((32, 32, 1), np.uint8))


def test_thesis_sizes():
    assert (SINGLE_RGB.in_channels, SINGLE_RGB.conv_channels, SINGLE_RGB.dense, SINGLE_RGB.latent) == (3, (32, 64), 64, 10)
    assert (STACKED_GRAY.in_channels, STACKED_GRAY.conv_channels, STACKED_GRAY.dense, STACKED_GRAY.latent) == (4, (64, 128), 64, 15)
    with pytest.raises(ValueError, match="multiple of 4"):
        AutoEncoderSpec(image_size=30)


def test_reconstruction_loss_is_eq_4_10():
    a = torch.zeros(2, 3, 4, 4)
    b = torch.zeros(2, 3, 4, 4)
    b[0] += 0.5  # image 0: 48 pixels off by 0.5 -> 12; image 1: exact -> 0
    assert float(reconstruction_loss(b, a)) == pytest.approx((48 * 0.25 + 0) / 2)


@pytest.fixture(scope="module")
def rendered_frames():
    """64 camera frames from random episodes of world 5.5a."""
    import dynnav_tasks

    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make("DynNav-VisualStaticTarget-v1", obs_mode="rgb"))
    rng = np.random.default_rng(0)
    frames, seed = [], 0
    obs, _ = env.reset(seed=seed)
    while len(frames) < 64:
        frames.append(obs)
        obs, _, terminated, truncated, _ = env.step(int(rng.integers(3)))
        if terminated or truncated:
            seed += 1
            obs, _ = env.reset(seed=seed)
    env.close()
    return np.stack(frames)


def test_reconstruction_loss_falls_on_rendered_frames(rendered_frames):
    torch.manual_seed(0)
    ae = ConvAutoEncoder(SINGLE_RGB)
    trainer = AutoEncoderTrainer(ae, lr=1e-3)
    x = ae.to_input(rendered_frames)
    with torch.no_grad():
        before = float(reconstruction_loss(ae(x)[1], x))
    rng = np.random.default_rng(0)
    for _ in range(150):
        trainer.train_batch(rendered_frames[rng.integers(0, len(rendered_frames), 32)])
    with torch.no_grad():
        after = float(reconstruction_loss(ae(x)[1], x))
    assert after < 0.25 * before, (before, after)
    # the latent tells frames apart
    z = ae.encode(rendered_frames)
    assert np.std(z, axis=0).mean() > 1e-3


def test_rare_colour_weights_by_hand():
    # 4x4 gray frames with one red pixel each: red covers 1/16 of the pixels, gray 15/16
    frames = np.full((10, 4, 4, 3), 128, np.uint8)
    frames[:, 1, 2] = (220, 59, 59)
    for power in (0.5, 1.0):
        w = RareColourWeights(power).fit(frames)(frames)
        assert w.shape == (10, 1, 4, 4)
        red, gray = float(w[0, 0, 1, 2]), float(w[0, 0, 0, 0])
        assert red / gray == pytest.approx(15.0 ** power, rel=1e-5)
        assert float(w.mean()) == pytest.approx(1.0, rel=1e-5)
    assert float(RareColourWeights(0.0).fit(frames)(frames).max()) == pytest.approx(1.0)
    # a colour the sample never showed counts as the rarest
    new = frames[:1].copy()
    new[0, 3, 3] = (0, 0, 255)
    w = RareColourWeights(1.0).fit(frames)(new)
    assert float(w[0, 0, 3, 3]) == pytest.approx(float(w[0, 0, 1, 2]))
    with pytest.raises(RuntimeError, match="fit"):
        RareColourWeights(1.0)(frames)


def test_rare_colour_weights_for_gray_stacks_and_the_weighted_loss():
    frames = np.zeros((2, 4, 4, 4), np.uint8)  # two stacks of 4 gray frames, all black
    frames[0, 0, 0, 3] = 200  # one bright value of 128
    w = RareColourWeights(1.0).fit(frames)(frames)
    assert w.shape == (2, 4, 4, 4)  # (B, C, H, W), one weight per value
    assert float(w[0, 3, 0, 0]) / float(w[0, 0, 0, 0]) == pytest.approx(127.0, rel=1e-5)
    a, b = torch.zeros(1, 1, 2, 2), torch.ones(1, 1, 2, 2)
    weights = torch.tensor([[[[1.0, 2.0], [3.0, 0.0]]]])
    assert float(reconstruction_loss(b, a, weights)) == pytest.approx(6.0)


def test_rare_colour_weights_make_a_small_red_square_reconstructed():
    """A 3x3 red square in every frame of a gray scene, at a random place: with equal weights the
    auto-encoder leaves it out; weighted by colour rarity (power 0.5) it draws it."""
    rng = np.random.default_rng(0)
    frames = np.full((256, 32, 32, 3), 190, np.uint8)
    frames[:, :12] = (90, 70, 130)  # a wall across the top
    for f, (r, c) in zip(frames, rng.integers(14, 29, size=(256, 2))):
        f[r:r + 3, c:c + 3] = (220, 59, 59)  # 0.9% of the pixels
    red = (frames[..., 0] > 200) & (frames[..., 1] < 80)

    def red_recall(power):
        torch.manual_seed(0)
        ae = ConvAutoEncoder(SINGLE_RGB)
        trainer = AutoEncoderTrainer(ae, lr=3e-3)
        weights = RareColourWeights(power).fit(frames) if power else None
        batch_rng = np.random.default_rng(1)
        for _ in range(350):
            trainer.train_batch(frames[batch_rng.integers(0, len(frames), 32)], weights)
        rec = ae.reconstruct(frames)
        return ((rec[..., 0] > 150) & (rec[..., 1] < 120) & red).sum() / red.sum()

    plain, weighted = red_recall(0.0), red_recall(0.5)
    assert plain < 0.1 and weighted > 0.5, (plain, weighted)
