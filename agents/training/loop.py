"""The training loop: one run of DQN or Double DQN as a config says (see ``agents.dqn``).

``train`` reads top to bottom: check everything and build the run (environment, replay memory,
Q-network, learner), lock the run directory, then for every episode: reset; for every step:
choose an epsilon-greedy action, step the environment, store the transition, update the
Q-network, sync the target network, record; then log the episode, update the camera's
auto-encoder on its schedule (Alg. 2) and save a checkpoint every ``checkpoint_every`` episodes.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path

import numpy as np
import torch

from agents.core.learner import DQNLearner
from agents.core.policy import build_learner, build_q_network
from agents.core.schedules import epsilon_at, learning_rate_at
from agents.training import checkpoint as ckpt
from agents.training.config import Config
from agents.training.config_io import config_from_dict, save_yaml, to_yaml_dict
from agents.training.envs import make_env_from
from agents.training.experience import make_experience
from agents.training.rollout import Episode, open_recorder
from agents.training.run_dir import MetricsLog, check_resumable, episode_seed, new_run_dir, update_state_representation
from agents.training.run_lock import RunDirLock
from agents.training.teacher import initialise, load_demonstrations, start_weights
from agents.training.tensorboard_log import TensorBoardLog
from agents.training.threads import limit_threads
from dynnav_tasks.outcomes import outcome_of


def save_checkpoint(run_dir: Path, config: Config, counts: dict, learner: DQNLearner, experience,
                    rng: np.random.Generator, n_actions: int) -> None:
    """Write the checkpoint: ``counts`` (episode, global_step, wall_time_s) and everything else
    ``--resume`` needs to continue exactly (networks, optimizer, memory, auto-encoder, generators)."""
    srl = experience.srl
    ckpt.save(run_dir, dict(
        config=to_yaml_dict(config), **counts,
        input_shapes=[list(shape) for shape, _ in experience.features.input_specs], n_actions=n_actions,
        learner=learner.state_dict(), memory=experience.memory.state_dict(),
        srl=srl.state_dict() if srl is not None else None,
        rng=rng.bit_generator.state, torch_rng=torch.get_rng_state(),
    ))


def restore(resumed: dict, learner: DQNLearner, experience, rng: np.random.Generator) -> tuple[int, int, float]:
    """Load a checkpoint's state into the run's parts; return its (episode, global_step, wall_time_s)."""
    learner.load_state_dict(resumed["learner"])
    experience.memory.load_state_dict(resumed["memory"])
    if experience.srl is not None:
        experience.srl.load_state_dict(resumed["srl"])
    rng.bit_generator.state = resumed["rng"]
    torch.set_rng_state(resumed["torch_rng"])
    return resumed["episode"], resumed["global_step"], resumed["wall_time_s"]


def load_resumed(config: Config, cleanup: contextlib.ExitStack) -> dict | None:
    """The checkpoint ``config.resume`` names (None for a new run), its run directory locked
    first (the lock released by ``cleanup``) so that it cannot change under us; ValueError if
    the config cannot continue it."""
    if config.resume and Path(config.resume).is_dir():
        cleanup.enter_context(RunDirLock(config.resume))
    resumed = ckpt.load(config.resume) if config.resume else None
    if resumed:
        check_resumable(config, config_from_dict(resumed["config"], source=f"config in {config.resume}"))
    return resumed


def open_run_dir(config: Config, cleanup: contextlib.ExitStack, keep_episodes: int | None) -> tuple[Path, MetricsLog]:
    """The run directory (the resumed one, or a new one, locked) with its config.yaml written and
    its metrics log open (keeping the first ``keep_episodes`` rows of a resumed run); call it only
    once everything checked out."""
    if config.resume:
        run_dir = Path(config.resume)
    else:
        run_dir = new_run_dir(config)
        cleanup.enter_context(RunDirLock(run_dir))
    ckpt.clean_leftovers(run_dir)
    save_yaml(config, run_dir / "config.yaml")  # a resumed run may have changed e.g. the episode count
    tensorboard = TensorBoardLog(run_dir) if config.run.tensorboard else None
    metrics = MetricsLog(run_dir / "metrics.csv", keep_episodes=keep_episodes, tensorboard=tensorboard)
    cleanup.callback(metrics.close)
    return run_dir, metrics


def train(config: Config) -> Path:
    """Train as ``config`` says (or continue ``config.resume``); return the run directory.

    Everything is checked (config, task, checkpoint, recording path) before any file is written;
    a run directory that another live process is writing is refused (``RunDirBusy``)."""
    if config.run.fast:
        raise ValueError("run.fast: this is the single-process loop; train a fast run with agents.dqn.train")
    limit_threads(1)
    d = config.dqn
    with contextlib.ExitStack() as cleanup:
        # --- checks: a resumed run's directory is locked first, so its checkpoint cannot change under us
        recorder = open_recorder(config.run.rerun, config.task)
        if recorder is not None:
            cleanup.callback(recorder.close)
        resumed = load_resumed(config, cleanup)

        # --- environment, replay memory, Q-network and its update
        env = make_env_from(config)
        cleanup.callback(env.close)
        experience = make_experience(env, config)  # what the Q-network reads and the replay memory keeps
        specs, n_actions = experience.features.input_specs, int(env.action_space.n)
        q_network = build_q_network(config, specs, n_actions)
        learner = build_learner(config, q_network, specs)  # DQN, or on sequences for a recurrent Q-network
        srl = experience.srl  # the camera's auto-encoder (None for state and pixel runs)
        demos = load_demonstrations(config, experience.features)  # a teacher's episodes, kept in the replay
        rng = np.random.default_rng(config.seed)
        if resumed:
            start_episode, global_step, wall_time = restore(resumed, learner, experience, rng)
        else:  # a new run: the teacher's student as the start (init_from), DQfD's pre-training
            start_episode, global_step, wall_time = 0, 0, 0.0
            initialise(learner, config, start_weights(config), demos)

        # --- the run directory: only now that everything checked out
        run_dir, metrics = open_run_dir(config, cleanup, start_episode if resumed else None)
        if resumed:
            print(f"resuming {run_dir} at episode {start_episode} (step {global_step})")
        elif srl is not None:
            print(f"camera state: {srl.settings.frames} frame(s) -> latent {srl.latent_dim} + "
                  f"{specs[0][0][0] - srl.latent_dim} state values; observation memory "
                  f"{experience.memory.nbytes / 1e6:.0f} MB; auto-encoder updates after episodes "
                  f"{', '.join(map(str, srl.settings.update_episodes))}")
        bar = metrics.progress_bar(config, start_episode) if config.run.progress else None
        if bar is not None:
            cleanup.callback(bar.close)

        # --- the training loop
        for episode in range(start_episode, config.episodes):
            # Alg. 2: with the auto-encoder, act at random (and do not train) until its first update
            acting = experience.ready
            epsilon = epsilon_at(config.schedule, episode) if acting else 1.0
            learner.learning_rate = learning_rate_at(config.schedule, episode)
            recording = recorder is not None and episode % config.run.rerun_every == 0
            views = experience.features.views if recording and srl is not None else None
            seed, losses, ret, length = episode_seed(config.seed, episode), [], 0.0, 0
            t0 = time.perf_counter()

            obs, _ = env.reset(seed=seed)
            x = experience.begin(obs)  # the Q-network's input (None until the auto-encoder's first update)
            learner.reset()  # a recurrent Q-network's hidden state starts at zero
            if recording:
                recorder.start_episode(env, episode)
            while True:
                # epsilon-greedy action (the Q-values are computed for a recording too, and every step
                # for a recurrent Q-network, whose hidden state follows the whole episode)
                q_values = learner.q_values(x) if acting and (recording or learner.recurrent) else None
                if not acting or rng.random() < epsilon:
                    action = int(rng.integers(n_actions))
                else:
                    action = int(np.argmax(q_values)) if q_values is not None else learner.act(x)
                obs, reward, terminated, truncated, info = env.step(action)
                reward, terminated = float(reward), bool(terminated)
                # store the transition (s, a, r, s', terminated); x becomes the next input
                x = experience.step(action, reward, obs, terminated)
                global_step += 1
                # one gradient step every train_frequency steps, once learning_starts steps are stored
                if acting and global_step > d.learning_starts and global_step % d.train_frequency == 0 \
                        and len(experience) >= d.batch_size:
                    experience.sample_into(learner.batch, rng)
                    if demos is not None:  # a share of the minibatch from the demonstrations, with labels
                        demos.sample_into(learner.batch, rng)
                    losses.append(learner.update())
                    if d.target_update == "soft":
                        learner.update_target(d.tau)
                if d.target_update == "hard" and global_step % d.target_update_interval == 0:
                    learner.update_target()
                if recording:
                    recorder.log_step(env, action=action, reward=reward, q_values=q_values,
                                      **(views(obs) if views is not None else {}))
                ret += reward
                length += 1
                if terminated or truncated:
                    break
            if recording:
                recorder.end_episode(info)

            elapsed = time.perf_counter() - t0
            wall_time += elapsed
            result = Episode(seed, ret, length, info, terminated, outcome_of(info, terminated))
            metrics.log(episode, global_step, result, losses, epsilon, learner.learning_rate, elapsed, wall_time,
                        recorder, bar)
            if srl is not None:
                update_state_representation(srl, experience.memory, rng, episode + 1, config, run_dir)
            if (episode + 1) % config.run.checkpoint_every == 0 or episode + 1 == config.episodes:
                counts = dict(episode=episode + 1, global_step=global_step, wall_time_s=wall_time)
                save_checkpoint(run_dir, config, counts, learner, experience, rng, n_actions)
                metrics.plot(run_dir, title=config.task)
    return run_dir
