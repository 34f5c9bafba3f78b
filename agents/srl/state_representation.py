"""State representation learning (SRL) for the camera runs: the auto-encoder on the thesis's
Algorithm 2 schedule.

* Before the first update (episode ``ae_first_update``, 400 by default) the agent acts at
  random, only collecting frames; the Q-network is not trained (it would learn on the
  latents of an untrained encoder).
* At episodes ``ae_first_update + k * ae_update_every`` for k < ``ae_updates`` (400, 800,
  1200 and, for frame stacks, 1600) the auto-encoder trains for ``ae_iterations`` iterations
  of ``ae_batches`` batches of ``ae_batch_size`` frames drawn from the observation memory
  (20 x 50 x 256 for one frame, 40 x 25 x 256 for stacks: Table 5.3).
* Between updates the encoder is frozen; the Q-network reads its latent (optionally beside
  parts of the task's state vector, Table 5.4) and trains at every step.

With ``ae_rare_colour_power`` p > 0 (beyond the study) each update first counts the colours
of a sample of the memory's frames and weights every pixel's squared error by its colour's
frequency^-p (``RareColourWeights``), so the small red target is reconstructed; the losses
in ``srl_loss.csv`` are then the weighted ones.

Latents are standardised per dimension with the mean and standard deviation over the
memory's frames, measured after each update, so the Q-network's inputs keep a scale of about
one whatever the encoder learned (the thesis fed raw latents; the scale is not given). After
an update every stored frame is re-encoded, so old transitions are replayed through the new
encoder.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import torch

from agents.srl.autoencoder import AutoEncoderSpec, AutoEncoderTrainer, ConvAutoEncoder, RareColourWeights

# thesis Table 5.3: (latent, conv filters, iterations, batches per iteration, updates)
SINGLE_FRAME_DEFAULTS = dict(latent=10, conv=(32, 64), iterations=20, batches=50, updates=3)
STACK_DEFAULTS = dict(latent=15, conv=(64, 128), iterations=40, batches=25, updates=4)
RARE_COLOUR_SAMPLE = 10_000  # frames whose colours set the loss weights of an update (ae_rare_colour_power)


@dataclass(frozen=True)
class SRLSettings:
    """The resolved auto-encoder sizes and schedule of a run (config zeros replaced by Table 5.3's values)."""

    frames: int
    frame_shape: tuple[int, int, int]
    spec: AutoEncoderSpec
    first_update: int
    update_every: int
    updates: int
    iterations: int
    batches: int
    batch_size: int
    learning_rate: float
    rare_colour_power: float = 0.0

    @classmethod
    def from_config(cls, config, image_size: int = 32) -> "SRLSettings":
        """The settings of a run's config, for frames of ``image_size`` pixels."""
        c = config.camera
        d = SINGLE_FRAME_DEFAULTS if c.camera_frames == 1 else STACK_DEFAULTS
        channels = 3 if c.camera_frames == 1 else c.camera_frames
        spec = AutoEncoderSpec(
            image_size=image_size, in_channels=channels,
            conv_channels=tuple(c.ae_conv_channels) or d["conv"], dense=c.ae_dense, latent=c.ae_latent or d["latent"],
        )
        return cls(
            frames=c.camera_frames, frame_shape=(image_size, image_size, channels), spec=spec,
            first_update=c.ae_first_update, update_every=c.ae_update_every,
            updates=c.ae_updates or d["updates"], iterations=c.ae_iterations or d["iterations"],
            batches=c.ae_batches or d["batches"], batch_size=c.ae_batch_size,
            learning_rate=c.ae_learning_rate, rare_colour_power=c.ae_rare_colour_power,
        )

    @property
    def update_episodes(self) -> list[int]:
        """Episode counts after which the auto-encoder trains (400, 800, 1200, ...)."""
        return [self.first_update + k * self.update_every for k in range(self.updates)]


class StateRepresentation:
    """The auto-encoder, its optimiser, the latent standardisation and the update count."""

    def __init__(self, settings: SRLSettings, seed: int):
        torch.manual_seed(seed)
        self.settings = settings
        self.model = ConvAutoEncoder(settings.spec).eval()
        self.trainer = AutoEncoderTrainer(self.model, lr=settings.learning_rate)
        self.updates_done = 0
        self.mean = np.zeros(settings.spec.latent, dtype=np.float32)
        self.std = np.ones(settings.spec.latent, dtype=np.float32)
        self.can_reconstruct = True
        """False when only the encoder was loaded (a pretrained model): no reconstructions"""

    @property
    def latent_dim(self) -> int:
        """Length of the latent vector."""
        return self.settings.spec.latent

    @property
    def trained(self) -> bool:
        """True once the first update has run (the Q-network's phase of Alg. 2)."""
        return self.updates_done > 0

    def due(self, episodes_done: int) -> bool:
        """Whether an update is scheduled after ``episodes_done`` finished episodes."""
        return episodes_done in self.settings.update_episodes

    def encode(self, frames: np.ndarray) -> np.ndarray:
        """Standardised latents of uint8 frames (one frame (H, W, C) or a batch)."""
        return ((self.model.encode(frames) - self.mean) / self.std).astype(np.float32)

    def reconstruct(self, frames: np.ndarray) -> np.ndarray:
        """The auto-encoder's uint8 reconstructions of uint8 frames (ValueError without a decoder)."""
        if not self.can_reconstruct:
            raise ValueError("this auto-encoder was loaded without its decoder (a pretrained model): it encodes "
                             "frames but cannot reconstruct them")
        return self.model.reconstruct(frames)

    def update(self, replay, rng: np.random.Generator, progress: bool = False) -> list[float]:
        """One scheduled update on ``replay``'s frames; returns the mean loss of each iteration.

        Afterwards the latent statistics are measured again and every stored frame is re-encoded."""
        s = self.settings
        weights = None
        if s.rare_colour_power > 0:
            sample = replay.sample_frames(min(replay.size, RARE_COLOUR_SAMPLE), rng)
            weights = RareColourWeights(s.rare_colour_power).fit(sample)
        losses = []
        bar = None
        if progress:
            from tqdm import tqdm

            bar = tqdm(total=s.iterations, desc=f"auto-encoder update {self.updates_done + 1}/{s.updates}",
                       unit="it", leave=False, dynamic_ncols=True)
        for _ in range(s.iterations):
            batch_losses = [self.trainer.train_batch(replay.sample_frames(s.batch_size, rng), weights) for _ in range(s.batches)]
            losses.append(float(np.mean(batch_losses)))
            if bar is not None:
                bar.update(1)
                bar.set_postfix(loss=f"{losses[-1]:.2f}", refresh=False)
        if bar is not None:
            bar.close()
        self.updates_done += 1
        self.mean[:], self.std[:] = 0.0, 1.0
        replay.refresh_latents(self.model.encode)
        raw = replay.latents[: replay.size]
        self.mean[:] = raw.mean(axis=0)
        self.std[:] = raw.std(axis=0) + 1e-6
        replay.latents[: replay.size] = (raw - self.mean) / self.std
        return losses

    def state_dict(self) -> dict:
        """The auto-encoder, its optimizer and its update count, for a checkpoint."""
        return dict(trainer=self.trainer.state_dict(), updates_done=self.updates_done,
                    mean=self.mean.copy(), std=self.std.copy(), spec=dataclasses.asdict(self.settings.spec))

    def encoder_weights(self) -> dict[str, torch.Tensor]:
        """What encoding needs, as tensors (a pretrained model's ``autoencoder.safetensors``): the
        encoder's weights under ``encoder.``, the latent standardisation as ``latent_mean`` and
        ``latent_std``. No decoder and no optimizer: enough to act, not to reconstruct or train on."""
        out = {f"encoder.{k}": v for k, v in self.model.encoder.state_dict().items()}
        out.update(latent_mean=torch.from_numpy(self.mean.copy()), latent_std=torch.from_numpy(self.std.copy()))
        return out

    def load_encoder_weights(self, tensors: dict[str, torch.Tensor]) -> None:
        """Restore what ``encoder_weights`` gave: the auto-encoder then encodes as trained, and
        cannot reconstruct (``can_reconstruct`` False). ValueError if they do not fit this encoder."""
        encoder = {k.removeprefix("encoder."): v for k, v in tensors.items() if k.startswith("encoder.")}
        try:
            self.model.encoder.load_state_dict(encoder)
            self.mean[:], self.std[:] = tensors["latent_mean"].float().numpy(), tensors["latent_std"].float().numpy()
        except (RuntimeError, KeyError, ValueError) as err:
            raise ValueError(f"the encoder weights do not fit this run's auto-encoder {self.settings.spec}: "
                             f"{err}") from err
        self.model.eval()
        self.updates_done = max(self.updates_done, 1)
        self.can_reconstruct = False

    def load_state_dict(self, state: dict) -> None:
        """Restore what ``state_dict`` saved."""
        spec = dict(state["spec"], conv_channels=tuple(state["spec"]["conv_channels"]))
        if AutoEncoderSpec(**spec) != self.settings.spec:
            raise ValueError(f"checkpoint auto-encoder is {state['spec']}, this run's {self.settings.spec}")
        self.trainer.load_state_dict(state["trainer"])
        self.model.eval()
        self.updates_done = int(state["updates_done"])
        self.mean[:], self.std[:] = state["mean"], state["std"]
