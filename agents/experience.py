"""What the Q-network reads and what the replay memory keeps, for state runs and camera runs.

Both classes turn the environment's observations into Q-network inputs and store the
transitions, behind the same calls the training loop makes (``memory`` is what a checkpoint saves)::

    x = experience.begin(obs)                                   # an episode's first observation
    x = experience.step(action, reward, next_obs, terminated)   # store a transition, next input
    experience.sample_into(learner.batch, rng)                  # a minibatch for one update

* ``VectorExperience``: the task's state vector (lasers, positions), scaled to [-1, 1].
* ``CameraExperience`` (thesis Sec. 5.2.3): the auto-encoder's latent of the camera frame (one
  RGB frame or a stack of gray frames), followed by the chosen parts of the state vector
  (Table 5.4). Before the auto-encoder's first update its inputs are ``None``: the agent acts
  at random and the Q-network does not train (Alg. 2).
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .envs import ObsScaler, frame_key, state_slices
from .frame_replay import FrameReplay
from .replay import ReplayMemory
from .state_representation import SRLSettings, StateRepresentation


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


class VectorExperience:
    """State-vector runs: scaled state vectors in a ``ReplayMemory``."""

    ready = True
    """the Q-network can act on and learn from these inputs"""
    srl = None
    """no state representation to learn"""

    def __init__(self, env, config):
        self.scale = ObsScaler(env.observation_space, config.normalize_obs)
        self.dim = int(env.observation_space.shape[0])
        self.memory = ReplayMemory(config.buffer_size, self.dim)
        self._x = None

    def begin(self, obs) -> np.ndarray:
        self._x = self.scale(obs)
        return self._x

    def step(self, action: int, reward: float, next_obs, terminated: bool) -> np.ndarray:
        x = self.scale(next_obs)
        self.memory.add(self._x, action, reward, x, terminated)
        self._x = x
        return x

    def sample_into(self, batch, rng) -> None:
        self.memory.sample_into(batch, rng)

    def __len__(self) -> int:
        return len(self.memory)


class CameraFeatures:
    """Camera observation -> [standardised latent | scaled state parts] (no storage)."""

    def __init__(self, env, config, srl: StateRepresentation):
        self.srl = srl
        self.frame_key = frame_key(config.camera_frames)
        space = env.observation_space["state"]
        self.parts = state_part_indices(env.unwrapped.state_layout(), config.camera_state)
        scaler = ObsScaler(space, config.normalize_obs)
        self.offset, self.scale = scaler.offset[self.parts], scaler.scale[self.parts]
        self.dim = srl.latent_dim + len(self.parts)
        self.last_latent: Optional[np.ndarray] = None
        """the latent of the frame most recently turned into an input (for recordings and plots)"""

    def split(self, obs) -> tuple[np.ndarray, np.ndarray]:
        """(uint8 frame, scaled state parts) of an observation."""
        return obs[self.frame_key], (obs["state"][self.parts] - self.offset) * self.scale

    def combine(self, frame: np.ndarray, state: np.ndarray) -> np.ndarray:
        self.last_latent = self.srl.encode(frame)
        return np.concatenate([self.last_latent, state]).astype(np.float32)

    def __call__(self, obs) -> np.ndarray:
        return self.combine(*self.split(obs))

    def views(self, obs) -> dict:
        """The latent and the reconstruction of an observation's frame, for a recording (a stack of
        gray frames shows its newest frame); empty before the auto-encoder's first update."""
        if not self.srl.trained:
            return {}
        frame = self.split(obs)[0]
        reconstruction = self.srl.reconstruct(frame)
        if reconstruction.shape[-1] != 3:
            reconstruction = reconstruction[..., -1]
        return dict(latent=self.srl.encode(frame), reconstruction=reconstruction)


class CameraExperience:
    """Camera runs: frames in a ``FrameReplay``, encoded by the frozen auto-encoder."""

    def __init__(self, env, config, srl: StateRepresentation):
        self.srl = srl
        self.encoder_features = CameraFeatures(env, config, srl)
        self.dim = self.encoder_features.dim
        frame_shape = env.observation_space[self.encoder_features.frame_key].shape
        self.memory = FrameReplay(config.buffer_size, frame_shape, len(self.encoder_features.parts), srl.latent_dim)

    @property
    def ready(self) -> bool:
        return self.srl.trained

    def _input(self, slot: int) -> Optional[np.ndarray]:
        if not self.srl.trained:
            return None
        m = self.memory
        x = self.encoder_features.combine(m.frames[slot], m.states[slot])
        m.latents[slot] = x[: self.srl.latent_dim]
        return x

    def begin(self, obs) -> Optional[np.ndarray]:
        return self._input(self.memory.start(*self.encoder_features.split(obs)))

    def step(self, action: int, reward: float, next_obs, terminated: bool) -> Optional[np.ndarray]:
        frame, state = self.encoder_features.split(next_obs)
        return self._input(self.memory.add(action, reward, frame, state, terminated))

    def sample_into(self, batch, rng) -> None:
        self.memory.sample_into(batch, rng)

    def __len__(self) -> int:
        return len(self.memory)


def new_state_representation(env, config) -> StateRepresentation:
    """An untrained auto-encoder sized for ``env``'s camera frames and ``config``'s settings."""
    image = env.observation_space[frame_key(config.camera_frames)].shape[0]
    return StateRepresentation(SRLSettings.from_config(config, image_size=image), seed=config.seed)


def make_experience(env, config):
    """The experience of a run: ``CameraExperience`` when ``config.camera_frames`` > 0."""
    if not config.camera_frames:
        return VectorExperience(env, config)
    return CameraExperience(env, config, new_state_representation(env, config))
