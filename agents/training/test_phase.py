"""The test phase: a trained Q-network drives greedily (epsilon 0) through a fixed set of
episodes; success, collision and timeout rates, steps and SPL are reported (``agents.training.stats``).

    python -m agents.dqn --eval --checkpoint runs/<run> [--eval-episodes 100]
    python -m agents.dqn --eval --checkpoint pretrained:5.3    # a pretrained navigator (results: runs/pretrained-5.3/)

Test episode i is reset with seed ``eval_seed + i`` (default 1_000_000 + i), so every
checkpoint is tested on the same episodes, none of which it was trained on (training episodes
use hashed seeds). Results go next to the checkpoint: eval.json (summary and every episode),
eval.md (the table printed here) and, for dynnav tasks, trajectories.png (``agents.training.test_report``).

A test may change task options (``eval_task_kwargs``, e.g. ``split: test`` for held-out
procedural worlds), and ``also_test_on`` adds more tests, each in ``tests/<key=value,...>/`` of
the run directory:

    python -m agents.dqn --eval --checkpoint runs/<run> --eval-task-kwargs split ood
    # -> runs/<run>/tests/split=ood/eval.json
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from agents.core.policy import Policy
from agents.files import atomic_write_bytes
from agents.training.envs import is_dynnav
from agents.training.policy_loading import load_policy, results_dir
from agents.training.rollout import greedy, open_recorder, rollout
from agents.training.run_lock import RunDirLock
from agents.training.stats import spl, straight_shortest, summarize
from agents.training.test_report import draw_trajectories, write_results
from agents.training.threads import limit_threads
from dynnav_tasks.crowd.metrics import episode_social
from dynnav_tasks.task_options import options_name, parse_task_options


def run_episodes(policy: Policy, episodes: int, seed: int, recorder=None, latents: list | None = None,
                 epsilon: float = 0.0) -> list[dict]:
    """Greedy rollouts of ``policy`` on seeds seed, seed + 1, ...; one record per episode.

    With ``epsilon`` > 0 a step's action is random with that probability, drawn from a generator
    seeded with the episode's seed, so such a test replays exactly too. ``latents``, for camera
    latent runs, receives (latent, target index, reward) per step."""
    env = policy.env
    dynnav = is_dynnav(policy.config.task)
    reach = float(env.unwrapped.reach_radius) if dynnav else 0.0
    n_actions = int(env.action_space.n)
    records = []
    for i in range(episodes):
        path, start = [], {}

        def on_reset(obs):
            policy.reset()  # a recurrent Q-network starts the episode from a zero state
            if dynnav:  # the task's snapshot, whatever the observation holds
                snapshot = env.unwrapped.snapshot
                start["robot"], start["target"] = snapshot.robot_xy, np.array(snapshot.target_xy)
                start["world"] = world_facts(env.unwrapped)
                path.append(start["robot"].tolist())

        def on_step(action, reward, obs, terminated, truncated, info):
            if dynnav:
                path.append(list(env.unwrapped.snapshot.pose[:2]))
            latent = getattr(policy.features, "last_latent", None)
            if latents is not None and latent is not None:
                latents.append((latent, env.unwrapped.target_index, reward))

        act = greedy(policy.q_values, n_actions, epsilon, np.random.default_rng(seed + i))
        episode = rollout(env, seed + i, act, on_reset, on_step, recorder, index=i, views=policy.views)
        record = dict(seed=seed + i, outcome=episode.outcome, steps=episode.length, ret=round(episode.ret, 4))
        if dynnav:
            shortest = straight_shortest(start["robot"], start["target"], reach)
            driven = float(episode.info["path_length"])
            record.update(start["world"])
            record.update(path_length=round(driven, 4), shortest_path=round(shortest, 4),
                          spl=spl(episode.outcome == "success", shortest, driven),
                          target_start=start["target"].tolist(), trajectory=path)
            social = episode_social(episode.info)
            if social is not None:  # a task with pedestrians: the episode's social metrics
                record.update({k: v for k, v in social.items() if k not in record})
        records.append(record)
    return records


def world_facts(task) -> dict:
    """What a test episode's world was: its seed (procedural tasks; None for a fixed world), the
    arena's longer side (m) and its number of moving obstacles."""
    world = task.world
    return dict(world_seed=getattr(task, "world_seed", None), arena_side=round(float(max(world.arena.size)), 3),
                moving_obstacles=int(world.moving_obstacle_count))


TESTS_DIR = "tests"
"""folder of a run directory holding its tests with other task options, one sub-folder each"""


def test_dir(run_dir: Path, options: dict) -> Path:
    """Where a test with task ``options`` of the run in ``run_dir`` is written: tests/<key=value,...>/."""
    return Path(run_dir) / TESTS_DIR / options_name(options)


def evaluate_as_configured(config, checkpoint_path, out_dir=None, only_missing: bool = False, **kwargs) -> dict:
    """``evaluate`` with the test settings of ``config`` (eval_episodes, eval_seed, eval_picture,
    eval_epsilon, eval_task_kwargs), then one more test per ``also_test_on`` entry, each in
    tests/<entry>/ of the run directory (of ``out_dir`` if given); returns the first test's summary.
    ``out_dir``: the first test's folder (default: the run directory; with --eval and task options,
    tests/<options>/ in it); ``only_missing``: skip the tests whose eval.json exists. ``kwargs`` go to ``evaluate`` (verbose, rerun, device)."""
    t = config.test
    extra = [parse_task_options(entry) for entry in t.also_test_on]  # errors before any test runs
    run_dir = results_dir(checkpoint_path)
    home = Path(out_dir) if out_dir is not None else run_dir  # the extra tests go to its tests/
    if out_dir is None and config.eval and t.eval_task_kwargs:
        out_dir = test_dir(run_dir, t.eval_task_kwargs)
    settings = dict(episodes=t.eval_episodes, seed=t.eval_seed, picture=t.eval_picture, epsilon=t.eval_epsilon)
    first = Path(out_dir) if out_dir is not None else run_dir
    summary = None
    if not (only_missing and (first / "eval.json").is_file()):
        summary = evaluate(checkpoint_path, out_dir=out_dir, task_kwargs=t.eval_task_kwargs, **settings, **kwargs)
    for options in extra:
        where = test_dir(home, options)
        if not (only_missing and (where / "eval.json").is_file()):
            evaluate(checkpoint_path, out_dir=where, task_kwargs=options, **settings, **kwargs)
    return summary


def evaluate(checkpoint_path, episodes: int = 100, seed: int = 1_000_000, picture: bool = True,
             out_dir: str | Path | None = None, verbose: bool = True, rerun: str | Path | None = None,
             epsilon: float = 0.0, device: str | None = None, task_kwargs: dict | None = None) -> dict:
    """Test the checkpoint's Q-network; write eval.json / eval.md (/ trajectories.png); return the summary.

    ``epsilon``: probability of a random action per step (0, greedy, is the test).
    ``rerun``: also write every test episode to this Rerun recording (dynnav tasks).
    ``task_kwargs``: task options laid over the run's own for this test (e.g. split="ood")."""
    limit_threads(1)
    task_kwargs = dict(task_kwargs or {})
    policy = load_policy(checkpoint_path, device=device, **task_kwargs)
    try:
        recorder = open_recorder(rerun, policy.config.task)  # checks the recording path before any work
        out_dir = Path(out_dir) if out_dir is not None else results_dir(checkpoint_path)
        out_dir.mkdir(parents=True, exist_ok=True)
        with RunDirLock(out_dir):  # not while another process writes there (e.g. still trains)
            return run_test_phase(policy, out_dir, episodes, seed, picture, verbose, recorder, epsilon, task_kwargs)
    finally:
        policy.env.close()


def run_test_phase(policy: Policy, out_dir: Path, episodes: int, seed: int, picture: bool, verbose: bool, recorder,
                   epsilon: float, task_kwargs: dict | None = None) -> dict:
    """The test phase of ``policy`` with its results written to ``out_dir``; returns the summary."""
    config, path, trained = policy.config, policy.path, policy.state["episode"]
    latents = [] if hasattr(policy.features, "last_latent") else None
    records = run_episodes(policy, episodes, seed, recorder, latents, epsilon)
    if recorder is not None:
        recorder.close()
    if latents:
        from agents.srl.pictures import plot_latents

        z, targets, rewards = (np.array(v) for v in zip(*latents))
        npz = io.BytesIO()
        np.savez_compressed(npz, latents=z, targets=targets, rewards=rewards)
        atomic_write_bytes(out_dir / "latents.npz", npz.getvalue())
        plot_latents(z, targets, rewards, out_dir, title=config.task)
    summary = summarize(records, epsilon)
    options = dict(task_kwargs or {})
    result = dict(task=config.task, checkpoint=str(path), trained_episodes=trained, eval_seed=seed,
                  task_kwargs=options, tested_on=options_name(options), summary=summary, episodes=records)
    on = f" on {options_name(options)}" if options else ""
    table = write_results(out_dir, result, f"Test of {path} after {trained} training episodes{on}")
    if verbose:
        print(f"\ntest phase: {path} ({trained} training episodes)\n")
        print(table)
    if picture and is_dynnav(config.task):
        draw_trajectories(policy.env, records, out_dir / "trajectories.png")
        if verbose:
            print(f"trajectories: {out_dir / 'trajectories.png'}")
    if verbose:
        print(f"results: {out_dir / 'eval.json'}, {out_dir / 'eval.md'}")
    return summary
