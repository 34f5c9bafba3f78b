"""Task options written as one string, ``key=value,key=value``: how a test in other settings is
named (``split=ood``, ``obstacle_count=4,obstacle_speed_scale=1.5``) on command lines, in config
files, in folder names and in the run table's ``tested_on`` column.

>>> parse_task_options("obstacle_count=4,obstacle_speed_scale=1.5")
{'obstacle_count': 4, 'obstacle_speed_scale': 1.5}
>>> options_name({"split": "ood", "difficulty": "easy"})
'difficulty=easy,split=ood'
"""

from __future__ import annotations

from typing import Union

TaskOption = Union[int, float, bool, str]


def parse_task_options(text: str) -> dict[str, TaskOption]:
    """'key=value,key=value' -> task options, each value an int (4), a float (1.5, 1e-05), a bool
    (true, false) or else a word (ood); ValueError saying what is wrong."""
    options: dict[str, TaskOption] = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        key, value = key.strip(), value.strip()
        if not sep or not key or not value:
            raise ValueError(f"task options {text!r}: write them as key=value, separated by commas "
                             f"(e.g. split=ood or obstacle_count=4,obstacle_speed_scale=1.5)")
        if not all(c.isalnum() or c in "._+-" for c in value):
            raise ValueError(f"task options {text!r}: the value of {key} must be a number, true/false or a word, "
                             f"got {value!r}")
        if key in options:
            raise ValueError(f"task options {text!r} set {key} twice")
        options[key] = _scalar(value)
    return options


def _scalar(value: str) -> TaskOption:
    """An integer, a float, true / false, or else the word itself."""
    for kind in (int, float):
        try:
            return kind(value)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(value.lower(), value)


def options_name(options: dict[str, TaskOption]) -> str:
    """Task options as one string, the keys sorted ('' for none); ``parse_task_options`` reads it back."""
    return ",".join(f"{k}={str(v).lower() if isinstance(v, bool) else repr(v) if isinstance(v, float) else v}"
                    for k, v in sorted(options.items()))
