"""What the Q-network reads and what the replay memory keeps, for state, camera and pixel runs.

A *features* object turns an environment observation into the Q-network's input (an array,
or a tuple of arrays for a network with several inputs); ``input_specs`` gives each input's
shape and dtype. An *experience* adds the replay memory, behind the calls the training loop
makes (``memory`` is what a checkpoint saves)::

    x = experience.begin(obs)                                   # an episode's first observation
    x = experience.step(action, reward, next_obs, terminated)   # store a transition, next input
    experience.sample_into(batch, rng)                          # a minibatch for one update

* state runs: the task's state vector, scaled to [-1, 1] (``ReplayMemory``);
* camera runs, ``camera_input: latent`` (thesis Sec. 5.2.3): the auto-encoder's latent of the
  frame (one RGB frame or a stack of gray frames) followed by the chosen parts of the state
  vector (Table 5.4). Until the auto-encoder's first update the inputs are ``None``: the agent
  acts at random and the Q-network does not train (Alg. 2);
* camera runs, ``camera_input: pixels``: the uint8 frames themselves and the chosen state parts,
  two inputs of a conv Q-network.
Camera runs store every frame once, in a ``FrameReplay``. With a recurrent Q-network
(``dqn.recurrent``, docs/memory.md) a ``SequenceExperience`` keeps whole episodes in a
``FrameReplay`` (state-vector runs without frames) and samples sequences of them.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from agents.core.frame_replay import FrameReplay
from agents.core.obs_scaling import ObsScaler
from agents.core.replay import ReplayMemory
from agents.core.sequence_replay import sample_sequences_into
from agents.srl.state_representation import SRLSettings, StateRepresentation
from agents.training.envs import frame_key, state_slices


def state_part_indices(layout: list[tuple[str, int]], names) -> np.ndarray:
    """Indices of the named parts of a dynnav state vector, in the vector's order.

    Names are those of ``state_layout()`` (lasers, robot_xy, target_xy, obstacle0_xy, ...);
    ``obstacles`` selects every obstacle's position."""
    starts = state_slices(layout)
    wanted = set()
    for name in names:
        matches = [n for n in starts if n == name or (name == "obstacles" and n.startswith("obstacle"))]
        if not matches:
            valid = ", ".join(list(starts) + ["obstacles"])
            raise ValueError(f"camera_state: unknown state part {name!r}; valid parts: {valid}")
        wanted.update(matches)
    return np.array([i for n, part in starts.items() if n in wanted for i in range(part.start, part.stop)],
                    dtype=np.int64)


# ---------------------------------------------------------------------------------------- features
NO_FRAME = np.zeros(0, dtype=np.uint8)
"""the frame of a state-vector observation in a ``FrameReplay`` (none)"""


class VectorFeatures:
    """State vector -> scaled state vector."""

    def __init__(self, env, config):
        self.scale = ObsScaler(env.observation_space, config.env.normalize_obs)
        self.input_specs = [((int(env.observation_space.shape[0]),), np.float32)]

    def __call__(self, obs) -> np.ndarray:
        return self.scale(obs).astype(np.float32)

    def split(self, obs) -> tuple[np.ndarray, np.ndarray]:
        """No frame and the scaled state vector, as a ``FrameReplay`` stores a state-vector observation."""
        return NO_FRAME, self(obs)


class CameraParts:
    """The frame and the scaled state parts of a camera observation ``{"rgb" or "gray": ..., "state": ...}``."""

    def __init__(self, env, config):
        self.frame_key = frame_key(config.camera.camera_frames)
        self.frame_shape = tuple(env.observation_space[self.frame_key].shape)
        self.parts = state_part_indices(env.unwrapped.state_layout(), config.camera.camera_state)
        scaler = ObsScaler(env.observation_space["state"], config.env.normalize_obs)
        self.offset, self.scale = scaler.offset[self.parts], scaler.scale[self.parts]

    def split(self, obs) -> tuple[np.ndarray, np.ndarray]:
        """The frame and the scaled state parts of an observation."""
        return obs[self.frame_key], ((obs["state"][self.parts] - self.offset) * self.scale).astype(np.float32)


class LatentFeatures(CameraParts):
    """Camera observation -> [standardised latent | scaled state parts]."""

    def __init__(self, env, config, srl: StateRepresentation):
        super().__init__(env, config)
        self.srl = srl
        self.input_specs = [((srl.latent_dim + len(self.parts),), np.float32)]
        self.last_latent: Optional[np.ndarray] = None
        """the latent of the frame most recently turned into an input (for recordings and plots)"""

    def combine(self, frame: np.ndarray, state: np.ndarray) -> np.ndarray:
        """The Q-network input [latent of ``frame`` | ``state``]; remembers the latent."""
        self.last_latent = self.srl.encode(frame)
        return np.concatenate([self.last_latent, state]).astype(np.float32)

    def __call__(self, obs) -> np.ndarray:
        return self.combine(*self.split(obs))

    def views(self, obs) -> dict:
        """The latent and the reconstruction of an observation's frame, for a recording (a stack of
        gray frames shows its newest frame); empty before the auto-encoder's first update, the
        latent alone for an encoder without its decoder (a pretrained model)."""
        if not self.srl.trained:
            return {}
        frame = self.split(obs)[0]
        if not self.srl.can_reconstruct:
            return dict(latent=self.srl.encode(frame))
        reconstruction = self.srl.reconstruct(frame)
        if reconstruction.shape[-1] != 3:
            reconstruction = reconstruction[..., -1]
        return dict(latent=self.srl.encode(frame), reconstruction=reconstruction)


class PixelFeatures(CameraParts):
    """Camera observation -> (uint8 frame, scaled state parts): the two inputs of a pixel Q-network."""

    def __init__(self, env, config):
        super().__init__(env, config)
        self.input_specs = [(self.frame_shape, np.uint8), ((len(self.parts),), np.float32)]

    def __call__(self, obs) -> tuple[np.ndarray, np.ndarray]:
        return self.split(obs)


def new_state_representation(env, config) -> StateRepresentation:
    """An untrained auto-encoder sized for ``env``'s camera frames and ``config``'s settings."""
    image = env.observation_space[frame_key(config.camera.camera_frames)].shape[0]
    return StateRepresentation(SRLSettings.from_config(config, image_size=image), seed=config.seed)


def make_features(env, config, srl: Optional[StateRepresentation] = None):
    """The features of a run: vector, latent (with ``srl``, or a new one) or pixels, as the config says."""
    c = config.camera
    if not c.camera_frames:
        return VectorFeatures(env, config)
    if c.camera_input == "pixels":
        return PixelFeatures(env, config)
    return LatentFeatures(env, config, srl if srl is not None else new_state_representation(env, config))


# ---------------------------------------------------------------------------------------- experience
class VectorExperience:
    """State-vector runs: scaled state vectors in a ``ReplayMemory``."""

    ready = True
    """the Q-network can act on and learn from these inputs"""
    srl = None
    """no state representation to learn"""

    def __init__(self, features: VectorFeatures, config):
        self.features = features
        self.memory = ReplayMemory(config.dqn.buffer_size, features.input_specs[0][0][0])
        self._x = None

    def begin(self, obs) -> np.ndarray:
        """Note an episode's first observation; return the Q-network's input for it."""
        self._x = self.features(obs)
        return self._x

    def step(self, action: int, reward: float, next_obs, terminated: bool) -> np.ndarray:
        """Store the transition to ``next_obs``; return the Q-network's input for it."""
        x = self.features(next_obs)
        self.memory.add(self._x, action, reward, x, terminated)
        self._x = x
        return x

    def sample_into(self, batch, rng) -> None:
        """Fill ``batch`` with a minibatch of stored transitions drawn with ``rng``."""
        self.memory.sample_into(batch, rng)

    def __len__(self) -> int:
        return len(self.memory)


class FrameExperience:
    """Camera runs: frames and state parts in a ``FrameReplay``; the inputs are latents of the
    frozen auto-encoder (``LatentFeatures``) or the frames themselves (``PixelFeatures``)."""

    def __init__(self, features, config):
        self.features = features
        self.srl = getattr(features, "srl", None)
        latent = self.srl.latent_dim if self.srl is not None else 0
        self.memory = FrameReplay(config.dqn.buffer_size, features.frame_shape, len(features.parts), latent)

    @property
    def ready(self) -> bool:
        """Whether the Q-network can act on and learn from the inputs (after the auto-encoder's first update)."""
        return self.srl is None or self.srl.trained

    def _input(self, slot: int, frame: np.ndarray, state: np.ndarray):
        if self.srl is None:
            return frame, state
        if not self.srl.trained:
            return None
        x = self.features.combine(frame, state)
        self.memory.latents[slot] = x[: self.srl.latent_dim]
        return x

    def begin(self, obs):
        """Note an episode's first observation; return the Q-network's input for it."""
        frame, state = self.features.split(obs)
        return self._input(self.memory.start(frame, state), frame, state)

    def step(self, action: int, reward: float, next_obs, terminated: bool):
        """Store the transition to ``next_obs``; return the Q-network's input for it."""
        frame, state = self.features.split(next_obs)
        return self._input(self.memory.add(action, reward, frame, state, terminated), frame, state)

    def sample_into(self, batch, rng) -> None:
        """Fill ``batch`` with a minibatch of stored transitions drawn with ``rng``."""
        if self.srl is None:
            self.memory.sample_frames_into(batch, rng)
        else:
            self.memory.sample_into(batch, rng)

    def __len__(self) -> int:
        return len(self.memory)


class SequenceExperience(FrameExperience):
    """Recurrent Q-networks: every observation stored once, in episode order, in a ``FrameReplay``
    (state vectors as its state parts without frames, or camera frames with their state parts and
    latents), and minibatches of sequences (``agents.core.sequence_replay``)."""

    def __init__(self, features, config):
        self.features = features
        self.srl = getattr(features, "srl", None)
        if self.srl is None:
            shape, state_dim, latent = NO_FRAME.shape, features.input_specs[0][0][0], 0
        else:
            shape, state_dim, latent = features.frame_shape, len(features.parts), self.srl.latent_dim
        self.memory = FrameReplay(config.dqn.buffer_size, shape, state_dim, latent)

    def _input(self, slot: int, frame: np.ndarray, state: np.ndarray):
        return state if self.srl is None else super()._input(slot, frame, state)

    def sample_into(self, batch, rng) -> None:
        """Fill ``batch`` (a ``SequenceBatch``) with sequences of stored episodes drawn with ``rng``."""
        sample_sequences_into(self.memory, batch, rng)


def make_experience(env, config):
    """The features and replay memory of a run, as ``config`` says."""
    features = make_features(env, config)
    if config.dqn.recurrent:
        return SequenceExperience(features, config)
    if isinstance(features, VectorFeatures):
        return VectorExperience(features, config)
    return FrameExperience(features, config)
