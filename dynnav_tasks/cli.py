"""What the command-line tools that drive whole episodes share: task selection and seeds."""

from __future__ import annotations

from typing import Callable, Optional, Sequence


def run_over_tasks(task: Optional[str], allowed: Sequence[str], what: str, episodes: int, first_seed: int,
                   run: Callable[[str, range], object]) -> None:
    """Call ``run(task_id, seeds)`` for ``task`` (or every id in ``allowed`` when None) and print
    each result's ``summary()``; bad input exits with a message that names it."""
    from .errors import check_choice

    try:
        tasks = [check_choice(task, allowed, what)] if task else list(allowed)
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    if episodes < 1:
        raise SystemExit(f"error: --episodes must be >= 1, got {episodes}")
    seeds = range(first_seed, first_seed + episodes)
    for task_id in tasks:
        print(run(task_id, seeds).summary())
