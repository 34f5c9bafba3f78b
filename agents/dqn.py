"""DQN (thesis Alg. 1) and Double DQN (Appendix A) for dynnav tasks and any gymnasium env
with discrete actions and a state vector.

    python -m agents.dqn --config configs/moving_target_5_2.yaml        # train, then test
    python -m agents.dqn --task CartPole-v1 --episodes 300              # any gymnasium env
    python -m agents.dqn --resume runs/<run>                            # continue a stopped run
    python -m agents.dqn --eval --checkpoint runs/<run>/checkpoint.pkl  # test phase only
    python -m agents.dqn --config ... --rerun runs/train.rrd            # also record (Rerun)
    python -m agents.dqn --config configs/camera_5_5a.yaml              # camera + auto-encoder (Alg. 2)

A run directory ``runs/<task>__<name>__<seed>__<time>/`` receives the resolved config
(config.yaml), one metrics row per episode (metrics.csv), the checkpoint (checkpoint.pkl,
rewritten atomically every ``checkpoint_every`` episodes), the learning curves (reward.png,
loss.png) and the test results (eval.json, eval.md, trajectories.png).

The loop, per environment step: epsilon-greedy action; store (s, a, r, s', terminated);
once ``learning_starts`` steps are stored, every ``train_frequency`` steps one gradient step on
a minibatch; hard target copy every ``target_update_interval`` steps (or a soft update after
every gradient step). A timeout (truncation) still bootstraps from Q(s'); a success or a
collision (termination) does not. Epsilon and the learning rate change once per episode.

Camera runs (``camera_frames`` > 0, thesis Alg. 2) read an auto-encoder's latent instead of
the state vector (see agents/state_representation.py): actions are random and the Q-network
does not train until the auto-encoder's first update; the updates run between episodes on
their schedule, and write srl_loss.csv/png and reconstructions/ into the run directory.
"""

from __future__ import annotations

import csv
import io
import sys
import time
from collections import deque
from pathlib import Path

import numpy as np

from . import checkpoint as ckpt
from .config import Config, parse_args, save_yaml
from .envs import is_dynnav, make_env
from .experience import make_experience
from .qnetwork import QLearner
from .schedules import epsilon_at, learning_rate_at
from .threads import limit_threads

METRICS = ["episode", "global_step", "return", "length", "success", "collision", "timeout", "loss",
           "epsilon", "learning_rate", "steps_per_s", "wall_time_s"]


def episode_seed(seed: int, episode: int) -> int:
    """The reset seed of training episode ``episode`` (a hash of both: distinct from test seeds)."""
    return int(np.random.SeedSequence([seed, episode]).generate_state(1)[0])


def new_run_dir(config: Config) -> Path:
    stamp = time.strftime("%Y%m%d-%H%M%S")
    base = Path(config.runs_dir) / f"{config.task.replace('/', '-')}__{config.name}__{config.seed}__{stamp}"
    run_dir, k = base, 1
    while run_dir.exists():
        run_dir, k = Path(f"{base}-{k}"), k + 1
    run_dir.mkdir(parents=True)
    return run_dir


def keep_metric_rows(path: Path, episodes: int) -> None:
    """Drop the rows of episodes after the checkpoint a resumed run continues from."""
    if not path.exists():
        return
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r.get("episode", "").isdigit() and int(r["episode"]) < episodes]
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=METRICS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    ckpt.atomic_write_bytes(path, out.getvalue().encode())


def train(config: Config) -> Path:
    """Train as ``config`` says (or continue ``config.resume``); return the run directory."""
    limit_threads(1)
    recorder = open_recorder(config.rerun, config.task)  # checks the recording path before any work
    # --- run directory, environment, agent
    resumed = ckpt.load(config.resume) if config.resume else None
    env = make_env(config.task, config.reward_mode, config.reward_params, config.task_kwargs, config.camera_frames)
    experience = make_experience(env, config)  # what the Q-network reads and the replay memory keeps
    run_dir = Path(config.resume) if config.resume else new_run_dir(config)
    save_yaml(config, run_dir / "config.yaml")  # a resumed run may have changed e.g. the episode count
    srl = experience.srl  # the camera's auto-encoder (None for state runs)
    obs_dim, n_actions = experience.dim, int(env.action_space.n)
    rng = np.random.default_rng(config.seed)
    learner = QLearner(obs_dim, n_actions, config.hidden_sizes, config.batch_size, config.gamma,
                       double=config.algorithm == "ddqn", loss=config.loss, max_grad_norm=config.max_grad_norm,
                       learning_rate=config.learning_rate, rng=rng)
    start_episode, global_step, wall_time = 0, 0, 0.0
    if resumed:
        learner.load_state_dict(resumed["learner"])
        experience.memory.load_state_dict(resumed["memory"])
        if srl is not None:
            srl.load_state_dict(resumed["srl"])
        rng.bit_generator.state = resumed["rng"]
        start_episode, global_step, wall_time = resumed["episode"], resumed["global_step"], resumed["wall_time_s"]
        keep_metric_rows(run_dir / "metrics.csv", start_episode)
        print(f"resuming {run_dir} at episode {start_episode} (step {global_step})")
    elif srl is not None:
        memory_mb = experience.memory.nbytes / 1e6
        print(f"camera state: {srl.settings.frames} frame(s) -> latent {srl.latent_dim} + {obs_dim - srl.latent_dim} "
              f"state values; observation memory {memory_mb:.0f} MB; auto-encoder updates after episodes "
              f"{', '.join(map(str, srl.settings.update_episodes))}")

    metrics_path = run_dir / "metrics.csv"
    new_file = not metrics_path.exists()
    metrics_file = open(metrics_path, "a", newline="")
    writer = csv.DictWriter(metrics_file, fieldnames=METRICS, lineterminator="\n")
    if new_file:
        writer.writeheader()

    def save_checkpoint(episodes_done: int) -> None:
        metrics_file.flush()
        ckpt.save(run_dir / ckpt.FILENAME, dict(
            config=config.to_yaml_dict(), episode=episodes_done, global_step=global_step,
            wall_time_s=wall_time, learner=learner.state_dict(), memory=experience.memory.state_dict(),
            srl=srl.state_dict() if srl is not None else None,
            rng=rng.bit_generator.state, obs_dim=obs_dim, n_actions=n_actions,
        ))
        from .plots import plot_learning_curves

        plot_learning_curves(metrics_path, run_dir, title=config.task)

    # --- training loop
    recent_success, recent_return = deque(maxlen=100), deque(maxlen=100)
    bar = None
    if config.progress:
        from tqdm import tqdm

        bar = tqdm(total=config.episodes, initial=start_episode, desc=config.task, unit="ep", dynamic_ncols=True,
                   mininterval=0.5)
    for episode in range(start_episode, config.episodes):
        # Alg. 2: with a camera, act at random until the auto-encoder's first update
        epsilon = epsilon_at(config, episode) if experience.ready else 1.0
        learner.learning_rate = learning_rate_at(config, episode)
        obs, _ = env.reset(seed=episode_seed(config.seed, episode))
        x = experience.begin(obs)
        episode_return, length, losses = 0.0, 0, []
        recording = recorder is not None and episode % config.rerun_every == 0
        if recording:
            recorder.start_episode(env, episode)
        t0 = time.perf_counter()
        while True:
            acting = experience.ready
            q_values = learner.q(x) if recording and acting else None
            if not acting or rng.random() < epsilon:
                action = int(rng.integers(n_actions))
            else:
                action = int(np.argmax(q_values)) if recording else learner.act(x)
            next_obs, reward, terminated, truncated, info = env.step(action)
            x = experience.step(action, float(reward), next_obs, bool(terminated))
            if recording:
                views = experience.encoder_features.views(next_obs) if srl is not None else {}
                recorder.log_step(env, action=action, reward=float(reward), q_values=q_values, **views)
            global_step += 1
            episode_return += float(reward)
            length += 1

            if acting and global_step > config.learning_starts and global_step % config.train_frequency == 0 \
                    and len(experience) >= config.batch_size:
                experience.sample_into(learner.batch, rng)
                losses.append(learner.update())
                if config.target_update == "soft":
                    learner.update_target(config.tau)
            if config.target_update == "hard" and global_step % config.target_update_interval == 0:
                learner.update_target()

            if terminated or truncated:
                break
        elapsed = time.perf_counter() - t0
        wall_time += elapsed
        success = bool(info.get("success", False))
        writer.writerow(dict(
            episode=episode, global_step=global_step, **{"return": round(episode_return, 4)}, length=length,
            success=int(success), collision=int(bool(info.get("collision", False))),
            timeout=int(bool(info.get("timeout", truncated and not terminated))),
            loss=f"{np.mean(losses):.6g}" if losses else "", epsilon=round(epsilon, 5),
            learning_rate=f"{learner.learning_rate:.6g}", steps_per_s=round(length / elapsed, 1),
            wall_time_s=round(wall_time, 2),
        ))
        recent_success.append(success)
        recent_return.append(episode_return)
        if recorder is not None:
            if recording:
                recorder.end_episode(info)
            recorder.log_training(episode, episode_return=episode_return, loss=np.mean(losses) if losses else None,
                                  epsilon=epsilon, success_rate=float(np.mean(recent_success)))
        if bar is not None:
            bar.update(1)
            bar.set_postfix(success=f"{np.mean(recent_success):.0%}", ret=f"{np.mean(recent_return):.1f}",
                            eps=f"{epsilon:.2f}", sps=f"{length / elapsed:.0f}", refresh=False)
        if srl is not None:
            update_state_representation(srl, experience.memory, rng, episode + 1, config, run_dir)
        if (episode + 1) % config.checkpoint_every == 0 or episode + 1 == config.episodes:
            save_checkpoint(episode + 1)
    if bar is not None:
        bar.close()
    if recorder is not None:
        recorder.close()
    metrics_file.close()
    env.close()
    return run_dir


def update_state_representation(srl, memory, rng, episodes_done: int, config: Config, run_dir: Path) -> None:
    """After an episode: the scheduled auto-encoder update (Alg. 2) and the reconstruction pictures."""
    from . import srl_pictures as pics

    if srl.due(episodes_done):
        losses = srl.update(memory, rng, progress=config.progress)
        pics.append_srl_losses(run_dir / "srl_loss.csv", srl.updates_done, episodes_done, losses)
        pics.plot_srl_losses(run_dir / "srl_loss.csv", run_dir / "srl_loss.png", title=config.task)
    if srl.trained and episodes_done % config.ae_pictures_every == 0:
        # eight observations from the end of the memory, three steps apart
        slots = (memory.last - 3 * np.arange(min(8, 1 + (memory.size - 1) // 3))) % memory.capacity
        frames = memory.frames[slots[::-1]]
        pics.save_reconstruction_pairs(frames, srl.reconstruct(frames),
                                       run_dir / "reconstructions" / f"episode_{episodes_done:05d}.png")


def open_recorder(path, task: str):
    """A Rerun recorder writing to ``path`` (None: no recording); dynnav tasks only."""
    if path is None:
        return None
    if not is_dynnav(task):
        raise ValueError(f"--rerun records dynnav tasks (their world, lasers and camera), not {task!r}")
    from dynnav_tasks.recording import Recorder

    return Recorder(path)


def main(argv: list[str] | None = None) -> None:
    try:
        config = parse_args(argv)
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    from .evaluate import evaluate_as_configured

    try:
        if config.eval:
            evaluate_as_configured(config, config.checkpoint, rerun=config.rerun, out_dir=config.eval_out)
            return
        run_dir = train(config)
        if config.eval_after_training:
            evaluate_as_configured(config, run_dir / ckpt.FILENAME)
        print(f"\nrun directory: {run_dir}")
        pictures = [p.name for p in sorted(run_dir.glob("*.png"))]
        print(f"  config.yaml, metrics.csv, checkpoint.pkl; pictures: {', '.join(pictures)}")
    except ValueError as err:  # config, task or checkpoint errors
        raise SystemExit(f"error: {err}")


if __name__ == "__main__":
    main(sys.argv[1:])
