"""Playing a suite's episodes on both cores and scoring them.

Every episode resets its task with its own seed and the policy acts on what the task returns, so
an episode's result depends on the policy, the task and the seed alone: the episodes are spread
over ``workers`` processes (each opens the policy once per task) and put back in seed order, and
two runs of a deterministic policy give the same card.

Per cell: the rate of each outcome with its 95% Wilson interval, SPL (the straight way from the
start to the target less the reach radius, as the test phase takes it) and, among pedestrians,
the social metrics (``dynnav_tasks.crowd.metrics.aggregate``).
"""

from __future__ import annotations

import numpy as np

from agents.benchmark.policies import BenchmarkError, PolicySpec, check_action
from agents.benchmark.suites import Cell
from agents.training.stats import spl, straight_shortest, wilson_interval
from dynnav_tasks.crowd.metrics import aggregate as aggregate_social
from dynnav_tasks.crowd.metrics import episode_social
from dynnav_tasks.outcomes import outcome_of

CHUNK = 10
"""episodes a worker plays per job (the progress bar moves by this many)"""

_OPEN: dict = {}  # in a worker: (policy spec, cell index) -> Actor


def play(policy: PolicySpec, cell: Cell, seed: int, actor) -> dict:
    """One episode of ``cell`` from ``seed``: its outcome, steps, SPL and social metrics."""
    env = actor.env
    obs, _ = env.reset(seed=seed)
    actor.reset()
    base = env.unwrapped
    start, target = np.array(base.snapshot.robot_xy), np.array(base.snapshot.target_xy)
    done, steps = False, 0
    while not done:
        action = check_action(policy.spec, cell.task, env.action_space, actor.act(obs))
        obs, _, terminated, truncated, info = env.step(action)
        done, steps = bool(terminated or truncated), steps + 1
    outcome = outcome_of(info, bool(terminated))
    shortest = straight_shortest(start, target, float(base.reach_radius))
    record = dict(seed=seed, outcome=outcome, steps=steps,
                  spl=spl(outcome == "success", shortest, float(info["path_length"])))
    social = episode_social(info)
    if social is not None:
        record["social"] = social
    return record


def _job(args) -> tuple[int, list[dict]]:
    policy, index, cell, seeds = args
    key = (repr(policy), index)
    if key not in _OPEN:
        _OPEN[key] = policy.open(cell.task, cell.options)
    return index, [play(policy, cell, s, _OPEN[key]) for s in seeds]


def _worker_init() -> None:
    import torch

    torch.set_num_threads(1)


def run_cells(policy: PolicySpec, cells: list[Cell], workers: int = 2, progress: bool = True) -> list[list[dict]]:
    """Every cell's episode records, in seed order; ``workers`` 0 plays them in this process."""
    jobs = [(policy, i, cell, list(cell.seeds[k:k + CHUNK]))
            for i, cell in enumerate(cells) for k in range(0, cell.episodes, CHUNK)]
    results: list[list[dict]] = [[] for _ in cells]
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=sum(c.episodes for c in cells), desc="benchmark", unit="episode")
    try:
        if workers <= 0:
            done = map(_job, jobs)
            _run(done, results, bar)
        else:
            import multiprocessing as mp

            with mp.get_context("spawn").Pool(workers, initializer=_worker_init) as pool:
                _run(pool.imap_unordered(_job, jobs), results, bar)
    finally:
        if bar is not None:
            bar.close()
        for actor in _OPEN.values():
            actor.env.close()
        _OPEN.clear()
    return [sorted(r, key=lambda e: e["seed"]) for r in results]


def _run(done, results, bar) -> None:
    for index, records in done:
        results[index] += records
        if bar is not None:
            bar.update(len(records))


def score(records: list[dict]) -> dict:
    """A cell's score (module docstring) from its episode records."""
    n = len(records)
    if n == 0:
        raise BenchmarkError("no episodes to score")
    out = dict(episodes=n)
    for outcome in ("success", "collision", "timeout"):
        k = sum(r["outcome"] == outcome for r in records)
        lo, hi = wilson_interval(k, n)
        out[outcome] = round(k / n, 4)
        out[f"{outcome}_ci95"] = [round(lo, 4), round(hi, 4)]
    out["spl"] = round(float(np.mean([r["spl"] for r in records])), 4)
    steps = [r["steps"] for r in records if r["outcome"] == "success"]
    out["steps_per_success"] = round(float(np.mean(steps)), 1) if steps else None
    if "social" in records[0]:
        out["social"] = aggregate_social([dict(r["social"], steps=r["steps"]) for r in records])
    return out

