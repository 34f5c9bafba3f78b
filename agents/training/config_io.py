"""Reading, checking and writing ``Config``: YAML files, the command line, validation.

A YAML file groups fields as the dataclasses do (``dqn: {learning_rate: 0.001}``); a field at
the top level that belongs to a group (the older flat layout, e.g. ``learning_rate: 0.001``) is
moved into its group. An unknown key, a value of the wrong type or a file that is not YAML is
an error naming the file and the field.
"""

from __future__ import annotations

import dataclasses
import difflib
import sys
import types
import typing
from pathlib import Path
from typing import Literal, Optional

import tyro
import yaml

from agents.training.config import GROUPS, MODE_FIELDS, Config

TOP_FIELDS = {f.name for f in dataclasses.fields(Config)} - set(GROUPS)
GROUP_OF = {f.name: group for group, cls in GROUPS.items() for f in dataclasses.fields(cls)}
"""group of every grouped field, e.g. learning_rate -> schedule"""
EVAL_FLAGS = {"eval", "checkpoint", "eval_episodes", "eval_seed", "eval_epsilon", "eval_out", "eval_picture",
              "progress", "device", "rerun"}
"""settings --eval takes from the command line; everything else comes from the checkpoint"""


def get(config: Config, name: str):
    """A field's value by its name (grouped or top level)."""
    group = GROUP_OF.get(name)
    return getattr(getattr(config, group), name) if group else getattr(config, name)


def replace(config: Config, **values) -> Config:
    """A copy of ``config`` with fields changed by name, wherever their group: replace(c, seed=2, progress=False)."""
    top = {k: v for k, v in values.items() if k not in GROUP_OF}
    unknown = set(top) - TOP_FIELDS
    if unknown:
        raise ValueError(f"unknown config fields: {', '.join(sorted(unknown))}")
    for group in GROUPS:
        changes = {k: v for k, v in values.items() if GROUP_OF.get(k) == group}
        if changes:
            top[group] = dataclasses.replace(getattr(config, group), **changes)
    return dataclasses.replace(config, **top)


def make(**values) -> Config:
    """A Config from field values by name, e.g. make(task="CartPole-v1", learning_rate=0.001)."""
    return replace(Config(), **values)


# ---------------------------------------------------------------------------------------- types
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


def _fill(cls, values: dict, source: str, where: str = ""):
    hints = typing.get_type_hints(cls)
    names = {f.name for f in dataclasses.fields(cls)}
    kwargs = {}
    for key, value in values.items():
        if key not in names:
            if key in GROUP_OF:
                hint = f" It belongs in the {GROUP_OF[key]!r} group."
            else:
                close = difflib.get_close_matches(str(key), names | set(GROUP_OF), n=3, cutoff=0.6)
                hint = f" Did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
            raise ValueError(f"{source}: unknown field {where + str(key)!r}.{hint}")
        if not _type_ok(value, hints[key]):
            raise ValueError(f"{source}: field {key!r} expects {_describe(hints[key])}, got {value!r} "
                             f"({type(value).__name__})")
        if isinstance(value, int) and not isinstance(value, bool) and hints[key] is float:
            value = float(value)
        kwargs[key] = tuple(value) if typing.get_origin(hints[key]) is tuple else value
    return cls(**kwargs)


def config_from_dict(values: dict, source: str = "config") -> Config:
    """A Config from a (grouped or flat) mapping of field values; errors name the field."""
    if not isinstance(values, dict):
        raise ValueError(f"{source}: expected a mapping of field names to values, got {type(values).__name__}")
    top, grouped = {}, {group: {} for group in GROUPS}
    for key, value in values.items():
        if key in GROUPS:
            if not isinstance(value, dict):
                raise ValueError(f"{source}: {key!r} holds the {key} settings as a mapping, got {value!r}")
            grouped[key].update(value)
        elif key in GROUP_OF:  # the flat layout
            grouped[GROUP_OF[key]][key] = value
        else:
            top[key] = value
    config = _fill(Config, top, source)
    parts = {group: _fill(GROUPS[group], grouped[group], source, f"{group}.") for group in GROUPS}
    return dataclasses.replace(config, **parts)


def to_yaml_dict(config: Config) -> dict:
    """The grouped field values a run writes as its config.yaml (the mode fields left out)."""
    def plain(value):
        return list(value) if isinstance(value, tuple) else value

    out = {k: plain(getattr(config, k)) for k in TOP_FIELDS if k not in MODE_FIELDS}
    out = {f.name: out[f.name] for f in dataclasses.fields(Config) if f.name in out}  # in declaration order
    for group in GROUPS:
        out[group] = {k: plain(v) for k, v in dataclasses.asdict(getattr(config, group)).items()}
    out["run"].pop("rerun")
    return out


def load_yaml(path: str | Path) -> Config:
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"config file {str(path)!r} does not exist")
    try:
        values = yaml.safe_load(path.read_text(encoding="utf-8")) or {}
    except UnicodeDecodeError as err:
        raise ValueError(f"config file {str(path)!r} is not a text (UTF-8) YAML file: {err}") from err
    except yaml.YAMLError as err:
        raise ValueError(f"config file {str(path)!r} is not valid YAML: {err}") from err
    return config_from_dict(values, source=str(path))


def save_yaml(config: Config, path: str | Path) -> None:
    from agents.files import atomic_write_bytes

    atomic_write_bytes(path, yaml.safe_dump(to_yaml_dict(config), sort_keys=False).encode())


# ---------------------------------------------------------------------------------------- validation
POSITIVE = ["episodes", "checkpoint_every", "batch_size", "buffer_size", "train_frequency", "target_update_interval",
            "eval_episodes", "lr_decay_episodes", "rerun_every", "ae_dense", "ae_update_every", "ae_batch_size",
            "ae_pictures_every", "state_frames"]
NOT_NEGATIVE = ["learning_starts", "random_episodes", "epsilon_decay_episodes", "camera_frames", "ae_latent",
                "ae_first_update", "ae_updates", "ae_iterations", "ae_batches", "pixel_shift"]


def validate(c: Config) -> None:
    """Raise ValueError naming the first field with an impossible value."""
    for name in POSITIVE:
        if get(c, name) < 1:
            raise ValueError(f"{name} must be at least 1, got {get(c, name)}")
    for name in NOT_NEGATIVE:
        if get(c, name) < 0:
            raise ValueError(f"{name} must not be negative, got {get(c, name)}")
    d, s, cam = c.dqn, c.schedule, c.camera
    checks = {
        "gamma": 0.0 <= d.gamma <= 1.0,
        "tau": 0.0 < d.tau <= 1.0,
        "learning_rate": s.learning_rate > 0,
        "learning_rate_end": s.learning_rate_end > 0,
        "epsilon_start": 0.0 <= s.epsilon_start <= 1.0,
        "epsilon_end": 0.0 <= s.epsilon_end <= 1.0,
        "eval_epsilon": 0.0 <= c.test.eval_epsilon <= 1.0,
        "max_grad_norm": d.max_grad_norm >= 0,
        "hidden_sizes": len(d.hidden_sizes) > 0 and all(h > 0 for h in d.hidden_sizes),
        "ae_learning_rate": cam.ae_learning_rate > 0,
        "ae_rare_colour_power": 0.0 <= cam.ae_rare_colour_power <= 2.0,
        "ae_conv_channels": len(cam.ae_conv_channels) in (0, 2) and all(v > 0 for v in cam.ae_conv_channels),
    }
    for name, ok in checks.items():
        if not ok:
            raise ValueError(f"{name} has an impossible value: {get(c, name)!r}")
    if d.batch_size > d.buffer_size:
        raise ValueError(f"batch_size ({d.batch_size}) is larger than buffer_size ({d.buffer_size}): the replay "
                         f"memory could never fill a minibatch and no update would run; lower --batch-size or raise "
                         f"--buffer-size")
    if cam.camera_state and not cam.camera_frames:
        raise ValueError("camera_state selects state parts to feed beside the camera: set camera_frames too "
                         "(without a camera the whole state vector is used)")
    if c.env.state_frames > 1 and cam.camera_frames:
        raise ValueError("state_frames stacks state vectors for runs without a camera; with camera_frames, "
                         "camera_frames N >= 2 already stacks frames")
    if cam.camera_input == "pixels" and not cam.camera_frames:
        raise ValueError("camera_input pixels reads camera frames: set camera_frames (1: RGB, N >= 2: N gray frames)")
    check_device(c.run.device)
    if c.eval and not c.checkpoint:
        raise ValueError("--eval needs --checkpoint <checkpoint or run directory>")


def check_device(device: str) -> None:
    """ValueError unless ``device`` is cpu, or a GPU torch can use."""
    import torch

    try:
        dev = torch.device(device)
    except RuntimeError as err:
        raise ValueError(f"device {device!r} is not a torch device (use cpu, cuda or cuda:N): {err}") from err
    if dev.type == "cuda":
        if not torch.cuda.is_available():
            raise ValueError(f"device {device!r} was asked for, but torch finds no GPU here "
                             f"(torch.cuda.is_available() is False); use --device cpu")
        if dev.index is not None and dev.index >= torch.cuda.device_count():
            raise ValueError(f"device {device!r}: torch sees {torch.cuda.device_count()} GPU(s)")
    elif dev.type != "cpu":
        raise ValueError(f"device {device!r}: use cpu, cuda or cuda:N")


# ---------------------------------------------------------------------------------------- command line
_DICT_FIELDS = ("reward_params", "task_kwargs")  # EnvConfig's key-value options


def _flag_value(argv: list[str], flag: str) -> Optional[str]:
    """The value given to ``flag`` (``--flag v`` or ``--flag=v``), or None."""
    for i, arg in enumerate(argv):
        if arg == flag and i + 1 < len(argv):
            return argv[i + 1]
        if arg.startswith(flag + "="):
            return arg.split("=", 1)[1]
    return None


def flags_given(argv: list[str]) -> set[str]:
    """Field names set on the command line (``--learning-rate 0.1``, ``--no-progress``, ``--eval-out=x``)."""
    names = set()
    for arg in argv:
        if arg.startswith("--"):
            name = arg[2:].split("=", 1)[0].replace("-", "_")
            if name not in TOP_FIELDS and name not in GROUP_OF and name.startswith("no_"):
                name = name[3:]
            names.add(name)
    return names


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
    # tyro turns a non-empty dict default into fixed per-key flags, which would drop --reward-params and
    # --task-kwargs whenever the YAML sets them: parse them against empty dicts, then lay the flags' keys
    # over the YAML's (``--reward-params collision_reward -100`` keeps the YAML's distance_gamma)
    from_yaml = {name: getattr(default.env, name) for name in _DICT_FIELDS}
    empty = dataclasses.replace(default.env, **{name: {} for name in _DICT_FIELDS})
    config = tyro.cli(tyro.conf.OmitArgPrefixes[Config], args=argv, default=dataclasses.replace(default, env=empty),
                      description=Config.__doc__)
    merged = {name: {**from_yaml[name], **getattr(config.env, name)} for name in _DICT_FIELDS}
    config = dataclasses.replace(config, env=dataclasses.replace(config.env, **merged))
    if config.eval:
        ignored = sorted(flags_given(argv) - EVAL_FLAGS - {"help"})
        if ignored:
            flags = ", ".join("--" + n.replace("_", "-") for n in ignored)
            raise ValueError(f"--eval tests a checkpoint on the task and settings it was trained with; {flags} "
                             f"cannot change them (test flags: --eval-episodes, --eval-seed, --eval-epsilon, "
                             f"--eval-out, --eval-picture, --rerun, --device)")
    return config.validate()
