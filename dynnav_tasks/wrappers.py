"""``NumpyWrapper`` (a task in the plain gymnasium API) and the camera worlds' observation
wrappers (thesis Sec. 4.3, Table 5.4).

Both work on a task wrapped for plain gymnasium use (``NumpyWrapper``, below: numpy,
unbatched) made with ``obs_mode="rgb"`` (observations are images) or ``obs_mode="rgb+state"``
(observations are ``{"rgb": image, "state": vector}``, the thesis's image + lasers +
positions)::

    env = NumpyWrapper(dynnav_tasks.make("DynNav-VisualMovingTargets-v1", obs_mode="rgb"))
    env = GrayFrameStack(env, num_frames=4)   # observations: uint8 (32, 32, 4)
"""

from __future__ import annotations

from collections import deque

import gymnasium as gym
import numpy as np

_LUMA = np.array([0.299, 0.587, 0.114], dtype=np.float32)


def to_gray(rgb: np.ndarray) -> np.ndarray:
    """ITU-R 601 luma of an (H, W, 3) uint8 image, as (H, W) uint8."""
    return (rgb.astype(np.float32) @ _LUMA + 0.5).astype(np.uint8)


class GrayFrameStack(gym.ObservationWrapper):
    """The last ``num_frames`` camera frames in grayscale, stacked as channels.

    Observations become uint8 (H, W, num_frames), channel 0 the oldest frame and channel -1
    the newest. ``reset`` fills the stack with copies of the first frame, as the thesis did.
    With ``obs_mode="rgb+state"`` the "rgb" entry is replaced by "gray" (the stack) and
    "state" is kept.
    """

    def __init__(self, env: gym.Env, num_frames: int = 4):
        super().__init__(env)
        if num_frames < 1:
            raise ValueError(f"num_frames must be >= 1, got {num_frames}")
        space = env.observation_space
        self._dict = isinstance(space, gym.spaces.Dict)
        image = space["rgb"] if self._dict else space
        if not (isinstance(image, gym.spaces.Box) and image.dtype == np.uint8 and image.shape[-1:] == (3,)):
            raise ValueError(
                "GrayFrameStack needs camera observations: make the task with obs_mode='rgb' or "
                f"'rgb+state' and wrap it in NumpyWrapper or CPUGymWrapper first (got observation space {space})"
            )
        h, w, _ = image.shape
        self.num_frames = num_frames
        gray = gym.spaces.Box(0, 255, (h, w, num_frames), dtype=np.uint8)
        self.observation_space = gym.spaces.Dict(gray=gray, state=space["state"]) if self._dict else gray
        self._frames: deque = deque(maxlen=num_frames)

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        first = to_gray(obs["rgb"] if self._dict else obs)
        self._frames.clear()
        self._frames.extend([first] * self.num_frames)
        return self._stacked(obs), info

    def observation(self, obs):
        self._frames.append(to_gray(obs["rgb"] if self._dict else obs))
        return self._stacked(obs)

    def _stacked(self, obs):
        stack = np.stack(self._frames, axis=-1)
        return {"gray": stack, "state": obs["state"]} if self._dict else stack


class NumpyWrapper(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """A dynnav task in the plain gymnasium API: numpy observations, float rewards, bool flags,
    no batch dimension. Wrap what ``gymnasium.make`` returned::

        env = NumpyWrapper(gym.make("DynNav-MovingTarget-v1"))
        obs, info = env.reset(seed=0)       # obs: float32 (20,)

    It does what ManiSkill's ``CPUGymWrapper`` does, faster: when only gymnasium's bookkeeping
    wrappers (order enforcing, the passive checker) stand between it and the task, a step
    calls ``NavEnv.step_numpy`` and never makes a torch tensor; behind any other wrapper it
    converts that wrapper's batched torch outputs. Unlike ``CPUGymWrapper`` it records its
    arguments, so ``env.spec`` re-creates the wrapped env (``gymnasium.utils.env_checker``
    needs that).
    """

    _TRANSPARENT = (gym.wrappers.OrderEnforcing, gym.wrappers.PassiveEnvChecker)

    def __init__(self, env: gym.Env):
        gym.utils.RecordConstructorArgs.__init__(self)
        gym.Wrapper.__init__(self, env)
        base = env.unwrapped
        if not hasattr(base, "step_numpy"):
            raise TypeError(f"NumpyWrapper wraps dynnav tasks made with gymnasium.make, got {base!r}")
        self.observation_space = base.single_observation_space
        self.action_space = base.single_action_space
        inner, direct = env, True
        while inner is not base:
            direct = direct and isinstance(inner, self._TRANSPARENT)
            inner = inner.env
        self._base = base if direct else None

    def reset(self, *, seed=None, options=None):
        obs, info = self.env.reset(seed=seed, options=options)
        if self._base is not None:
            return self._base.numpy_observation, {**self._base.outcome(), "reconfigure": bool(_unbatch(info["reconfigure"]))}
        return _unbatch(obs), _unbatch(info)

    def step(self, action):
        if self._base is not None:
            return self._base.step_numpy(action)
        obs, reward, terminated, truncated, info = self.env.step(action)
        return _unbatch(obs), float(_unbatch(reward)), bool(_unbatch(terminated)), bool(_unbatch(truncated)), _unbatch(info)

    def render(self):
        frame = self.env.render()
        return None if frame is None else _unbatch(frame)


def _unbatch(x):
    """Batched torch (or numpy) data -> the first element, as numpy (dicts recursively)."""
    if isinstance(x, dict):
        return {k: _unbatch(v) for k, v in x.items()}
    if hasattr(x, "detach"):
        x = x.detach().cpu().numpy()
    if isinstance(x, np.ndarray) and x.ndim > 0:
        x = x[0]
    return x.item() if isinstance(x, np.ndarray) and x.ndim == 0 else x
