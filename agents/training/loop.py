"""The training loop: one run of DQN or Double DQN as a config says (see ``agents.dqn``)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import torch

from agents.training import checkpoint as ckpt
from agents.training.config import Config
from agents.training.config_io import config_from_dict, parse_args, save_yaml, to_yaml_dict
from agents.training.envs import make_env_from
from agents.training.test_phase import evaluate_as_configured
from agents.training.experience import make_experience
from agents.core.learner import Batch, DQNLearner
from agents.core.policy import build_q_network
from agents.training.rollout import open_recorder, rollout
from agents.training.run_dir import MetricsLog, check_resumable, episode_seed, new_run_dir, update_state_representation
from agents.core.schedules import epsilon_at, learning_rate_at
from agents.training.threads import limit_threads


def train(config: Config) -> Path:
    """Train as ``config`` says (or continue ``config.resume``); return the run directory.

    Everything is checked (config, task, checkpoint, recording path) before any file is written."""
    limit_threads(1)
    d = config.dqn
    recorder = open_recorder(config.run.rerun, config.task)
    resumed = ckpt.load(config.resume) if config.resume else None
    if resumed:
        check_resumable(config, config_from_dict(resumed["config"], source=f"config in {config.resume}"))
    # --- environment, replay memory, Q-network and its update
    env = make_env_from(config)
    experience = make_experience(env, config)  # what the Q-network reads and the replay memory keeps
    specs, n_actions = experience.features.input_specs, int(env.action_space.n)
    q_network = build_q_network(config, specs, n_actions)
    learner = DQNLearner(q_network, Batch(d.batch_size, specs), d.gamma, double=d.algorithm == "ddqn", loss=d.loss,
                         max_grad_norm=d.max_grad_norm, learning_rate=config.schedule.learning_rate,
                         device=config.run.device)
    srl = experience.srl  # the camera's auto-encoder (None for state and pixel runs)
    rng = np.random.default_rng(config.seed)
    start_episode, global_step, wall_time = 0, 0, 0.0
    if resumed:
        learner.load_state_dict(resumed["learner"])
        experience.memory.load_state_dict(resumed["memory"])
        if srl is not None:
            srl.load_state_dict(resumed["srl"])
        rng.bit_generator.state = resumed["rng"]
        torch.set_rng_state(resumed["torch_rng"])
        start_episode, global_step, wall_time = resumed["episode"], resumed["global_step"], resumed["wall_time_s"]
    # --- the run directory: only now that everything checked out
    run_dir = Path(config.resume) if config.resume else new_run_dir(config)
    ckpt.clean_leftovers(run_dir)
    save_yaml(config, run_dir / "config.yaml")  # a resumed run may have changed e.g. the episode count
    metrics = MetricsLog(run_dir / "metrics.csv", keep_episodes=start_episode if resumed else None)
    if resumed:
        print(f"resuming {run_dir} at episode {start_episode} (step {global_step})")
    elif srl is not None:
        print(f"camera state: {srl.settings.frames} frame(s) -> latent {srl.latent_dim} + "
              f"{specs[0][0][0] - srl.latent_dim} state values; observation memory "
              f"{experience.memory.nbytes / 1e6:.0f} MB; auto-encoder updates after episodes "
              f"{', '.join(map(str, srl.settings.update_episodes))}")

    def save_checkpoint(episodes_done: int) -> None:
        metrics.flush()
        ckpt.save(run_dir, dict(
            config=to_yaml_dict(config), episode=episodes_done, global_step=global_step, wall_time_s=wall_time,
            input_shapes=[list(shape) for shape, _ in specs], n_actions=n_actions,
            learner=learner.state_dict(), memory=experience.memory.state_dict(),
            srl=srl.state_dict() if srl is not None else None,
            rng=rng.bit_generator.state, torch_rng=torch.get_rng_state(),
        ))
        metrics.plot(run_dir, title=config.task)

    # --- training loop
    bar = metrics.progress_bar(config, start_episode) if config.run.progress else None
    for episode in range(start_episode, config.episodes):
        # Alg. 2: with the auto-encoder, act at random until its first update
        epsilon = epsilon_at(config.schedule, episode) if experience.ready else 1.0
        learner.learning_rate = learning_rate_at(config.schedule, episode)
        recording = recorder is not None and episode % config.run.rerun_every == 0
        losses, current = [], {}

        def act(obs):
            acting = experience.ready
            q_values = learner.q_values(current["x"]) if recording and acting else None
            if not acting or rng.random() < epsilon:
                return int(rng.integers(n_actions)), q_values
            return (int(np.argmax(q_values)) if recording else learner.act(current["x"])), q_values

        def on_reset(obs):
            current["x"] = experience.begin(obs)

        def on_step(action, reward, next_obs, terminated, truncated, info):
            nonlocal global_step
            acting = experience.ready
            current["x"] = experience.step(action, reward, next_obs, terminated)
            global_step += 1
            if acting and global_step > d.learning_starts and global_step % d.train_frequency == 0 \
                    and len(experience) >= d.batch_size:
                experience.sample_into(learner.batch, rng)
                losses.append(learner.update())
                if d.target_update == "soft":
                    learner.update_target(d.tau)
            if d.target_update == "hard" and global_step % d.target_update_interval == 0:
                learner.update_target()

        views = experience.features.views if recording and srl is not None else None
        t0 = time.perf_counter()
        result = rollout(env, episode_seed(config.seed, episode), act, on_reset, on_step,
                         recorder if recording else None, index=episode, views=views)
        elapsed = time.perf_counter() - t0
        wall_time += elapsed
        metrics.log(episode, global_step, result, losses, epsilon, learner.learning_rate, elapsed, wall_time,
                    recorder, bar)
        if srl is not None:
            update_state_representation(srl, experience.memory, rng, episode + 1, config, run_dir)
        if (episode + 1) % config.run.checkpoint_every == 0 or episode + 1 == config.episodes:
            save_checkpoint(episode + 1)
    if bar is not None:
        bar.close()
    if recorder is not None:
        recorder.close()
    metrics.close()
    env.close()
    return run_dir
