"""One finished run directory as a row of the run table (agents/study/table.py) and its test episodes.

A run directory (what ``python -m agents.dqn`` or a sweep writes) holds ``config.yaml`` (the fully
resolved config), ``metrics.csv`` (one line per training episode), ``eval.json`` (the test phase)
and, when a sweep made it, ``sweep_run.json`` (its experiment name and the test phase's time).
``read_run`` turns it into one run row and one row per test episode; the columns are described in
agents/study/table.py. Tests with other task options (``tests/<key=value,...>/eval.json``, see
``agents.training.test_phase``) are more rows of the same run, told apart by ``tested_on``.

* config hash: the first 12 hex digits of the SHA-256 of the resolved config as canonical JSON
  (sorted keys), without the fields that say where and how a run was made rather than what was
  trained: ``name``, ``description``, ``seed``, the ``run`` group (folder, checkpoints, device,
  progress) and the test fields ``eval_after_training``, ``eval_out``, ``eval_task_kwargs`` and
  ``also_test_on`` (a row's ``tested_on`` says which test it is). The seeds of one experiment share it.
  The memory settings (``MEMORY_FIELDS``) count only with ``recurrent`` set, the encoders
  (``FLAT_ENCODERS``) only when not flat and the ``demos`` group only with a teacher: without them
  they change nothing, and runs recorded before they existed keep their hash. A teacher's run
  counts as whether it is given, not by its folder, which differs from seed to seed.
* convergence episode: the first training episode at which the success rate over the last
  WINDOW episodes reaches 90% of its value over the run's last WINDOW episodes (only full
  windows; none if the run ends at 0%).
* training curve: per block of BLOCK training episodes the mean return, Q-loss and success
  (the last block may be shorter; a block without any finite value is ``nan``).
* training time: the last ``wall_time_s`` of metrics.csv; a run with no training episode of its
  own (an ``agents.imitation`` student: its metrics.csv has no row) gives it as ``train_s`` in
  ``sweep_run.json``.
* code commit: the commit that added the run's folder to git if it is tracked, else the current
  HEAD of the checkout this code runs from (none outside a git checkout).
"""

from __future__ import annotations

import csv
import hashlib
import json
import subprocess
from pathlib import Path

import numpy as np
import yaml

from agents.training.plots import moving_average
from dynnav_tasks.crowd.metrics import AGGREGATE_METRICS

WINDOW = 100
"""training episodes per moving window of the convergence episode"""
BLOCK = 50
"""training episodes per block of the down-sampled training curve"""
CURVES = ("return", "loss", "success")
"""metrics.csv columns kept as down-sampled curves"""
NOT_HASHED = {"name": None, "description": None, "seed": None, "run": None,
              "test": ("eval_after_training", "eval_out", "eval_task_kwargs", "also_test_on")}
"""config fields left out of the config hash (None: the whole field or group)"""
MEMORY_FIELDS = ("recurrent", "recurrent_size", "sequence_length", "burn_in")
"""dqn fields of the recurrent Q-network, hashed only when ``recurrent`` is set"""
FLAT_ENCODERS = {"laser_encoder": "flat", "obstacle_encoder": "flat", "lookahead": False}
"""dqn fields of the egocentric encoders and the look-ahead, hashed only when not flat (off)"""
TEACHER_PATHS = ("init_from", "demonstrations")
"""demos fields that name another run: hashed as whether they are set (each seed's teacher has its own
folder); the demos group is hashed only when one is set"""
REQUIRED = ("config.yaml", "metrics.csv", "eval.json")
CODE_ROOT = Path(__file__).resolve().parents[2]


def config_hash(config: dict) -> str:
    """12 hex digits identifying what a resolved config trains (see the module docstring)."""
    kept = {}
    for key, value in config.items():
        dropped = NOT_HASHED.get(key, ())
        if dropped is None:
            continue
        if dropped and isinstance(value, dict):
            value = {k: v for k, v in value.items() if k not in dropped}
        if key == "dqn" and isinstance(value, dict):
            value = {k: v for k, v in value.items() if (value.get("recurrent") or k not in MEMORY_FIELDS)
                     and FLAT_ENCODERS.get(k, object()) != v}
        if key == "demos" and isinstance(value, dict):
            if not any(value.get(k) for k in TEACHER_PATHS):
                continue
            value = {k: (bool(v) if k in TEACHER_PATHS else v) for k, v in value.items()}
        kept[key] = value
    text = json.dumps(kept, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def episodes_to_converge(success, window: int = WINDOW) -> int | None:
    """First episode (1-based) whose moving success rate reaches 90% of the final one."""
    success = np.asarray(success, dtype=float)
    if len(success) < window:
        return None
    rate = moving_average(success, window)[window - 1:]
    final = rate[-1]
    if not final > 0:
        return None
    return int(np.argmax(rate >= 0.9 * final - 1e-12)) + window


def block_means(values, block: int = BLOCK) -> list[float]:
    """Mean of the finite values in each block of ``block`` consecutive entries (nan if none)."""
    values = np.asarray(values, dtype=float)
    out = []
    for start in range(0, len(values), block):
        chunk = values[start:start + block]
        chunk = chunk[np.isfinite(chunk)]
        out.append(float(chunk.mean()) if len(chunk) else float("nan"))
    return out


def format_curve(values: list[float]) -> str:
    """A curve as the table stores it: space-separated values to 4 significant digits."""
    return " ".join("nan" if not np.isfinite(v) else format(v, ".4g") for v in values)


def parse_curve(text: str) -> np.ndarray:
    """The values of a stored curve (empty string: no values)."""
    return np.array([float(v) for v in text.split()], dtype=float)


def _git(args: list[str], cwd: Path) -> str | None:
    try:
        done = subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def head_commit(root: Path = CODE_ROOT) -> str | None:
    """The commit checked out where this code runs (None outside a git checkout)."""
    return _git(["rev-parse", "HEAD"], root) or None


def added_commits(run_dirs: list[Path]) -> dict[Path, str]:
    """run directory -> the newest commit that added a file in it, for those tracked in git
    (``git log --diff-filter=A --format=%H -1 -- <folder>``, one git call per repository)."""
    found: dict[Path, str] = {}
    by_root: dict[Path, list[Path]] = {}
    for d in run_dirs:
        root = _git(["rev-parse", "--show-toplevel"], d)
        if root:
            by_root.setdefault(Path(root).resolve(), []).append(d.resolve())
    for root, dirs in by_root.items():
        rel = {d.relative_to(root).as_posix(): d for d in dirs}
        out = _git(["log", "--diff-filter=A", "--format=%x00%H", "--name-only", "--", *rel], root) or ""
        commit = None
        for line in out.splitlines():
            if line.startswith("\0"):
                commit = line[1:]
            elif line and commit:
                folder = line.rsplit("/", 1)[0]
                while folder and folder not in rel:
                    folder = folder.rsplit("/", 1)[0] if "/" in folder else ""
                if folder:
                    found.setdefault(rel[folder], commit)  # git log lists the newest first
    return found


def check_run_dir(run_dir: Path) -> None:
    """Raise ValueError saying what a folder lacks to be a finished run directory."""
    if not run_dir.is_dir():
        raise ValueError(f"{run_dir}: no such folder; give a run directory (with {', '.join(REQUIRED)})")
    missing = [name for name in REQUIRED if not (run_dir / name).is_file()]
    if missing:
        hint = (" (its test phase has not run: `python -m agents.dqn --eval " + str(run_dir) + "` runs it)"
                if missing == ["eval.json"] else "")
        raise ValueError(f"{run_dir} is not a finished run directory: no {', '.join(missing)}{hint}")


def _read_metrics(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    columns = rows[0].keys() if rows else []
    return {k: np.array([float(r[k]) if r[k] not in ("", None) else np.nan for r in rows]) for k in columns}


def _read_test(path: Path) -> tuple[str, dict, list[dict]]:
    """(tested_on, summary, episode records) of an eval.json."""
    ev = json.loads(path.read_text())
    return str(ev.get("tested_on", "")), ev["summary"], ev["episodes"]


def social_columns(social: dict | None) -> dict:
    """A test's social metrics (its summary's ``social``) as the table's columns (empty without pedestrians)."""
    return {k: None if not social else social.get(k) for k in AGGREGATE_METRICS if k != "path_length"}


def read_run(run_dir: str | Path, experiment: str | None = None, commit: str | None = None) -> tuple[list[dict], list[dict]]:
    """(run rows, test-episode rows) of a finished run directory: one row for its test phase and one
    per test in tests/*/; ``experiment`` defaults to the sweep's name for it (sweep_run.json), else
    the config's ``name``. ValueError if it is not one."""
    run_dir = Path(run_dir)
    check_run_dir(run_dir)
    try:
        config = yaml.safe_load((run_dir / "config.yaml").read_text())
        tests = [_read_test(p) for p in [run_dir / "eval.json", *sorted(run_dir.glob("tests/*/eval.json"))]]
        info_path = run_dir / "sweep_run.json"
        info = json.loads(info_path.read_text()) if info_path.is_file() else {}
        metrics = _read_metrics(run_dir / "metrics.csv")
    except (ValueError, KeyError, TypeError, AttributeError, yaml.YAMLError) as err:
        raise ValueError(f"{run_dir}: cannot read its record ({type(err).__name__}: {err})") from err
    if not isinstance(config, dict) or not config.get("task"):
        raise ValueError(f"{run_dir}/config.yaml is not a run's resolved config (no task)")
    experiment = experiment or info.get("experiment") or config.get("name")
    if not experiment:
        raise ValueError(f"{run_dir}: no experiment name in sweep_run.json or config.yaml; give one (--experiment)")
    missing = [c for c in CURVES + ("wall_time_s",) if c not in metrics and metrics]
    if missing:
        raise ValueError(f"{run_dir}/metrics.csv lacks the column(s) {', '.join(missing)}")
    done = len(metrics.get("episode", []))
    # a run trained without episodes of its own (agents.imitation: labels and fits) says its time in sweep_run.json
    train_s = float(metrics["wall_time_s"][-1]) if done else float(info.get("train_s", 0.0))
    eval_s = float(info.get("eval_s", 0.0))
    training = dict(task=config["task"], commit=commit or "", run=run_dir.resolve().name,
                    converge_episode=episodes_to_converge(metrics["success"]) if done else None,
                    wall_clock_s=round(train_s + eval_s, 1), train_s=round(train_s, 1), eval_s=round(eval_s, 1),
                    episodes_planned=int(config.get("episodes") or 0), episodes_done=done, curve_block=BLOCK)
    for name in CURVES:
        training[f"curve_{name}"] = format_curve(block_means(metrics[name])) if done else ""
    rows, episode_rows, seen = [], [], set()
    for on, summary, episodes in tests:
        if on in seen:  # the test phase's own folder wins over tests/ with the same options
            continue
        seen.add(on)
        key = dict(experiment=experiment, config_hash=config_hash(config), seed=int(config.get("seed") or 0),
                   tested_on=on)
        rows.append(dict(key, **training, test_episodes=int(summary["episodes"]),
                         success_rate=summary["success_rate"], collision_rate=summary["collision_rate"],
                         timeout_rate=summary["timeout_rate"], avg_steps_success=summary["avg_steps_success"],
                         spl=summary.get("spl"), avg_return=summary.get("avg_return"),
                         **social_columns(summary.get("social"))))
        episode_rows += [dict(key, episode=i, episode_seed=e.get("seed"), outcome=e["outcome"], steps=e["steps"],
                              episode_return=e.get("ret"), spl=e.get("spl"), world_seed=e.get("world_seed"),
                              arena_side=e.get("arena_side"), moving_obstacles=e.get("moving_obstacles"))
                         for i, e in enumerate(episodes)]
    return rows, episode_rows
