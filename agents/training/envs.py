"""Make a training or test environment from a task id.

dynnav tasks are ManiSkill tasks: they are wrapped in ``dynnav_tasks.NumpyWrapper`` (numpy,
unbatched, the same values as ManiSkill's ``CPUGymWrapper`` without the torch round trip) and
take the reward options. Any other gymnasium id is made as it is and must have
a ``Discrete`` action space and a one-dimensional ``Box`` observation space.
"""

from __future__ import annotations

import difflib
import os

import gymnasium as gym

os.environ.setdefault("MS_RENDERER_LOG_LEVEL", "error")


def dynnav_ids() -> tuple[str, ...]:
    """The registered dynnav task ids."""
    import dynnav_tasks

    return tuple(dynnav_tasks.ALL_TASK_IDS)


def is_dynnav(task: str) -> bool:
    """Whether ``task`` is a dynnav task (not another gymnasium env)."""
    return task in dynnav_ids()


def check_task(task: str) -> None:
    """Raise ValueError for a task id gymnasium does not know, listing the close matches."""
    known = list(gym.registry.keys())
    if task in known or is_dynnav(task):
        return
    candidates = list(dict.fromkeys(list(dynnav_ids()) + known))
    close = difflib.get_close_matches(task, candidates, n=3, cutoff=0.6)
    hint = f" Did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
    raise ValueError(f"Unknown task id {task!r}.{hint} dynnav tasks: {', '.join(dynnav_ids())}.")


def frame_key(camera_frames: int) -> str:
    """The observation key of the camera frames: "rgb" for one frame, "gray" for a stack."""
    return "rgb" if camera_frames == 1 else "gray"


def state_slices(layout: list[tuple[str, int]]) -> dict[str, slice]:
    """Where each named part of a dynnav state vector (``state_layout()``) sits."""
    out, offset = {}, 0
    for name, size in layout:
        out[name] = slice(offset, offset + size)
        offset += size
    return out


def make_env(task: str, reward_mode: str | None = None, reward_params: dict | None = None,
             task_kwargs: dict | None = None, camera_frames: int = 0, state_frames: int = 1) -> gym.Env:
    """The environment for ``task`` with the plain gymnasium API (numpy in, numpy out).

    ``camera_frames`` 0: observations are the state vector (with ``state_frames`` N >= 2, the
    last N state vectors, oldest first, as one flat vector); 1: ``{"rgb": frame, "state": vector}``;
    N >= 2: ``{"gray": last N gray frames, "state": vector}`` (dynnav tasks only)."""
    check_task(task)
    if is_dynnav(task):
        import dynnav_tasks
        kwargs = {"reward_params": dict(reward_params or {}), **dict(task_kwargs or {})}
        if reward_mode is not None:
            kwargs["reward_mode"] = reward_mode
        if camera_frames:
            kwargs["obs_mode"] = "rgb+state"
        try:
            env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task, **kwargs))
        except TypeError as err:  # an unknown keyword argument
            raise ValueError(f"{task}: {err}") from err
        if camera_frames >= 2:
            from dynnav_tasks.wrappers import GrayFrameStack

            env = GrayFrameStack(env, num_frames=camera_frames)
    else:
        if reward_mode is not None or reward_params or task_kwargs or camera_frames:
            raise ValueError(f"reward_mode, reward_params, task_kwargs and camera_frames apply to dynnav tasks "
                             f"only, not {task!r}")
        env = gym.make(task)
    if not isinstance(env.action_space, gym.spaces.Discrete):
        env.close()
        raise ValueError(f"{task!r} has a {type(env.action_space).__name__} action space; DQN needs Discrete")
    space = env.observation_space
    if camera_frames:
        return env
    if not isinstance(space, gym.spaces.Box) or len(space.shape) != 1:
        env.close()
        raise ValueError(f"{task!r} observations are {space}; this agent needs a one-dimensional Box")
    if state_frames > 1:
        from gymnasium.wrappers import FlattenObservation, FrameStackObservation

        env = FlattenObservation(FrameStackObservation(env, state_frames, padding_type="reset"))
    return env


def make_env_from(config, **task_kwargs) -> gym.Env:
    """``make_env`` with a run config's task, reward, task options and camera frames (``task_kwargs``
    are added to the config's)."""
    e = config.env
    return make_env(config.task, e.reward_mode, e.reward_params, {**e.task_kwargs, **task_kwargs},
                    config.camera.camera_frames, e.state_frames)
