"""The test phase: a trained Q-network drives greedily (epsilon 0) through a fixed set of
episodes; success, collision and timeout rates, steps and SPL are reported.

    python -m agents.dqn --eval --checkpoint runs/<run>/checkpoint.pkl [--eval-episodes 100]

Test episode i is reset with seed ``eval_seed + i`` (default 1_000_000 + i), so every
checkpoint is tested on the same episodes, none of which it was trained on (training episodes
use hashed seeds). Results go next to the checkpoint: eval.json (summary and every episode),
eval.md (the table printed here) and, for dynnav tasks, trajectories.png (every test path
drawn on the task's top-down render, as in the thesis's Fig. 6.2).

* success rate: with a 95% Wilson score interval (sound for rates near 0 or 1, unlike the
  normal approximation).
* SPL (success weighted by path length, Anderson et al. 2018): mean over episodes of
  S_i * l_i / max(p_i, l_i), S_i = 1 on success, p_i the path the robot drove
  (``info["path_length"]``) and l_i the shortest path, taken as the straight-line distance from
  the robot's start to the target's position at the start minus the reach radius (0.3 m): the
  robot succeeds as soon as its centre is within that radius. Obstacles and the target's motion
  are ignored, so l_i is a lower bound and SPL of 1 is out of reach in worlds where the straight
  line is blocked.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from . import checkpoint as ckpt
from .config import config_from_dict
from .envs import ObsScaler, is_dynnav, make_env, state_slices
from .qnetwork import MLP
from .threads import limit_threads

OUTCOME_COLORS = {"success": (30, 90, 255), "collision": (230, 30, 30), "timeout": (255, 170, 0)}


def wilson_interval(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95% for z = 1.96)."""
    if n <= 0:
        return (math.nan, math.nan)
    p = successes / n
    denom = 1 + z * z / n
    center = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return (max(0.0, center - half), min(1.0, center + half))


def outcome_of(info: dict, terminated: bool) -> str:
    """success / collision (dynnav), timeout (truncated), or terminated (other envs' endings)."""
    if info.get("success", False):
        return "success"
    if info.get("collision", False):
        return "collision"
    return "terminated" if terminated else "timeout"


def state_of(obs):
    """The state vector of an observation (camera runs observe ``{"rgb" or "gray": ..., "state": ...}``)."""
    return obs["state"] if isinstance(obs, dict) else obs


def run_episodes(net: MLP, env, episodes: int, seed: int, dynnav: bool, scale=None, recorder=None,
                 latents: list | None = None, epsilon: float = 0.0) -> list[dict]:
    """Greedy rollouts of ``net`` on seeds seed, seed + 1, ...; one record per episode.

    With ``epsilon`` > 0 a step's action is random with that probability, drawn from a generator
    seeded with the episode's seed, so such a test replays exactly too.

    ``scale`` maps the env's observation to the network's input (the ObsScaler or CameraFeatures
    used in training); ``recorder`` (a dynnav_tasks.recording.Recorder) logs every step with its
    Q-values; ``latents``, for camera runs, receives (latent, target index, reward) per step.
    """
    scale = scale or (lambda obs: obs)
    parts = state_slices(env.unwrapped.state_layout()) if dynnav else {}
    reach = float(getattr(env.unwrapped, "reach_radius", 0.0))
    records = []
    for i in range(episodes):
        obs, _ = env.reset(seed=seed + i)
        rng = np.random.default_rng(seed + i)
        path, ret, steps = [], 0.0, 0
        if dynnav:
            start, target = state_of(obs)[parts["robot_xy"]].copy(), state_of(obs)[parts["target_xy"]].copy()
            path.append(start.tolist())
        if recorder is not None:
            recorder.start_episode(env, i)
        while True:
            q_values = net(scale(obs))
            latent = getattr(scale, "last_latent", None)
            action = int(np.argmax(q_values))
            if epsilon > 0 and rng.random() < epsilon:
                action = int(rng.integers(len(q_values)))
            obs, reward, terminated, truncated, info = env.step(action)
            if recorder is not None:
                views = scale.views(obs) if hasattr(scale, "views") else {}
                recorder.log_step(env, action=action, reward=float(reward), q_values=q_values, **views)
            if latents is not None and latent is not None:
                latents.append((latent, env.unwrapped.target_index, float(reward)))
            ret += float(reward)
            steps += 1
            if dynnav:
                path.append(state_of(obs)[parts["robot_xy"]].tolist())
            if terminated or truncated:
                break
        record = dict(seed=seed + i, outcome=outcome_of(info, bool(terminated)), steps=steps, ret=round(ret, 4))
        if recorder is not None:
            recorder.end_episode(info)
        if dynnav:
            shortest = max(float(np.linalg.norm(target - start)) - reach, 0.0)
            driven = float(info["path_length"])
            success = record["outcome"] == "success"
            record.update(
                path_length=round(driven, 4), shortest_path=round(shortest, 4),
                spl=round(shortest / max(driven, shortest, 1e-9), 4) if success else 0.0,
                target_start=target.tolist(), trajectory=path,
            )
        records.append(record)
    return records


def summarize(records: list[dict], epsilon: float = 0.0) -> dict:
    n = len(records)
    count = {k: sum(r["outcome"] == k for r in records) for k in ("success", "collision", "timeout", "terminated")}
    lo, hi = wilson_interval(count["success"], n)
    steps = [r["steps"] for r in records if r["outcome"] == "success"]
    summary = dict(
        episodes=n,
        epsilon=epsilon,
        success_rate=count["success"] / n,
        success_ci95=[round(lo, 4), round(hi, 4)],
        collision_rate=count["collision"] / n,
        timeout_rate=count["timeout"] / n,
        terminated_rate=count["terminated"] / n,
        avg_steps_success=round(float(np.mean(steps)), 2) if steps else None,
        avg_return=round(float(np.mean([r["ret"] for r in records])), 4),
    )
    if records and "spl" in records[0]:
        summary["spl"] = round(float(np.mean([r["spl"] for r in records])), 4)
    return summary


def markdown_table(task: str, summary: dict) -> str:
    lo, hi = summary["success_ci95"]
    avg = summary["avg_steps_success"]
    rows = [
        ("task", task),
        (f"test episodes (epsilon {summary.get('epsilon', 0.0):g})", summary["episodes"]),
        ("success rate", f"{summary['success_rate']:.0%} (95% CI {lo:.0%}-{hi:.0%})"),
        ("collision rate", f"{summary['collision_rate']:.0%}"),
        ("timeout rate", f"{summary['timeout_rate']:.0%}"),
        ("ended otherwise (terminated)", f"{summary['terminated_rate']:.0%}"),
        ("average steps (successful episodes)", "-" if avg is None else f"{avg:.1f}"),
        ("average return", f"{summary['avg_return']:.2f}"),
    ]
    if not summary["terminated_rate"]:
        rows = [r for r in rows if not r[0].startswith("ended otherwise")]
    if "spl" in summary:
        rows.append(("SPL", f"{summary['spl']:.3f}"))
    width = max(len(r[0]) for r in rows)
    lines = [f"| {'metric':<{width}} | value |", f"|{'-' * (width + 2)}|-------|"]
    lines += [f"| {name:<{width}} | {value} |" for name, value in rows]
    return "\n".join(lines) + "\n"


def draw_trajectories(env, records: list[dict], path: Path) -> None:
    """Every test trajectory on the task's top-down render, coloured by outcome."""
    from PIL import ImageDraw

    from dynnav_tasks.pictures import annotated_top_down

    env.reset(seed=records[0]["seed"])
    img = annotated_top_down(env)
    draw = ImageDraw.Draw(img)
    px = env.unwrapped.top_down_pixel
    for r in records:
        pts = [px(x, y) for x, y in r["trajectory"]]
        color = OUTCOME_COLORS.get(r["outcome"], (128, 128, 128))
        if len(pts) > 1:
            draw.line(pts, fill=color, width=2)
        (c, w), (tc, tw) = pts[0], px(*r["target_start"])
        draw.ellipse([c - 3, w - 3, c + 3, w + 3], fill=(255, 255, 255))
        draw.ellipse([tc - 3, tw - 3, tc + 3, tw + 3], outline=(120, 0, 0))
    y = 6
    for name, color in OUTCOME_COLORS.items():
        n = sum(r["outcome"] == name for r in records)
        draw.rectangle([6, y + 2, 16, y + 10], fill=color)
        draw.text((22, y), f"{name} ({n})", fill=(255, 255, 255))
        y += 14
    tmp = path.with_name(f".{path.name}.tmp.png")
    img.save(tmp)
    tmp.replace(path)


def load_policy(checkpoint_path, **task_kwargs):
    """(config, env, Q-network, state scaler, checkpoint path, checkpoint state) of a trained agent.

    ``task_kwargs`` are added to the task's own (e.g. obs_mode for recordings)."""
    path = ckpt.resolve(checkpoint_path)
    state = ckpt.load(path)
    config = config_from_dict(state["config"], source=f"config in {path}")
    return (config, *policy_from_state(config, state, **task_kwargs), path, state)


def policy_from_state(config, state: dict, **task_kwargs):
    """(env, Q-network, observation -> network input) for a loaded checkpoint ``state``.

    For a camera run the input is the checkpoint's auto-encoder's latent of the frame (beside the
    chosen state parts); the environment then observes ``{"rgb" or "gray": ..., "state": ...}``."""
    env = make_env(config.task, config.reward_mode, config.reward_params, {**config.task_kwargs, **task_kwargs},
                   config.camera_frames)
    net = MLP(state["learner"]["sizes"])
    net.flat[:] = state["learner"]["q"]
    if not config.camera_frames:
        return env, net, ObsScaler(env.observation_space, config.normalize_obs)
    from .experience import CameraFeatures, new_state_representation

    srl = new_state_representation(env, config)
    srl.load_state_dict(state["srl"])
    return env, net, CameraFeatures(env, config, srl)


def evaluate_as_configured(config, checkpoint_path, **kwargs) -> dict:
    """``evaluate`` with the test settings of a run's ``config`` (eval_episodes, eval_seed,
    eval_picture, eval_epsilon); ``kwargs`` go to ``evaluate`` (out_dir, verbose, rerun)."""
    return evaluate(checkpoint_path, episodes=config.eval_episodes, seed=config.eval_seed,
                    picture=config.eval_picture, epsilon=config.eval_epsilon, **kwargs)


def evaluate(checkpoint_path, episodes: int = 100, seed: int = 1_000_000, picture: bool = True,
             out_dir: str | Path | None = None, verbose: bool = True, rerun: str | Path | None = None,
             epsilon: float = 0.0) -> dict:
    """Test the checkpoint's Q-network; write eval.json / eval.md (/ trajectories.png); return the summary.

    ``epsilon``: probability of a random action per step (0, greedy, is the test; see run_episodes).

    ``rerun``: also write every test episode to this Rerun recording (dynnav tasks)."""
    limit_threads(1)
    from .dqn import open_recorder

    path = ckpt.resolve(checkpoint_path)
    state = ckpt.load(path)
    config = config_from_dict(state["config"], source=f"config in {path}")
    recorder = open_recorder(rerun, config.task)  # checks the recording path before any work
    env, net, scale = policy_from_state(config, state)
    out_dir = Path(out_dir) if out_dir is not None else path.parent
    out_dir.mkdir(parents=True, exist_ok=True)
    dynnav = is_dynnav(config.task)
    latents = [] if config.camera_frames else None
    records = run_episodes(net, env, episodes, seed, dynnav, scale, recorder, latents, epsilon)
    if recorder is not None:
        recorder.close()
    if latents:
        from .srl_pictures import plot_latents

        z, targets, rewards = (np.array(v) for v in zip(*latents))
        np.savez_compressed(out_dir / "latents.npz", latents=z, targets=targets, rewards=rewards)
        plot_latents(z, targets, rewards, out_dir, title=config.task)
    summary = summarize(records, epsilon)
    result = dict(task=config.task, checkpoint=str(path), trained_episodes=state["episode"], eval_seed=seed,
                  summary=summary, episodes=records)
    table = markdown_table(config.task, summary)
    ckpt.atomic_write_bytes(out_dir / "eval.json", json.dumps(result, indent=1).encode())
    ckpt.atomic_write_bytes(out_dir / "eval.md", (f"Test of {path} after {state['episode']} training episodes\n\n"
                                                   + table).encode())
    if verbose:
        print(f"\ntest phase: {path} ({state['episode']} training episodes)\n")
        print(table)
    if picture and dynnav:
        draw_trajectories(env, records, out_dir / "trajectories.png")
        if verbose:
            print(f"trajectories: {out_dir / 'trajectories.png'}")
    if verbose:
        print(f"results: {out_dir / 'eval.json'}, {out_dir / 'eval.md'}")
    env.close()
    return summary
