"""Policy specs: what ``--policy`` names, and how each is opened on a task.

=============================  =================================================================
``pretrained:NAME``            a pretrained navigator (``agents.pretrained``), on its own task's
                               settings with the cell's options laid over them
a run directory                a DQN run's checkpoint (``python -m agents.dqn`` wrote it), the same
``FILE.zip`` with ``--algo``   a Stable-Baselines3 model (``ppo``, ``sac``, ``dqn``, ``a2c``,
                               ``td3``), acting deterministically on the task made with the cell's
                               options and ``--options``
``module:function``            a Python callable from observation to action, imported from the
                               current folder or the installed packages; ``function.reset()`` or
                               the module's ``reset()``, if there, is called at each reset
``controller:NAME``            a scripted controller (``dynnav_tasks.baselines.registry``:
                               ``planner``, ``go_to_target``, ``dwa``, ``orca_robot``,
                               ``social_force_robot``) on the drive it commands; it reads the
                               task's state as the baselines do, not the observation
=============================  =================================================================

A DQN policy plays its own task: a cell of another task is refused (name one of its task with
``--task``). A policy whose first action does not fit the task's action space is refused with the
space it should fit.
"""

from __future__ import annotations

import importlib
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Optional

import numpy as np

SB3_ALGOS = ("ppo", "sac", "dqn", "a2c", "td3")


class BenchmarkError(ValueError):
    """A policy, suite or option the benchmark cannot use; the message says what to do."""


@dataclass
class Actor:
    """A policy opened on one task: its environment, ``act(obs)`` and ``reset()``."""

    env: Any
    act: Callable[[np.ndarray], Any]
    reset: Callable[[], None]


@dataclass(frozen=True)
class PolicySpec:
    """What ``--policy`` (with ``--algo`` and ``--options``) names; cheap to send to a worker."""

    spec: str
    algo: Optional[str] = None
    options: dict = field(default_factory=dict)

    @property
    def kind(self) -> str:
        """"dqn", "sb3", "controller" or "callable"."""
        if self.spec.startswith("pretrained:") or Path(self.spec).is_dir():
            return "dqn"
        if self.spec.startswith("controller:"):
            return "controller"
        if self.spec.endswith(".zip"):
            return "sb3"
        return "callable"

    def check(self) -> None:
        """Refuse a spec that names nothing usable, before any episode runs (BenchmarkError)."""
        s = self.spec
        if self.kind == "dqn":
            if self.algo:
                raise BenchmarkError(f"--algo names a Stable-Baselines3 algorithm; {s} is a DQN run or pretrained model")
            if s.startswith("pretrained:"):
                from agents.pretrained import available

                name = s.split(":", 1)[1]
                if name not in available():
                    raise BenchmarkError(f"no pretrained model {name!r}; the models: {', '.join(available())}")
            return
        if self.kind == "sb3":
            if not Path(s).is_file():
                raise BenchmarkError(f"{s} does not exist: give the .zip a Stable-Baselines3 model was saved to")
            if self.algo not in SB3_ALGOS:
                raise BenchmarkError(f"{s} is a Stable-Baselines3 model: name its algorithm with --algo "
                                     f"({', '.join(SB3_ALGOS)})")
            return
        if self.algo:
            raise BenchmarkError(f"--algo applies to a Stable-Baselines3 .zip, not to {s}")
        if self.kind == "controller":
            self._controller()
            return
        if ":" not in s or not all(s.split(":", 1)):
            raise BenchmarkError(f"{s!r} is not a policy: give pretrained:NAME, a run directory, a Stable-Baselines3 "
                                 ".zip with --algo, controller:NAME or module:function")
        self._callable()

    def _callable(self) -> tuple[Callable, Optional[Callable]]:
        module_name, name = self.spec.split(":", 1)
        if "" not in sys.path and "." not in sys.path:
            sys.path.insert(0, "")  # the current folder, as ``python -m`` has it
        try:
            module = importlib.import_module(module_name)
        except ImportError as err:
            raise BenchmarkError(f"cannot import {module_name!r} for --policy {self.spec} ({err}); run from the "
                                 "folder that holds it") from err
        fn = getattr(module, name, None)
        if not callable(fn):
            raise BenchmarkError(f"{module_name} has no function {name!r} (--policy {self.spec})")
        reset = getattr(fn, "reset", None) or getattr(module, "reset", None)
        return fn, reset if callable(reset) else None

    def _controller(self):
        from dynnav_tasks.baselines.registry import make_controller

        try:
            return make_controller(self.spec.split(":", 1)[1])
        except ValueError as err:
            raise BenchmarkError(f"--policy {self.spec}: {err}") from err

    def open(self, task: str, options: dict) -> Actor:
        """The policy acting on ``task`` made with ``options`` (BenchmarkError if it cannot)."""
        if self.kind == "dqn":
            return self._open_dqn(task, options)
        if self.kind == "controller":
            return self._open_controller(task, options)
        import dynnav_tasks

        env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task, obs_mode="state", **{**options, **self.options}))
        if self.kind == "sb3":
            return self._open_sb3(env, task)
        fn, reset = self._callable()
        return Actor(env, fn, reset or (lambda: None))

    def _open_dqn(self, task: str, options: dict) -> Actor:
        from agents.training.policy_loading import load_policy

        policy = load_policy(self.spec, **{**self.options, **options})
        if policy.config.task != task:
            policy.env.close()
            raise BenchmarkError(f"{self.spec} plays {policy.config.task}, not {task}: benchmark it with "
                                 f"--task {policy.config.task} (or a suite of that task)")

        def act(obs):
            return int(np.argmax(policy.q_values(obs)))

        return Actor(policy.env, act, policy.reset)

    def _open_controller(self, task: str, options: dict) -> Actor:
        import dynnav_tasks
        from dynnav_tasks.baselines.episodes import control_mode_of

        controller = self._controller()
        made = {**options, **self.options}
        mode = control_mode_of(controller)
        if made.get("control_mode", mode) != mode:
            raise BenchmarkError(f"{self.spec} commands the {mode} drive; drop control_mode={made['control_mode']} "
                                 "from the options")
        env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make(task, obs_mode="state", **{**made, "control_mode": mode}))
        base = env.unwrapped
        return Actor(env, lambda obs: controller.act(base), lambda: controller.start(base))

    def _open_sb3(self, env, task: str) -> Actor:
        try:
            import stable_baselines3 as sb3
        except ImportError as err:
            raise BenchmarkError("a .zip policy needs Stable-Baselines3: pip install -e '.[bench]'") from err
        model = getattr(sb3, self.algo.upper()).load(self.spec, device="cpu")
        if model.observation_space.shape != env.observation_space.shape:
            env.close()
            raise BenchmarkError(f"{self.spec} reads observations of shape {model.observation_space.shape}; {task} "
                                 f"gives {env.observation_space.shape} (give the task options it was trained with)")

        def act(obs):
            return model.predict(obs, deterministic=True)[0]

        return Actor(env, act, lambda: None)


def check_action(spec: str, task: str, space, action) -> Any:
    """``action`` as the task takes it, or BenchmarkError saying which space it should fit."""
    value = np.asarray(action)
    if hasattr(space, "n"):  # Discrete
        if value.size != 1 or not np.issubdtype(value.dtype, np.integer) and not float(value).is_integer() \
                or not 0 <= int(value) < space.n:
            raise BenchmarkError(f"{spec}'s action {action!r} does not fit {task}'s action space {space}: give an "
                                 f"integer from 0 to {space.n - 1} (or make the task with control_mode=diff_drive_vel)")
        return int(value)
    value = value.astype(space.dtype, copy=False).reshape(space.shape) if value.size == int(np.prod(space.shape)) \
        else value
    if not space.contains(value):
        raise BenchmarkError(f"{spec}'s action {action!r} does not fit {task}'s action space {space}")
    return value
