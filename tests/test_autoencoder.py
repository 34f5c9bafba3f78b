"""The camera auto-encoder: shapes, the loss of Eq. 4.10, and learning on rendered frames."""

import numpy as np
import pytest
import torch

from agents.autoencoder import (
    SINGLE_RGB,
    STACKED_GRAY,
    AutoEncoderSpec,
    AutoEncoderTrainer,
    ConvAutoEncoder,
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
    from mani_skill.utils.wrappers.gymnasium import CPUGymWrapper

    env = CPUGymWrapper(dynnav_tasks.make("DynNav-VisualStaticTarget-v1", obs_mode="rgb"))
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
