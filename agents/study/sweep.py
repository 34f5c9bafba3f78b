"""Run experiments x seeds on Ray: each (experiment, seed) is one Ray task on one CPU.

    python -m agents.study.sweep configs/study/5.2.yaml configs/study/5.3.yaml \\
        --seeds 3 --out sweeps/laser
    python -m agents.study.sweep configs/study/5.3-potential-{0.85,0.9,0.95,1.0}.yaml --address auto   # an existing Ray cluster

Without ``--address`` a new Ray instance starts inside this process on this machine
(``--num-cpus``, default all cores), even where ``ray start`` has run; with it (``auto`` or
``host:port``), the sweep joins a running cluster, whose workers must see the sweep folder
at the same path (a shared file system).

Layout: ``<out>/<experiment>/seed<N>/<task>__<experiment>__<N>__<time>/`` is the run directory
agents.dqn writes (config.yaml, metrics.csv, checkpoint/, eval.json, ...); the experiment is
the config file's name without ``.yaml``. Started again on the same folder, the sweep skips runs
whose eval.json exists, continues runs that have a checkpoint from it (``Config.resume``), and
starts the others afresh. A failing run is retried ``--max-retries`` times (each retry continues
from the last checkpoint), then reported with its error in ``<out>/sweep_summary.json``, which
is rewritten atomically after every finished run; sweeps sharing a folder (one per core, say)
merge their runs there. A run's status there: done, resumed (continued from a checkpoint),
skipped (finished before), failed (with its error and traceback), unfinished (queued or
running, or the sweep was stopped).

Each run the sweep finishes is added to a run table (agents/study/table.py) as soon as its test
phase ends: ``--table`` names the table's folder, by default the sweep folder itself
(``<out>/runs.csv.gz`` and ``<out>/episodes.csv.gz``); ``--table results`` adds the runs to this
repository's table, from which ``python -m agents.study.report`` writes RESULTS.md. A run found
finished from an earlier sweep is added only if the table does not list it yet (it keeps the row
it has, with the code commit that made it).
"""

from __future__ import annotations

import argparse
import dataclasses
import fcntl
import json
import os
import shutil
import sys
import time
import traceback
from pathlib import Path

from agents.files import atomic_write_bytes
from agents.study.table import add_runs
from agents.training.checkpoint import exists
from agents.training.config import Config
from agents.training.config_io import load_yaml, replace

SUMMARY = "sweep_summary.json"
RUN_INFO = "sweep_run.json"


@dataclasses.dataclass(frozen=True)
class RunSpec:
    """One (experiment, seed) of a sweep."""

    experiment: str
    config_path: str
    seed: int
    seed_dir: str  # <out>/<experiment>/seed<N>: holds exactly one run directory

    def config(self) -> Config:
        config = load_yaml(self.config_path)
        return replace(config, name=self.experiment, seed=self.seed, runs_dir=self.seed_dir, progress=False,
                       eval_after_training=False, resume=None).validate()


def find_run_dir(seed_dir: str | Path) -> Path | None:
    """The run directory inside a seed folder (None if there is none yet)."""
    seed_dir = Path(seed_dir)
    found = sorted(p for p in seed_dir.glob("*__*__*__*") if p.is_dir()) if seed_dir.is_dir() else []
    with_checkpoint = [p for p in found if exists(p)]
    if len(with_checkpoint) > 1:
        raise RuntimeError(f"{seed_dir} holds {len(with_checkpoint)} run directories with checkpoints; "
                           "expected one (remove the extra ones)")
    if with_checkpoint:
        return with_checkpoint[0]
    return found[-1] if found else None


def run_status(seed_dir: str | Path) -> str:
    """'finished' (eval.json written), 'resumable' (a checkpoint), or 'new'."""
    run_dir = find_run_dir(seed_dir)
    if run_dir is None:
        return "new"
    if (run_dir / "eval.json").is_file():
        return "finished"
    return "resumable" if exists(run_dir) else "new"


def execute(spec: RunSpec) -> dict:
    """Train (or continue) and test one run; return its record for the summary."""
    from agents.training.checkpoint import load
    from agents.dqn import train
    from agents.training.test_phase import evaluate_as_configured
    from agents.training.threads import limit_threads

    limit_threads(1)
    config = spec.config()
    run_dir = find_run_dir(spec.seed_dir)
    if run_dir is not None and (run_dir / "eval.json").is_file():
        evaluate_as_configured(config, run_dir, verbose=False, only_missing=True)  # also_test_on added later
        return _record(spec, run_dir, "skipped")
    if run_dir is not None and not exists(run_dir):
        shutil.rmtree(run_dir)  # stopped before its first checkpoint: nothing to continue from
        run_dir = None
    resumed_at = load(run_dir, memory=False)["episode"] if run_dir is not None else 0
    if run_dir is not None:
        config = replace(config, resume=str(run_dir))
    t0 = time.perf_counter()
    run_dir = train(config)
    t1 = time.perf_counter()
    evaluate_as_configured(config, run_dir, verbose=False)
    t2 = time.perf_counter()
    info = dict(experiment=spec.experiment, config=spec.config_path, seed=spec.seed, resumed_at_episode=resumed_at,
                train_s_last_attempt=round(t1 - t0, 2), eval_s=round(t2 - t1, 2), host=os.uname().nodename)
    atomic_write_bytes(run_dir / RUN_INFO, json.dumps(info, indent=1).encode())
    return _record(spec, run_dir, "resumed" if resumed_at else "done")


def _record(spec: RunSpec, run_dir: Path, status: str) -> dict:
    summary = json.loads((run_dir / "eval.json").read_text())["summary"]
    return dict(experiment=spec.experiment, seed=spec.seed, status=status, run_dir=str(run_dir),
                success_rate=summary["success_rate"], avg_steps_success=summary["avg_steps_success"])


def plan(config_paths: list[str], seeds: list[int], out: Path) -> list[RunSpec]:
    """Every (experiment, seed); errors name a missing or invalid config before anything runs."""
    specs, seen = [], {}
    for path in config_paths:
        load_yaml(path).validate()  # raises ValueError naming the file and field
        experiment = Path(path).stem
        if experiment in seen and seen[experiment] != str(Path(path).resolve()):
            raise ValueError(f"two configs are named {experiment!r}: {seen[experiment]} and {path}")
        seen[experiment] = str(Path(path).resolve())
        for seed in seeds:
            specs.append(RunSpec(experiment, str(Path(path).resolve()), seed,
                                 str((out / experiment / f"seed{seed}").resolve())))
    return list(dict.fromkeys(specs))


def _counts(runs: list[dict]) -> dict:
    return {k: sum(r["status"] == k for r in runs) for k in ("done", "resumed", "skipped", "failed", "unfinished")}


def write_summary(out: Path, records: dict, started: float, args: dict) -> dict:
    """Record this sweep's runs in ``<out>/sweep_summary.json``; return this sweep's own summary.

    Sweeps run side by side on one folder (one per core, say) share the file: under a lock, each
    merges its runs into those already there, the newest record per (experiment, seed) winning,
    so the file lists every run any sweep on the folder has recorded."""
    runs = sorted(records.values(), key=lambda r: (r["experiment"], r["seed"]))
    own = dict(sweep=str(out), arguments=args, elapsed_s=round(time.time() - started, 1), counts=_counts(runs),
               runs=runs)
    with open(out / f"{SUMMARY}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        try:
            earlier = json.loads((out / SUMMARY).read_text())["runs"]
        except (FileNotFoundError, ValueError, KeyError, TypeError):
            earlier = []
        merged = {(r["experiment"], r["seed"]): r for r in earlier if isinstance(r, dict) and "experiment" in r}
        merged.update({(r["experiment"], r["seed"]): r for r in runs})
        every = sorted(merged.values(), key=lambda r: (r["experiment"], r["seed"]))
        atomic_write_bytes(out / SUMMARY, json.dumps(dict(own, counts=_counts(every), runs=every), indent=1).encode())
    return own


def add_to_table(table: Path, spec: RunSpec, record: dict) -> None:
    """Add a finished run of the sweep to the run table (one it skipped: only if not there yet)."""
    if record["status"] in ("done", "resumed", "skipped"):
        add_runs(table, [record["run_dir"]], spec.experiment, replace=record["status"] != "skipped")


def run_sweep(config_paths: list[str], seeds: list[int], out: str | Path, address: str | None = None,
              num_cpus: int | None = None, max_retries: int = 1, verbose: bool = True,
              table: str | Path | None = None) -> dict:
    """Run the sweep to its end; return its summary (its runs are also in ``<out>/sweep_summary.json``)
    and add each finished run to the run table in ``table`` (default: the folder ``out``).

    Ray is started (or joined, ``address``) unless it is already initialised in this process."""
    import ray

    out = Path(out)
    table = Path(table) if table is not None else out
    if table.is_file():
        raise ValueError(f"--table {table} is a file; give the folder that holds (or will hold) runs.csv.gz")
    specs = plan(config_paths, seeds, out)
    out.mkdir(parents=True, exist_ok=True)
    started = time.time()
    args = dict(configs=[str(p) for p in config_paths], seeds=seeds, max_retries=max_retries)
    records = {s: dict(experiment=s.experiment, seed=s.seed, status="unfinished", run_dir=None) for s in specs}
    todo = []
    for s in specs:
        status = run_status(s.seed_dir)
        if status == "finished":
            records[s] = _record(s, find_run_dir(s.seed_dir), "skipped")
            add_to_table(table, s, records[s])
        else:
            todo.append(s)
    if not ray.is_initialized():
        if address:
            ray.init(address=address, log_to_driver=False)
        else:
            # Ray runs its workers at niceness 15, so any other busy process on the machine would
            # starve the runs: they run at the sweep's own priority instead (RAY_worker_niceness, if
            # set, still decides)
            os.environ.setdefault("RAY_worker_niceness", str(os.nice(0)))
            ray.init(address="local", num_cpus=num_cpus or os.cpu_count(), include_dashboard=False,
                     log_to_driver=False)  # "local": a new instance even if `ray start` ran here
    task = ray.remote(num_cpus=1, max_retries=max_retries, retry_exceptions=True)(execute)
    pending = {task.remote(s): s for s in todo}
    say = print if verbose else (lambda *a, **k: None)
    say(f"sweep {out}: {len(specs)} runs, {len(specs) - len(todo)} already finished, {len(todo)} to run")
    write_summary(out, records, started, args)
    while pending:
        ready, _ = ray.wait(list(pending), num_returns=1)
        spec = pending.pop(ready[0])
        try:
            records[spec] = ray.get(ready[0])
        except Exception as err:  # the task's error after its retries, with its traceback
            cause = getattr(err, "cause", None) or err
            records[spec] = dict(experiment=spec.experiment, seed=spec.seed, status="failed",
                                 run_dir=str(find_run_dir(spec.seed_dir) or spec.seed_dir),
                                 error=f"{type(cause).__name__}: {cause}",
                                 traceback="".join(traceback.format_exception(cause))[-4000:])
        r = records[spec]
        add_to_table(table, spec, r)
        done = sum(x["status"] in ("done", "resumed", "skipped") for x in records.values())
        failed = sum(x["status"] == "failed" for x in records.values())
        result = (f"success {r['success_rate']:.0%}" if r["status"] != "failed" else f"FAILED: {r['error']}")
        say(f"[{time.strftime('%H:%M:%S')}] {spec.experiment} seed {spec.seed}: {result} | "
            f"done {done}/{len(specs)}, failed {failed}, running or queued {len(pending)}", flush=True)
        write_summary(out, records, started, args)
    say(f"summary: {out / SUMMARY}")
    return write_summary(out, records, started, args)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m agents.study.sweep", description=__doc__.split("\n\n")[0])
    parser.add_argument("configs", nargs="+", help="experiment YAML files (configs/study/*.yaml)")
    parser.add_argument("--seeds", type=int, default=3, help="seeds 1..N per experiment (default 3)")
    parser.add_argument("--seed-list", type=int, nargs="+", help="these seeds instead of 1..N")
    parser.add_argument("--out", default=None, help="sweep folder (default sweeps/<first config's name>)")
    parser.add_argument("--address", default=None, help="join this Ray cluster (e.g. auto or host:6379)")
    parser.add_argument("--num-cpus", type=int, default=None, help="local Ray's CPUs = parallel runs (default all)")
    parser.add_argument("--max-retries", type=int, default=1, help="retries of a failed run (default 1)")
    parser.add_argument("--table", default=None,
                        help="run table folder each finished run is added to (default: the sweep folder; "
                             "results: this repository's table, which RESULTS.md is made from)")
    args = parser.parse_args(argv)
    if args.seeds < 1:
        raise SystemExit("error: --seeds must be at least 1")
    seeds = args.seed_list or list(range(1, args.seeds + 1))
    out = args.out or str(Path("sweeps") / Path(args.configs[0]).stem)
    try:
        summary = run_sweep(args.configs, seeds, out, address=args.address, num_cpus=args.num_cpus,
                            max_retries=args.max_retries, table=args.table)
    except (ValueError, RuntimeError, OSError) as err:
        raise SystemExit(f"error: {err}")
    if summary["counts"]["failed"]:
        sys.exit(1)


if __name__ == "__main__":
    main(sys.argv[1:])
