"""The convolutional auto-encoder that compresses camera frames for the Q-network
(thesis Sec. 4.3, Figs. 4.3-4.4).

Encoder: two 3x3 convolutions with stride 2 (32 -> 16 -> 8 pixels), a dense layer and the
latent layer; the decoder mirrors it with 3x3 transposed convolutions of stride 2. ReLU everywhere but the
latent (linear) and the output (sigmoid, pixels in [0, 1]).

=====================  ===============  =======================  ======
input                  channels         dense                    latent
=====================  ===============  =======================  ======
one RGB frame          32x32x3          conv 32, conv 64, 64     10
4 stacked gray frames  32x32x4          conv 64, conv 128, 64    15
=====================  ===============  =======================  ======

The thesis's figures give the layer widths but not the strides (its stated shapes, 3x3x32
after a stride-1 convolution of a 32x32 image, cannot be right); stride 2 keeps the dense
layer small (8x8x64 = 4096 inputs). Frames are uint8 (H, W, C) as the tasks return them;
``encode`` and ``reconstruct`` take such frames (or batches of them) directly.

Reconstruction loss (Eq. 4.10): the squared error summed over an image's pixels and
channels, averaged over the N images of the batch, pixels scaled to [0, 1].

Beyond the study, ``RareColourWeights`` weights each pixel's squared error by how rare its
colour is in the observation memory. The red target disc covers about 0.06% of the pixels of
world 5.5b's frames; with every pixel weighted the same the auto-encoder leaves it out of its
reconstructions (as the thesis's Fig. 6.12 shows), and the latent cannot say whether the
target is in view.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
from torch import nn


@dataclass(frozen=True)
class AutoEncoderSpec:
    """Layer sizes of the auto-encoder."""

    image_size: int = 32
    """side of the square input frames"""
    in_channels: int = 3
    """3 for an RGB frame, N for N stacked gray frames"""
    conv_channels: tuple[int, int] = (32, 64)
    """filters of the two convolutions (the stacked-frame thesis model uses 64, 128)"""
    dense: int = 64
    """width of the dense layer before the latent"""
    latent: int = 10
    """latent size (the thesis: 10 for one frame, 15 for stacked frames)"""

    def __post_init__(self):
        if self.image_size % 4:
            raise ValueError(f"image_size must be a multiple of 4 (two stride-2 convolutions), got {self.image_size}")
        if min(self.in_channels, self.dense, self.latent, *self.conv_channels) < 1:
            raise ValueError(f"every auto-encoder size must be >= 1, got {self}")


SINGLE_RGB = AutoEncoderSpec()
STACKED_GRAY = AutoEncoderSpec(in_channels=4, conv_channels=(64, 128), latent=15)


class ConvAutoEncoder(nn.Module):
    """Two stride-2 convolutions and two dense layers down to the latent vector, and the mirror
    image back up to the frame (sigmoid output in [0, 1]), sized by an ``AutoEncoderSpec``."""

    def __init__(self, spec: AutoEncoderSpec = SINGLE_RGB):
        super().__init__()
        self.spec = spec
        c1, c2 = spec.conv_channels
        side = spec.image_size // 4
        flat = c2 * side * side
        self.encoder = nn.Sequential(
            nn.Conv2d(spec.in_channels, c1, 3, stride=2, padding=1), nn.ReLU(),
            nn.Conv2d(c1, c2, 3, stride=2, padding=1), nn.ReLU(),
            nn.Flatten(),
            nn.Linear(flat, spec.dense), nn.ReLU(),
            nn.Linear(spec.dense, spec.latent),
        )
        self.decoder = nn.Sequential(
            nn.Linear(spec.latent, spec.dense), nn.ReLU(),
            nn.Linear(spec.dense, flat), nn.ReLU(),
            nn.Unflatten(1, (c2, side, side)),
            nn.ConvTranspose2d(c2, c1, 3, stride=2, padding=1, output_padding=1), nn.ReLU(),
            nn.ConvTranspose2d(c1, spec.in_channels, 3, stride=2, padding=1, output_padding=1), nn.Sigmoid(),
        )

    # ------------------------------------------------------------------ tensors
    def to_input(self, frames: np.ndarray) -> torch.Tensor:
        """uint8 (B, H, W, C) or (H, W, C) frames -> float (B, C, H, W) in [0, 1]."""
        x = np.asarray(frames)
        if x.ndim == 3:
            x = x[None]
        s = self.spec
        if x.shape[1:] != (s.image_size, s.image_size, s.in_channels):
            raise ValueError(f"expected frames of shape (H, W, C) = {(s.image_size, s.image_size, s.in_channels)}, got {x.shape[1:]}")
        return torch.from_numpy(np.ascontiguousarray(x)).permute(0, 3, 1, 2).float().div_(255.0)

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """The latent vectors and the reconstructions of a batch of frames (B, C, H, W) in [0, 1]."""
        z = self.encoder(x)
        return z, self.decoder(z)

    # ------------------------------------------------------------------ numpy helpers
    @torch.inference_mode()
    def encode(self, frames: np.ndarray) -> np.ndarray:
        """Latent vectors (B, latent), or (latent,) for one frame, as float32 numpy."""
        z = self.encoder(self.to_input(frames)).numpy()
        return z[0] if np.asarray(frames).ndim == 3 else z

    @torch.inference_mode()
    def reconstruct(self, frames: np.ndarray) -> np.ndarray:
        """Reconstructed frames as uint8, shaped like the input."""
        _, y = self(self.to_input(frames))
        out = (y.permute(0, 2, 3, 1).numpy() * 255.0 + 0.5).astype(np.uint8)
        return out[0] if np.asarray(frames).ndim == 3 else out


def reconstruction_loss(reconstruction: torch.Tensor, target: torch.Tensor,
                        weights: torch.Tensor | None = None) -> torch.Tensor:
    """Eq. 4.10: per-image sum of squared errors, averaged over the batch.

    ``weights`` (broadcastable to the images, e.g. (B, 1, H, W)) multiplies each squared error."""
    err = (reconstruction - target).pow(2)
    if weights is not None:
        err = err * weights
    return err.flatten(1).sum(dim=1).mean()


class RareColourWeights:
    """Per-pixel loss weights (frequency of the pixel's colour)^-power, normalised to a mean of 1.

    Colours are binned at ``levels`` levels per channel. For RGB frames a pixel's bin is its
    (r, g, b) triple, and one weight covers its three channels; for stacks of gray frames
    every value is binned on its own. ``fit`` counts the bins over a sample of frames
    (uint8, (B, H, W, C)); a bin not seen there gets the largest weight of those seen.
    power 0 gives every pixel weight 1 (Eq. 4.10); 1 gives every colour the same total weight.
    """

    def __init__(self, power: float, levels: int = 16):
        if power < 0:
            raise ValueError(f"power must not be negative, got {power}")
        if not 2 <= levels <= 256 or 256 % levels:
            raise ValueError(f"levels must divide 256 and be at least 2, got {levels}")
        self.power, self.levels = float(power), levels
        self.table: np.ndarray | None = None

    def _bins(self, frames: np.ndarray) -> np.ndarray:
        q = np.asarray(frames, dtype=np.int64) // (256 // self.levels)
        if q.shape[-1] == 3:
            return (q[..., 0] * self.levels + q[..., 1]) * self.levels + q[..., 2]  # (B, H, W)
        return q  # (B, H, W, C): each gray value on its own

    def fit(self, frames: np.ndarray) -> "RareColourWeights":
        """Measure how often each colour bin occurs in ``frames``; rarer bins weigh more."""
        bins = self._bins(frames)
        freq = np.bincount(bins.ravel(), minlength=self.levels ** 3) / bins.size  # room for RGB's bins
        seen = freq > 0
        w = np.zeros_like(freq)
        w[seen] = freq[seen] ** -self.power
        w /= (freq * w).sum()
        w[~seen] = w[seen].max()
        self.table = w.astype(np.float32)
        return self

    def __call__(self, frames: np.ndarray) -> torch.Tensor:
        """Weights shaped for ``reconstruction_loss``: (B, 1, H, W) for RGB, (B, C, H, W) for stacks."""
        if self.table is None:
            raise RuntimeError("RareColourWeights.fit must run before the weights are used")
        w = torch.from_numpy(self.table[self._bins(frames)])
        return w.unsqueeze(1) if w.ndim == 3 else w.permute(0, 3, 1, 2)


class AutoEncoderTrainer:
    """Adam on the reconstruction loss, over batches of uint8 frames."""

    def __init__(self, model: ConvAutoEncoder, lr: float = 1e-3):
        self.model = model
        self.optimizer = torch.optim.Adam(model.parameters(), lr=lr)

    def train_batch(self, frames: np.ndarray, weights: RareColourWeights | None = None) -> float:
        """One Adam step on a batch of uint8 frames; returns its reconstruction loss."""
        self.model.train()
        x = self.model.to_input(frames)
        _, y = self.model(x)
        loss = reconstruction_loss(y, x, None if weights is None else weights(frames))
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        self.optimizer.step()
        self.model.eval()
        return loss.item()

    def state_dict(self) -> dict:
        """The model's and its optimizer's state, for a checkpoint."""
        return {"model": self.model.state_dict(), "optimizer": self.optimizer.state_dict()}

    def load_state_dict(self, state: dict) -> None:
        """Restore what ``state_dict`` saved."""
        self.model.load_state_dict(state["model"])
        self.optimizer.load_state_dict(state["optimizer"])
