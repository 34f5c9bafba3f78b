"""The run table: every finished run as one row, the data RESULTS.md and its figures are made from.

    python -m agents.study.table add RUN_DIR [RUN_DIR ...] [--experiment NAME] [--table results] [--keep]
    python -m agents.study.table show [--table results]

A table is a folder holding two gzip CSV files (UTF-8, a header line, rows sorted by their key,
written with gzip mtime 0 so that the same rows give the same bytes):

``runs.csv.gz``, one row per run and test, keyed by (experiment, config_hash, seed, tested_on):

==================== ==========================================================================
experiment           the experiment's name (a sweep: the config file's stem)
config_hash          12 hex digits of the resolved config, without name, seed and where it ran
                     (agents/study/run_record.py says which fields)
seed                 the training seed
tested_on            the task options the test changed, 'key=value,...' (e.g. split=ood); empty:
                     the run's own task (every row of the study)
task                 the environment id
commit               the code's git commit (empty if unknown)
run                  the run directory's folder name (<task>__<name>__<seed>__<time>)
test_episodes        test episodes (epsilon as configured, 0 in the study)
success_rate         share of test episodes that reached the target
collision_rate       share that ended in a collision
timeout_rate         share that ran out of steps
avg_steps_success    mean steps of the successful test episodes (empty if none)
spl                  success weighted by path length, mean over test episodes
avg_return           mean undiscounted return of the test episodes
converge_episode     first training episode whose 100-episode success rate reaches 90% of the
                     final one (empty: never, or the run is shorter than 100 episodes)
wall_clock_s         training (sum of episode times over restarts) plus test phase, seconds
train_s, eval_s      the two parts of wall_clock_s
episodes_planned     training episodes the config asks for
episodes_done        training episodes in metrics.csv
curve_block          training episodes per block of the curves below
curve_return         per block: mean return of the training episodes, space-separated
curve_loss           per block: mean Q-loss (nan before learning starts)
curve_success        per block: share of training episodes that reached the target
human_collision_rate in a task with pedestrians (else empty), the test's social metrics
min_human_distance   (``dynnav_tasks.crowd.metrics.aggregate``): the share of episodes ended by
personal_space_...   a human's contact, the mean minimum distance to a human (m), personal-space
discomfort_frequency compliance and discomfort frequency (over all steps), time to goal (s,
time_to_goal         successes), path irregularity (rad/m) and jerk (m/s^3)
path_irregularity
jerk
==================== ==========================================================================

A table written before the social columns existed reads with them empty (its header is the
first columns of today's); the next write adds them.

``episodes.csv.gz``, one row per test episode, keyed by the run's key and ``episode``: the
episode's index in the test phase, ``episode_seed`` (a reset of the task with it draws the same
world, which is what agents.analysis.outcomes groups by), ``outcome`` (success, collision,
timeout), ``steps``, ``episode_return``, ``spl`` and the episode's world: ``world_seed``
(procedural tasks), ``arena_side`` (the arena's longer side, m) and ``moving_obstacles`` (their
number); these three are empty in the rows made before they were recorded. No trajectories.

Adding a run replaces the row (and test episodes) of a run with the same key, or of the same
experiment, run folder name and test (a run continued with a longer config): a test of a run
is never listed twice. Writers on one table take a lock on its folder, so sweeps sharing it merge.
"""

from __future__ import annotations

import argparse
import csv
import fcntl
import gzip
import io
import os
import sys
from contextlib import contextmanager
from pathlib import Path

from agents.files import atomic_write_bytes
from agents.study.run_record import added_commits, head_commit, read_run

RUNS = "runs.csv.gz"
EPISODES = "episodes.csv.gz"
KEY = ("experiment", "config_hash", "seed", "tested_on")
RUN_COLUMNS = {
    "experiment": str, "config_hash": str, "seed": int, "tested_on": str, "task": str, "commit": str, "run": str,
    "test_episodes": int,
    "success_rate": float, "collision_rate": float, "timeout_rate": float, "avg_steps_success": float,
    "spl": float, "avg_return": float, "converge_episode": int, "wall_clock_s": float, "train_s": float,
    "eval_s": float, "episodes_planned": int, "episodes_done": int, "curve_block": int, "curve_return": str,
    "curve_loss": str, "curve_success": str,
    "human_collision_rate": float, "min_human_distance": float, "personal_space_compliance": float,
    "discomfort_frequency": float, "time_to_goal": float, "path_irregularity": float, "jerk": float}
"""column -> type of runs.csv.gz, in file order (an empty cell is None)"""
EPISODE_COLUMNS = {"experiment": str, "config_hash": str, "seed": int, "tested_on": str, "episode": int,
                   "episode_seed": int, "outcome": str, "steps": int, "episode_return": float, "spl": float,
                   "world_seed": int, "arena_side": float, "moving_obstacles": int}
"""column -> type of episodes.csv.gz, in file order"""
DEFAULT_TABLE = "results"


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(round(value, 6))
    return str(value)


def _parse(value: str, kind):
    if value == "" and kind is not str:
        return None
    return kind(value)


def encode(rows: list[dict], columns: dict) -> bytes:
    """Rows as deterministic gzip CSV bytes (sorted by their key; gzip mtime 0)."""
    order = [c for c in columns if c in KEY] + (["episode"] if "episode" in columns else [])
    rows = sorted(rows, key=lambda r: tuple(r[c] for c in order))
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(columns)
    for r in rows:
        writer.writerow([_cell(r.get(c)) for c in columns])
    return gzip.compress(text.getvalue().encode(), compresslevel=9, mtime=0)


def decode(data: bytes, columns: dict, source: str) -> list[dict]:
    """Rows of gzip CSV bytes, typed by ``columns``; ValueError naming ``source`` if they are not such a table."""
    try:
        lines = gzip.decompress(data).decode().splitlines()
        reader = csv.reader(lines)
        header = next(reader, None)
        if not header or header != list(columns)[:len(header)] or not set(KEY) <= set(header):
            raise ValueError(f"columns {header} are not {list(columns)}")
        missing = dict.fromkeys(list(columns)[len(header):])  # columns added since it was written
        return [dict({c: _parse(v, columns[c]) for c, v in zip(header, row, strict=True)}, **missing)
                for row in reader]
    except (OSError, EOFError, UnicodeDecodeError, ValueError) as err:
        raise ValueError(f"{source} is not a run table of agents.study.table ({err})") from err


def read_table(table: str | Path = DEFAULT_TABLE, episodes: bool = False) -> list[dict]:
    """The rows of a table folder's runs.csv.gz (``episodes``: of its episodes.csv.gz); [] if absent."""
    name, columns = (EPISODES, EPISODE_COLUMNS) if episodes else (RUNS, RUN_COLUMNS)
    path = Path(table) / name
    if Path(table).is_file():
        raise ValueError(f"{table} is a file; give the folder holding {RUNS} and {EPISODES}")
    return decode(path.read_bytes(), columns, str(path)) if path.is_file() else []


@contextmanager
def _locked(folder: Path):
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)  # released when the descriptor closes
        yield
    finally:
        os.close(fd)


def _key(row: dict) -> tuple:
    return tuple(row[c] for c in KEY)


def add_rows(table: str | Path, runs: list[dict], episodes: list[dict], replace: bool = True) -> dict:
    """Merge run rows (and their test episodes) into a table folder, replacing the rows of the same
    runs (same key, or same experiment and run folder name; ``replace=False``: keeping those);
    return counts of added, replaced and kept runs and the table's size."""
    table = Path(table)
    if table.is_file():
        raise ValueError(f"{table} is a file; give the folder holding {RUNS} and {EPISODES}")
    bad = [r for r in runs if set(r) != set(RUN_COLUMNS)]
    if bad:
        raise ValueError(f"a run row must have exactly the columns {list(RUN_COLUMNS)}")
    table.mkdir(parents=True, exist_ok=True)
    new = {_key(r): r for r in runs}
    with _locked(table):
        old_runs = read_table(table)
        old_episodes = read_table(table, episodes=True)
        same = {(r["experiment"], r["run"], r["tested_on"]): k for k, r in new.items()}
        # old key -> the new key of the same run and test
        present = {_key(r): _key(r) if _key(r) in new else same[(r["experiment"], r["run"], r["tested_on"])]
                   for r in old_runs if _key(r) in new or (r["experiment"], r["run"], r["tested_on"]) in same}
        if not replace:
            new = {k: r for k, r in new.items() if k not in present.values()}
            episodes = [e for e in episodes if _key(e) in new]
            present = {}
        kept_runs = [r for r in old_runs if _key(r) not in present] + list(new.values())
        kept_episodes = [e for e in old_episodes if _key(e) not in present] + episodes
        replaced = len(set(present.values()))
        # the runs file last: it lists a run only once its test episodes are there
        atomic_write_bytes(table / EPISODES, encode(kept_episodes, EPISODE_COLUMNS))
        atomic_write_bytes(table / RUNS, encode(kept_runs, RUN_COLUMNS))
    return dict(added=len(new) - replaced, replaced=replaced, kept=len(runs) - len(new), runs=len(kept_runs))


def add_runs(table: str | Path, run_dirs: list[str | Path], experiment: str | None = None,
             replace: bool = True) -> dict:
    """Read finished run directories (all are checked before anything is written) and add them to
    the table (``replace=False``: a run already there keeps its row); their code commit is the one
    that added each folder to git, else the current HEAD."""
    run_dirs = [Path(d) for d in run_dirs]
    if not run_dirs:
        raise ValueError("no run directories given")
    commits = added_commits(run_dirs)
    head = head_commit() if len(commits) < len(run_dirs) else None
    runs, episodes = [], []
    for d in run_dirs:
        rows, tests = read_run(d, experiment, commits.get(d.resolve()) or head)
        runs += rows
        episodes += tests
    keys = [_key(r) for r in runs]
    if len(set(keys)) < len(keys):
        twice = sorted({k for k in keys if keys.count(k) > 1})
        raise ValueError(f"two of the given run directories are the same run {twice[0]} (experiment, config "
                         "hash, seed, test); give one of them")
    return add_rows(table, runs, episodes, replace)


def main(argv: list[str] | None = None) -> None:
    """``add``: put run directories into a table; ``show``: list its experiments."""
    parser = argparse.ArgumentParser(prog="python -m agents.study.table", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    add = sub.add_parser("add", help="add finished run directories (config.yaml, metrics.csv, eval.json)")
    add.add_argument("run_dirs", nargs="+", metavar="RUN_DIR")
    add.add_argument("--experiment", default=None,
                     help="their experiment name (default: the sweep's, from sweep_run.json, else the config's name)")
    add.add_argument("--table", default=DEFAULT_TABLE, help=f"table folder (default {DEFAULT_TABLE})")
    add.add_argument("--keep", action="store_true",
                     help="keep the rows the table has for these runs (add only their tests it lacks)")
    show = sub.add_parser("show", help="per experiment: runs and mean test success")
    show.add_argument("--table", default=DEFAULT_TABLE, help=f"table folder (default {DEFAULT_TABLE})")
    args = parser.parse_args(argv)
    try:
        if args.command == "add":
            counts = add_runs(args.table, args.run_dirs, args.experiment, replace=not args.keep)
            kept = f", {counts['kept']} kept as they were" if counts["kept"] else ""
            print(f"{args.table}: {counts['added']} run(s) added, {counts['replaced']} replaced{kept}, "
                  f"{counts['runs']} in the table")
            return
        rows = read_table(args.table)
    except (ValueError, OSError) as err:
        raise SystemExit(f"error: {err}")
    if not rows:
        raise SystemExit(f"error: no runs in {Path(args.table) / RUNS}")
    groups: dict[str, list[dict]] = {}
    for r in rows:
        groups.setdefault(r["experiment"] + (f" (tested on {r['tested_on']})" if r["tested_on"] else ""), []).append(r)
    for name in sorted(groups):
        rates = [r["success_rate"] for r in groups[name]]
        print(f"{name}: {len(rates)} run(s), test success {sum(rates) / len(rates):.1%}")


if __name__ == "__main__":
    main(sys.argv[1:])
