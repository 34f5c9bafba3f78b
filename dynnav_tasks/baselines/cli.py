"""What the command-line tools that drive whole episodes share: task selection, seeds, and a
JSON file of their success rates (``--out``) that ``agents.study.report`` reads.

``run_over_tasks`` runs the study's fixed worlds (one entry per task id); ``run_over_cells``
runs a procedural task over its difficulties and splits (one entry per controller, difficulty
and split, e.g. ``state_planner/medium/test``, with SPL and the number of worlds played);
``drive_controller`` picks between them for a controller's command line (``ControllerArgs``)."""

from __future__ import annotations

import fcntl
import json
import os
import re
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable, Optional, Sequence


@dataclass
class ControllerArgs:
    """The options of a scripted controller's command line beside its ``task``."""

    difficulty: Optional[str] = None
    """with a procedural task: "easy", "medium" or "hard" (default: each)"""
    split: Optional[str] = None
    """with a procedural task: "train", "test" or "ood" (default: each)"""
    episodes: int = 200
    """episodes per task, difficulty and split (seeds first_seed .. first_seed + episodes - 1)"""
    first_seed: int = 0
    """seed of the first episode"""
    options: Optional[str] = None
    """with a task that is not procedural: its options, key=value,... (e.g. humans=10,model=social_force)"""
    out: Optional[str] = None
    """also merge the rates into this JSON file, e.g. docs/results/procedural_ceilings.json"""


def drive_controller(args, run: Callable, controller: str, fixed_tasks: Sequence[str]) -> None:
    """Drive the episodes ``args`` (a ``ControllerArgs`` with a ``task``) names and print (and with
    ``--out`` record) the rates: a procedural task over its cells, else one of ``fixed_tasks``.
    ``run(task_id, seeds, label, task_kwargs)`` plays the episodes with the controller."""
    from dynnav_tasks import PROCEDURAL_TASK_IDS

    if args.task in PROCEDURAL_TASK_IDS:
        if args.options:
            raise SystemExit("error: --options applies to a task that is not procedural; a procedural one takes "
                             "--difficulty and --split")
        run_over_cells(args.task, args.difficulty, args.split, args.episodes, args.first_seed,
                       lambda d, s, seeds: run(args.task, seeds, f"{args.task} {d} {s}", dict(difficulty=d, split=s)),
                       controller=controller, out=args.out)
        return
    if args.difficulty or args.split:
        raise SystemExit(f"error: --difficulty and --split apply to a procedural task ({', '.join(PROCEDURAL_TASK_IDS)})")
    from dynnav_tasks.task_options import parse_task_options

    try:
        options = parse_task_options(args.options) if args.options else {}
    except ValueError as err:
        raise SystemExit(f"error: --options: {err}")

    def run_task(task: str, seeds):
        try:
            return run(task, seeds, None, options or None)
        except TypeError as err:  # the task refused an option (before any episode ran)
            unknown = re.search(r"unexpected keyword argument '(\w+)'", str(err))
            if unknown is None:
                raise
            raise SystemExit(f"error: --options: {task} has no option {unknown.group(1)!r}; its docstring lists "
                             "the options it takes")

    run_over_tasks(args.task, fixed_tasks, "task id", args.episodes, args.first_seed, run_task, out=args.out,
                   options=options, controller=controller)


def outcome_rates(outcomes: Sequence[str], first_seed: int) -> dict:
    """{"success", "collision", "timeout"} rates of ``outcomes``, with the episode count and seeds."""
    n = len(outcomes)
    return dict(success=outcomes.count("success") / n, collision=outcomes.count("collision") / n,
                timeout=outcomes.count("timeout") / n, episodes=n, first_seed=first_seed)


@contextmanager
def _folder_lock(folder: str):
    """Hold an exclusive lock on ``folder`` (so that two processes merging into one file there
    take turns instead of losing each other's entries)."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def merge_json(path: str, key: str, value: dict) -> None:
    """Set ``path[key] = value`` in a JSON object file (created if missing), written to a
    temporary file and renamed into place, so the file is never left half written; processes
    merging into the same file at once take turns."""
    with _folder_lock(os.path.dirname(os.path.abspath(path))):
        _merge_json(path, key, value)


def _merge_json(path: str, key: str, value: dict) -> None:
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
                   run: Callable[[str, range], object], out: Optional[str] = None, options: Optional[dict] = None,
                   controller: Optional[str] = None) -> None:
    """Call ``run(task_id, seeds)`` for ``task`` (or every id in ``allowed`` when None) and print
    each result's ``summary()``; with ``out``, also merge each task's ``outcome_rates`` (and the
    result's ``numbers()``, if it has them: SPL, steps per success and, among pedestrians, the
    social metrics) into that JSON file, as the entry ``task_id`` (with the task ``options``
    ``run`` uses: ``"task_id [key=value,...]"``; with ``controller``: ``"controller/task_id ..."``).
    Bad input exits with a message that names it, before any episode runs."""
    from dynnav_tasks.task_options import options_name

    from dynnav_tasks.errors import check_choice

    try:
        tasks = [check_choice(task, allowed, what)] if task else list(allowed)
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    _check_run(episodes, out)
    seeds = range(first_seed, first_seed + episodes)
    for task_id in tasks:
        result = run(task_id, seeds)
        print(result.summary())
        if out is not None:
            key = f"{task_id} [{options_name(options)}]" if options else task_id
            numbers = result.numbers() if hasattr(result, "numbers") else {}
            merge_json(out, f"{controller}/{key}" if controller else key,
                       dict(outcome_rates(result.outcomes, first_seed), **numbers))


def run_over_cells(task: str, difficulty: Optional[str], split: Optional[str], episodes: int, first_seed: int,
                   run: Callable[[str, str, range], object], controller: str, out: Optional[str] = None) -> None:
    """Call ``run(difficulty, split, seeds)`` for ``difficulty`` and ``split`` of the procedural
    ``task`` (each None: every one) and print each result's ``summary()``; with ``out``, also
    merge ``"{controller}/{difficulty}/{split}"``: the rates, the task and the result's
    ``numbers()`` (SPL, steps per success, worlds played) into that JSON file. Bad input exits
    with a message that names it, before any episode runs."""
    from dynnav_tasks.errors import check_choice
    from dynnav_tasks.generation import DIFFICULTIES, SPLITS

    try:
        difficulties = [check_choice(difficulty, DIFFICULTIES, "difficulty")] if difficulty else list(DIFFICULTIES)
        splits = [check_choice(split, SPLITS, "split")] if split else list(SPLITS)
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    _check_run(episodes, out)
    seeds = range(first_seed, first_seed + episodes)
    for d in difficulties:
        for s in splits:
            result = run(d, s, seeds)
            print(result.summary())
            if out is not None:
                merge_json(out, f"{controller}/{d}/{s}", dict(task=task, difficulty=d, split=s,
                                                               **outcome_rates(result.outcomes, first_seed),
                                                               **result.numbers()))


def _check_run(episodes: int, out: Optional[str]) -> None:
    if episodes < 1:
        raise SystemExit(f"error: --episodes must be >= 1, got {episodes}")
    if out is not None and not os.path.isdir(os.path.dirname(os.path.abspath(out))):
        raise SystemExit(f"error: --out {out}: the folder {os.path.dirname(os.path.abspath(out))} does not exist")
