"""Reading and writing ``Config``: YAML files with their bases, and the command line.

A YAML file groups fields as the dataclasses do (``dqn: {learning_rate: 0.001}``); a field at
the top level that belongs to a group (the older flat layout, e.g. ``learning_rate: 0.001``) is
moved into its group. An unknown key, a value of the wrong type or a file that is not YAML is
an error naming the file and the field.

A file may start from another: ``base: <path>``, relative to the file's own folder, and then
writes only what differs. The base is read first (it may name a base of its own), then the
file's values are laid over it:

* a top-level field (``task``, ``episodes`` ...) replaces the base's;
* a group (``env:``, ``dqn:``, ``schedule:``, ``camera:``, ``demos:``, ``test:``, ``run:``) is merged key by
  key: ``schedule: {learning_rate: 0.001}`` changes the learning rate and keeps the base's
  other schedule settings;
* inside ``env:``, ``reward_params`` and ``task_kwargs`` are merged key by key too:
  ``reward_params: {collision_reward: -100.0}`` over a base's ``{distance_gamma: 0.1}`` gives
  both. A list (``hidden_sizes``, ``camera_state`` ...) is replaced whole. A key cannot be
  removed, only set again (to the default, say);
* ``name`` and ``description`` are never taken from a base: they say what this file is. A
  file's run name is its own ``name:``, else its file name without ``.yaml``.

A base that does not exist, that is not a mapping, or a chain of bases that comes back to a
file already in it is an error naming the files. Runs write the fully resolved config (every
field, no ``base:``) as their ``config.yaml``.
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

from agents.training.config import GROUP_OF, GROUPS, MODE_FIELDS, Config, get  # noqa: F401 (get: re-exported)

TOP_FIELDS = {f.name for f in dataclasses.fields(Config)} - set(GROUPS)
EVAL_FLAGS = {"eval", "checkpoint", "eval_episodes", "eval_seed", "eval_epsilon", "eval_out", "eval_picture",
              "eval_task_kwargs", "also_test_on", "progress", "device", "rerun"}
"""settings --eval takes from the command line; everything else comes from the checkpoint"""


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


def _grouped(values: dict, source: str) -> dict:
    """A file's mapping in the grouped layout: top-level fields, and one mapping per group given
    (a flat-layout field moved into its group); a group that is not a mapping is an error."""
    if not isinstance(values, dict):
        raise ValueError(f"{source}: expected a mapping of field names to values, got {type(values).__name__}")
    out = {}
    for key, value in values.items():
        if key in GROUPS:
            if not isinstance(value, dict):
                raise ValueError(f"{source}: {key!r} holds the {key} settings as a mapping, got {value!r}")
            out.setdefault(key, {}).update(value)
        elif key in GROUP_OF:  # the flat layout
            out.setdefault(GROUP_OF[key], {})[key] = value
        else:
            out[key] = value
    return out


def config_from_dict(values: dict, source: str = "config") -> Config:
    """A Config from a (grouped or flat) mapping of field values; errors name the field."""
    values = _grouped(values, source)
    if "base" in values:
        raise ValueError(f"{source}: 'base' names a file to start from; it works in a YAML file read by path "
                         f"(--config, load_yaml), not in a mapping of values")
    top = {k: v for k, v in values.items() if k not in GROUPS}
    config = _fill(Config, top, source)
    parts = {group: _fill(GROUPS[group], values.get(group, {}), source, f"{group}.") for group in GROUPS}
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


# ---------------------------------------------------------------------------------------- YAML files and bases
NOT_INHERITED = ("name", "description")
"""fields a file never takes from its base"""
MERGED_KEYS = ("reward_params", "task_kwargs")
"""env mappings merged key by key over the base's"""


def _read(path: Path, via: tuple[Path, ...]) -> dict:
    """One file's own mapping (its ``base:`` still in it); errors name the file and the file whose base it is."""
    what = f"config file {str(path)!r}" + (f" (the base of {str(via[-1])!r})" if via else "")
    if not path.is_file():
        raise ValueError(f"{what} does not exist" + ("; base: is a path relative to the folder of the file "
                                                      "that names it" if via else ""))
    try:
        values = yaml.safe_load(path.read_text(encoding="utf-8"))
    except UnicodeDecodeError as err:
        raise ValueError(f"{what} is not a text (UTF-8) YAML file: {err}") from err
    except yaml.YAMLError as err:
        raise ValueError(f"{what} is not valid YAML: {err}") from err
    values = {} if values is None else values
    if not isinstance(values, dict):
        raise ValueError(f"{what}: expected a mapping of field names to values, got {type(values).__name__}")
    return values


def merge(base: dict, over: dict) -> dict:
    """``over``'s values laid over ``base``'s (both in the grouped layout), as the module's docstring says."""
    out = {k: dict(v) if k in GROUPS else v for k, v in base.items()}
    for key, value in over.items():
        if key not in GROUPS:
            out[key] = value
            continue
        group = out.setdefault(key, {})
        for field_name, field_value in value.items():
            old = group.get(field_name)
            if key == "env" and field_name in MERGED_KEYS and isinstance(old, dict) and isinstance(field_value, dict):
                field_value = {**old, **field_value}
            group[field_name] = field_value
    return out


def resolve_yaml(path: str | Path, via: tuple[Path, ...] = ()) -> dict:
    """The field values ``path`` stands for, its chain of bases merged (grouped layout, no ``base``);
    ``name`` and ``description`` are the file's own, if it sets them."""
    path = Path(path)
    if path.resolve() in [p.resolve() for p in via]:
        chain = " -> ".join(str(p) for p in (*via, path))
        raise ValueError(f"config files form a cycle of bases: {chain}; a chain of bases must end in a file "
                         f"without base:")
    own = _read(path, via)
    base = own.pop("base", None)
    config_from_dict(own, source=str(path))  # unknown fields and wrong types, named with this file
    own = _grouped(own, str(path))
    if base is None:
        return own
    if not isinstance(base, str) or not base.strip():
        raise ValueError(f"config file {str(path)!r}: base must be the path of a YAML file, relative to this "
                         f"file's folder, got {base!r}")
    inherited = resolve_yaml(path.parent / base, (*via, path))
    for key in NOT_INHERITED:
        inherited.pop(key, None)
    return merge(inherited, own)


def load_yaml(path: str | Path) -> Config:
    """A Config from a YAML file and its chain of bases; ``name`` defaults to the file's stem."""
    path = Path(path)
    values = resolve_yaml(path)
    values.setdefault("name", path.stem)
    return config_from_dict(values, source=str(path))


def save_yaml(config: Config, path: str | Path) -> None:
    """Write ``config`` fully resolved (every field, grouped, no base) to ``path``, atomically."""
    from agents.files import atomic_write_bytes

    atomic_write_bytes(path, yaml.safe_dump(to_yaml_dict(config), sort_keys=False).encode())


# ---------------------------------------------------------------------------------------- command line
_DICT_FIELDS = ("reward_params", "task_kwargs", "eval_task_kwargs")  # key-value options (env and test groups)


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
    from_yaml = {name: get(default, name) for name in _DICT_FIELDS}
    config = tyro.cli(tyro.conf.OmitArgPrefixes[Config], args=argv,
                      default=replace(default, **{name: {} for name in _DICT_FIELDS}), description=Config.__doc__)
    config = replace(config, **{name: {**from_yaml[name], **get(config, name)} for name in _DICT_FIELDS})
    if config.eval:
        ignored = sorted(flags_given(argv) - EVAL_FLAGS - {"help"})
        if ignored:
            flags = ", ".join("--" + n.replace("_", "-") for n in ignored)
            raise ValueError(f"--eval tests a checkpoint on the task and settings it was trained with; {flags} "
                             f"cannot change them (test flags: --eval-episodes, --eval-seed, --eval-epsilon, "
                             f"--eval-task-kwargs, --also-test-on, --eval-out, --eval-picture, --rerun, --device)")
    return config.validate()
