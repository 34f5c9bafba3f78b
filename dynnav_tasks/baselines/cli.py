"""What the command-line tools that drive whole episodes share: task selection, seeds, and a
JSON file of their success rates (``--out``) that ``agents.study.report`` reads."""

from __future__ import annotations

import json
import os
import tempfile
from typing import Callable, Optional, Sequence


def outcome_rates(outcomes: Sequence[str], first_seed: int) -> dict:
    """{"success", "collision", "timeout"} rates of ``outcomes``, with the episode count and seeds."""
    n = len(outcomes)
    return dict(success=outcomes.count("success") / n, collision=outcomes.count("collision") / n,
                timeout=outcomes.count("timeout") / n, episodes=n, first_seed=first_seed)


def merge_json(path: str, key: str, value: dict) -> None:
    """Set ``path[key] = value`` in a JSON object file (created if missing), written to a
    temporary file and renamed into place, so the file is never left half written."""
    data = {}
    if os.path.exists(path):
        try:
            with open(path) as f:
                data = json.load(f)
        except (OSError, ValueError) as err:
            raise SystemExit(f"error: {path} is not a JSON file this tool wrote ({err}); move it away or choose another --out")
        if not isinstance(data, dict):
            raise SystemExit(f"error: {path} does not hold a JSON object; move it away or choose another --out")
    data[key] = value
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=".json")
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(dict(sorted(data.items())), f, indent=2)
            f.write("\n")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def run_over_tasks(task: Optional[str], allowed: Sequence[str], what: str, episodes: int, first_seed: int,
                   run: Callable[[str, range], object], out: Optional[str] = None) -> None:
    """Call ``run(task_id, seeds)`` for ``task`` (or every id in ``allowed`` when None) and print
    each result's ``summary()``; with ``out``, also merge each task's ``outcome_rates`` into that
    JSON file. Bad input exits with a message that names it, before any episode runs."""
    from dynnav_tasks.errors import check_choice

    try:
        tasks = [check_choice(task, allowed, what)] if task else list(allowed)
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    if episodes < 1:
        raise SystemExit(f"error: --episodes must be >= 1, got {episodes}")
    if out is not None and not os.path.isdir(os.path.dirname(os.path.abspath(out))):
        raise SystemExit(f"error: --out {out}: the folder {os.path.dirname(os.path.abspath(out))} does not exist")
    seeds = range(first_seed, first_seed + episodes)
    for task_id in tasks:
        result = run(task_id, seeds)
        print(result.summary())
        if out is not None:
            merge_json(out, task_id, outcome_rates(result.outcomes, first_seed))
