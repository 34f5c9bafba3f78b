"""The training configuration: one dataclass, parsed by tyro, loadable from YAML.

    python -m agents.dqn --config configs/moving_target_5_2.yaml --seed 3

``--config`` loads a YAML file of field values; flags given on the command line override it.
An unknown key or a value of the wrong type in the YAML file is an error naming the field.
"""

from __future__ import annotations

import dataclasses
import difflib
import sys
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, Optional

import tyro
import yaml


@dataclass
class Config:
    """Train a DQN / Double DQN agent, or test a trained one (``--eval``)."""

    config: Optional[str] = None
    """YAML file of field values to start from (with --resume: the run's config.yaml); flags on the command line override it"""

    # --- task
    task: str = "DynNav-MovingTarget-v1"
    """gymnasium task id: a dynnav task (dynnav_tasks.TASK_IDS) or any env with Discrete actions and a Box state"""
    reward_mode: Optional[str] = None
    """dynnav reward function (sparse, distance, distance_orientation, distance_orientation_always, potential); None: the task's default"""
    reward_params: dict[str, float] = field(default_factory=dict)
    """dynnav overrides of dynnav_tasks.rewards.RewardParams, e.g. potential_gamma 0.95"""

    normalize_obs: bool = True
    """scale every bounded state component to [-1, 1] using the observation space's bounds"""

    task_kwargs: dict[str, float] = field(default_factory=dict)
    """dynnav task options, e.g. forward_step 0.15 turn_step 0.3927 turn_forward_step 0.05"""

    # --- run
    name: str = "dqn"
    """experiment name, part of the run directory runs/<task>__<name>__<seed>__<time>"""
    seed: int = 1
    """seeds the network, exploration, replay sampling and every training episode"""
    runs_dir: str = "runs"
    """directory the run directories are created in"""
    episodes: int = 2000
    """training episodes"""
    checkpoint_every: int = 100
    """write a checkpoint (and the learning-curve pictures) every this many episodes"""
    progress: bool = True
    """show a progress bar"""

    # --- algorithm
    algorithm: Literal["dqn", "ddqn"] = "dqn"
    """dqn: target max_a Q_target(s', a) (Alg. 1); ddqn: Q_target(s', argmax_a Q(s', a)) (Appendix A)"""
    gamma: float = 0.97
    """discount factor"""
    hidden_sizes: tuple[int, ...] = (128, 128)
    """widths of the Q-network's ReLU hidden layers"""
    batch_size: int = 128
    """minibatch size"""
    buffer_size: int = 100_000
    """replay memory capacity (transitions)"""
    learning_starts: int = 1000
    """environment steps collected before the first update"""
    train_frequency: int = 1
    """one update every this many environment steps"""
    loss: Literal["mse", "huber"] = "mse"
    """TD loss: mean squared error (the thesis) or Huber (smooth L1, delta 1)"""
    max_grad_norm: float = 0.0
    """clip the gradient's global norm to this; 0: no clipping"""
    target_update: Literal["hard", "soft"] = "hard"
    """hard: copy the network every target_update_interval steps; soft: theta- <- tau theta + (1 - tau) theta- every step"""
    target_update_interval: int = 500
    """environment steps between hard target copies (C in Alg. 1)"""
    tau: float = 0.005
    """soft target update rate"""

    # --- schedules (per episode)
    learning_rate: float = 0.003
    """Adam learning rate (at the first episode)"""
    learning_rate_end: float = 0.0003
    """learning rate reached after lr_decay_episodes (ignored by the constant schedule)"""
    lr_schedule: Literal["constant", "linear", "exponential"] = "constant"
    """how the learning rate moves from learning_rate to learning_rate_end"""
    lr_decay_episodes: int = 2000
    """episodes over which the learning rate decays"""
    random_episodes: int = 0
    """first episodes played at epsilon 1 (fully random), before the decay starts"""
    epsilon_start: float = 0.8
    """epsilon when the decay starts"""
    epsilon_end: float = 0.05
    """epsilon after the decay"""
    epsilon_decay_episodes: int = 1000
    """episodes over which epsilon decays (after random_episodes)"""
    epsilon_schedule: Literal["linear", "exponential"] = "linear"
    """how epsilon moves from epsilon_start to epsilon_end"""

    # --- camera state representation (thesis Sec. 4.3, 5.2.3, Alg. 2; dynnav tasks)
    camera_frames: int = 0
    """0: the Q-network reads the task's state vector; 1: the auto-encoded RGB camera frame;
    N >= 2: the auto-encoded stack of the last N gray frames"""
    camera_state: tuple[str, ...] = ()
    """with a camera: parts of the state vector fed beside the latent (Table 5.4), e.g. lasers robot_xy
    obstacles (every obstacle's position); see the task's state_layout()"""
    ae_latent: int = 0
    """auto-encoder latent size; 0: 10 for one frame, 15 for stacks (Table 5.3)"""
    ae_conv_channels: tuple[int, ...] = ()
    """filters of the two convolutions; empty: 32 64 for one frame, 64 128 for stacks"""
    ae_dense: int = 64
    """width of the auto-encoder's dense layer"""
    ae_learning_rate: float = 0.001
    """Adam learning rate of the auto-encoder"""
    ae_first_update: int = 400
    """episode of the first auto-encoder update; before it actions are random and the Q-network does not train"""
    ae_update_every: int = 400
    """episodes between auto-encoder updates"""
    ae_updates: int = 0
    """number of auto-encoder updates; 0: 3 for one frame, 4 for stacks"""
    ae_iterations: int = 0
    """iterations per update; 0: 20 for one frame, 40 for stacks"""
    ae_batches: int = 0
    """batches per iteration; 0: 50 for one frame, 25 for stacks"""
    ae_batch_size: int = 256
    """frames per auto-encoder batch"""
    ae_rare_colour_power: float = 0.0
    """beyond the study: weight each pixel's reconstruction error by (frequency of its colour in the
    observation memory)^-p, normalised to a mean weight of 1; 0: every pixel the same (Eq. 4.10).
    After one update (20 x 50 x 256 frames) on 5.5b's frames, 0.5 reconstructs about 40% of the red
    target's pixels, 0 none"""
    ae_pictures_every: int = 100
    """save observation / reconstruction pairs every this many episodes once the auto-encoder is trained"""

    # --- test phase
    eval: bool = False
    """test a checkpoint (--checkpoint) instead of training"""
    checkpoint: Optional[str] = None
    """checkpoint file (or run directory) to test with --eval"""
    resume: Optional[str] = None
    """run directory of a stopped run to continue from its last checkpoint"""
    eval_after_training: bool = True
    """run the test phase when training ends"""
    eval_episodes: int = 100
    """test episodes (greedy unless eval_epsilon > 0)"""
    eval_seed: int = 1_000_000
    """test episode i is reset with seed eval_seed + i (training episodes use other seeds)"""
    eval_epsilon: float = 0.0
    """probability of a random action in a test step (0: greedy, as the study tests; a small value
    such as 0.05 shows whether a greedy policy is caught in a loop that random actions break)"""
    eval_out: Optional[str] = None
    """folder for eval.json, eval.md and the pictures of --eval (default: beside the checkpoint)"""
    eval_picture: bool = True
    """draw the test trajectories on the task's top-down picture (dynnav tasks)"""

    # --- Rerun recordings (dynnav tasks)
    rerun: Optional[str] = None
    """write a Rerun recording (.rrd) here: every rerun_every-th training episode step by step with
    its Q-values, the training curves, and (with --eval) every test episode"""
    rerun_every: int = 100
    """record every this many training episodes (the first included)"""

    def validate(self) -> "Config":
        """Raise ValueError naming the first field with an impossible value."""
        positive = ["episodes", "checkpoint_every", "batch_size", "buffer_size", "train_frequency",
                    "target_update_interval", "eval_episodes", "lr_decay_episodes", "rerun_every",
                    "ae_dense", "ae_update_every", "ae_batch_size", "ae_pictures_every"]
        for name in positive:
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
        for name in ("learning_starts", "random_episodes", "epsilon_decay_episodes", "camera_frames", "ae_latent",
                     "ae_first_update", "ae_updates", "ae_iterations", "ae_batches"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} must not be negative, got {getattr(self, name)}")
        checks = {
            "gamma": 0.0 <= self.gamma <= 1.0,
            "tau": 0.0 < self.tau <= 1.0,
            "learning_rate": self.learning_rate > 0,
            "learning_rate_end": self.learning_rate_end > 0,
            "epsilon_start": 0.0 <= self.epsilon_start <= 1.0,
            "epsilon_end": 0.0 <= self.epsilon_end <= 1.0,
            "eval_epsilon": 0.0 <= self.eval_epsilon <= 1.0,
            "max_grad_norm": self.max_grad_norm >= 0,
            "hidden_sizes": len(self.hidden_sizes) > 0 and all(h > 0 for h in self.hidden_sizes),
            "ae_learning_rate": self.ae_learning_rate > 0,
            "ae_rare_colour_power": 0.0 <= self.ae_rare_colour_power <= 2.0,
            "ae_conv_channels": len(self.ae_conv_channels) in (0, 2) and all(c > 0 for c in self.ae_conv_channels),
        }
        for name, ok in checks.items():
            if not ok:
                raise ValueError(f"{name} has an impossible value: {getattr(self, name)!r}")
        if self.camera_state and not self.camera_frames:
            raise ValueError("camera_state selects state parts to feed beside the camera's latent: set camera_frames "
                             "too (without a camera the whole state vector is used)")
        if self.eval and not self.checkpoint:
            raise ValueError("--eval needs --checkpoint <checkpoint file or run directory>")
        return self

    def to_yaml_dict(self) -> dict:
        """Field values to write as the run's resolved config (the mode flags left out)."""
        skip = {"config", "eval", "checkpoint", "resume", "rerun"}
        out = {}
        for f in dataclasses.fields(self):
            if f.name not in skip:
                value = getattr(self, f.name)
                out[f.name] = list(value) if isinstance(value, tuple) else value
        return out


FIELDS = {f.name: f for f in dataclasses.fields(Config)}


def _type_ok(value, hint) -> bool:
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if hint is typing.Any:
        return True
    if origin in (typing.Union, types.UnionType):
        return any(_type_ok(value, a) for a in args)
    if hint is type(None):
        return value is None
    if origin is Literal:
        return value in args
    if hint is bool:
        return isinstance(value, bool)
    if hint is int:
        return isinstance(value, int) and not isinstance(value, bool)
    if hint is float:
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    if hint is str:
        return isinstance(value, str)
    if origin is tuple:
        item = args[0] if args else typing.Any
        return isinstance(value, (list, tuple)) and all(_type_ok(v, item) for v in value)
    if origin is dict:
        k, v = args
        return isinstance(value, dict) and all(_type_ok(a, k) and _type_ok(b, v) for a, b in value.items())
    return isinstance(value, hint)


def _describe(hint) -> str:
    if isinstance(hint, type):
        return hint.__name__
    return str(hint).replace("typing.", "").replace("NoneType", "None")


def config_from_dict(values: dict, source: str = "config") -> Config:
    """A Config from field values; unknown keys and wrong types are errors naming the field."""
    if not isinstance(values, dict):
        raise ValueError(f"{source}: expected a mapping of field names to values, got {type(values).__name__}")
    hints = typing.get_type_hints(Config)
    kwargs = {}
    for key, value in values.items():
        if key not in FIELDS:
            close = difflib.get_close_matches(str(key), FIELDS, n=3, cutoff=0.6)
            hint = f" Did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
            raise ValueError(f"{source}: unknown field {key!r}.{hint}")
        if not _type_ok(value, hints[key]):
            raise ValueError(
                f"{source}: field {key!r} expects {_describe(hints[key])}, got {value!r} ({type(value).__name__})"
            )
        if isinstance(value, int) and not isinstance(value, bool) and hints[key] is float:
            value = float(value)
        kwargs[key] = tuple(value) if typing.get_origin(hints[key]) is tuple else value
    return Config(**kwargs)


def load_yaml(path: str | Path) -> Config:
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"config file {str(path)!r} does not exist")
    try:
        values = yaml.safe_load(path.read_text()) or {}
    except yaml.YAMLError as err:
        raise ValueError(f"config file {str(path)!r} is not valid YAML: {err}") from err
    return config_from_dict(values, source=str(path))


def save_yaml(config: Config, path: str | Path) -> None:
    from .checkpoint import atomic_write_bytes

    atomic_write_bytes(path, yaml.safe_dump(config.to_yaml_dict(), sort_keys=False).encode())


def _flag_value(argv: list[str], flag: str) -> Optional[str]:
    """The value given to ``flag`` (``--flag v`` or ``--flag=v``), or None."""
    for i, arg in enumerate(argv):
        if arg == flag and i + 1 < len(argv):
            return argv[i + 1]
        if arg.startswith(flag + "="):
            return arg.split("=", 1)[1]
    return None


def parse_args(argv: Optional[list[str]] = None) -> Config:
    """Command line -> Config: ``--config`` YAML first (or a resumed run's config), then flags."""
    argv = list(sys.argv[1:] if argv is None else argv)
    default = Config()
    base = _flag_value(argv, "--config")
    resume = _flag_value(argv, "--resume")
    if resume and not base:
        base = str(Path(resume) / "config.yaml")
    if base:
        default = load_yaml(base)
    config = tyro.cli(Config, args=argv, default=default, description=Config.__doc__)
    return config.validate()

