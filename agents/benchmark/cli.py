"""The command line of ``dynnav-benchmark`` (``python -m agents.benchmark``); see ``agents.benchmark``."""

from __future__ import annotations

import re
import shlex
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import tyro

from agents.benchmark.card import make_card, markdown, write_card
from agents.benchmark.policies import BenchmarkError, PolicySpec
from agents.benchmark.scoring import run_cells, score
from agents.benchmark.suites import EPISODES, FIRST_SEED, Cell, suite_cells


@dataclass
class Args:
    policy: str
    """pretrained:NAME, a run directory, a Stable-Baselines3 FILE.zip (with --algo), controller:NAME or module:function"""
    suite: Optional[str] = None
    """study, procedural or crowd (agents/benchmark/suites.py); or give --task"""
    task: Optional[str] = None
    """one task to score instead of a suite"""
    options: Optional[str] = None
    """task options, key=value,...: the --task's own, and for a .zip or a callable the options its
    observation needs in every cell (e.g. way=true, control_mode=diff_drive_vel)"""
    algo: Optional[str] = None
    """the Stable-Baselines3 algorithm of a .zip: ppo, sac, dqn, a2c or td3"""
    episodes: Optional[int] = None
    """episodes per cell instead of the suite's (the card says so; a published card keeps the suite's)"""
    workers: int = 2
    """processes that play the episodes (0: this one)"""
    name: Optional[str] = None
    """the navigator's name on the card and the leaderboard, e.g. "PPO, progress reward" (default: --policy)"""
    out: Optional[Path] = None
    """the score card's JSON (its Markdown goes beside it); default runs/benchmark/<suite>__<policy>.json"""
    progress: bool = True
    """a progress bar"""


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9.-]+", "-", text).strip("-")


def plan(args: Args) -> tuple[PolicySpec, str, list[Cell]]:
    """The policy, the suite's name and its cells, all checked (BenchmarkError) before any episode."""
    from dynnav_tasks import ALL_TASK_IDS
    from dynnav_tasks.errors import check_choice
    from dynnav_tasks.task_options import parse_task_options

    if (args.suite is None) == (args.task is None):
        raise BenchmarkError("give either --suite (study, procedural, crowd) or --task, not both or neither")
    try:
        options = parse_task_options(args.options) if args.options else {}
    except ValueError as err:
        raise BenchmarkError(f"--options: {err}") from err
    if args.episodes is not None and args.episodes < 1:
        raise BenchmarkError(f"--episodes must be 1 or more, got {args.episodes}")
    if args.task is not None:
        try:
            check_choice(args.task, ALL_TASK_IDS, "task id")
        except ValueError as err:
            raise BenchmarkError(str(err)) from err
        cells, suite, extra = [Cell(args.task, options, EPISODES, FIRST_SEED)], args.task, {}
    else:
        try:
            cells = suite_cells(args.suite)
        except ValueError as err:
            raise BenchmarkError(str(err)) from err
        suite, extra = args.suite, options
    if args.episodes is not None:
        cells = [Cell(c.task, c.options, args.episodes, c.first_seed) for c in cells]
    policy = PolicySpec(args.policy, args.algo, extra)
    policy.check()
    return policy, suite, cells


def main(argv: Optional[list[str]] = None) -> None:
    """Score the policy and write its card."""
    argv = sys.argv[1:] if argv is None else argv
    args = tyro.cli(Args, args=argv)
    try:
        policy, suite, cells = plan(args)
        out = args.out or Path("runs") / "benchmark" / f"{_slug(suite)}__{_slug(args.policy)}.json"
        records = run_cells(policy, cells, args.workers, args.progress)
        scores = [score(r) for r in records]
    except BenchmarkError as err:
        raise SystemExit(f"error: {err}")
    card = make_card(args.policy, args.algo, suite, cells, scores, shlex.join(["dynnav-benchmark", *argv]),
                     args.name)
    json_path, md_path = write_card(card, out)
    print(markdown(card))
    print(f"score card: {json_path}, {md_path}")


if __name__ == "__main__":
    main()
