"""The fast training loop (``run.fast: true``, ``--fast``): collecting and learning on two cores.

This process steps the environment and acts epsilon-greedily with its own copy of the Q-network;
a second process (``agents.training.learner_process``) makes the (Double) DQN updates from a
replay memory in shared memory and publishes its weights, which this process copies every
``fast_sync_steps`` steps. The learner makes exactly as many updates as the single-process loop
(``agents.training.loop``) would after each step, never more, so the replay ratio is the
config's; the collector waits when the learner falls behind.

The run directory is the same (config.yaml, metrics.csv, checkpoint/, the test phase), so
``--eval``, the run table and the report read a fast run like any other. A fast run does not
replay bit for bit (its actor's weights lag the learner's by up to a few hundred steps, by
timing); ``--resume`` continues from the last checkpoint with the same networks, Adam state,
replay memory and exploration generator, but the steps after it differ from run to run.
State-vector and pixel runs (``camera_input: pixels``); not the auto-encoder's camera runs, and no
Rerun recording while training.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path

import numpy as np

from agents.core.frame_replay import FrameReplay
from agents.core.networks import MLPQNetwork, q_values_of
from agents.core.policy import build_q_network
from agents.core.schedules import epsilon_at, learning_rate_at
from agents.training.config import Config, check_fast
from agents.training.envs import make_env_from
from agents.training.experience import make_experience
from agents.training.learner_process import LearnerProcess
from agents.training.shared_replay import SharedFrameReplay, SharedReplayMemory
from agents.training.loop import load_resumed, open_run_dir, restore, save_checkpoint
from agents.training.rollout import Episode
from agents.training.run_dir import episode_seed
from agents.training.teacher import load_demonstrations, start_weights
from agents.training.threads import limit_threads
from dynnav_tasks.outcomes import outcome_of


def greedy_action(actor):
    """``act(x) -> int``, the greedy action of ``actor``: for the MLP in numpy on views of its weights
    (a tenth of torch's per-call time for one input; the views follow ``copy_weights_to``), else through torch."""
    if not isinstance(actor, MLPQNetwork):
        return lambda x: int(np.argmax(q_values_of(actor, x)))
    layers = [(m.weight.detach().numpy(), m.bias.detach().numpy()) for m in actor.linears]
    hidden, (w_out, b_out) = layers[:-1], layers[-1]

    def act(x) -> int:
        for w, b in hidden:
            x = np.maximum(w @ x + b, 0.0)
        return int(np.argmax(w_out @ x + b_out))

    return act


def shared_memory_for(experience, config) -> SharedReplayMemory | SharedFrameReplay:
    """An empty replay memory in shared memory in place of the one ``experience`` made."""
    memory = experience.memory
    if isinstance(memory, FrameReplay):
        return SharedFrameReplay(config.dqn.buffer_size, memory.frame_shape, memory.state_dim, memory.latent_dim)
    return SharedReplayMemory(config.dqn.buffer_size, memory.obs_dim)


def train_fast(config: Config) -> Path:
    """Train as ``config`` says (or continue ``config.resume``) on two processes; return the run directory."""
    limit_threads(1)
    check_fast(config)
    with contextlib.ExitStack() as cleanup:
        # --- checks: a resumed run's directory is locked first, so its checkpoint cannot change under us
        resumed = load_resumed(config, cleanup)

        # --- environment, shared replay memory, the acting network and the learner process
        env = make_env_from(config)
        cleanup.callback(env.close)
        experience = make_experience(env, config)
        specs, n_actions = experience.features.input_specs, int(env.action_space.n)
        experience.memory = shared_memory_for(experience, config)  # the learner samples from it
        actor = build_q_network(config, specs, n_actions)  # the learner's initial weights: same seed
        act = greedy_action(actor)
        demos = load_demonstrations(config, experience.features)  # checked here, used by the learner process
        learner = cleanup.enter_context(LearnerProcess(config, specs, n_actions, experience.memory, demos,
                                                       None if resumed else start_weights(config)))
        rng = np.random.default_rng(config.seed)
        start_episode, global_step, wall_time = restore(resumed, learner, experience, rng) if resumed else (0, 0, 0.0)

        # --- the run directory: only now that everything checked out
        run_dir, metrics = open_run_dir(config, cleanup, start_episode if resumed else None)
        if resumed:
            print(f"resuming {run_dir} at episode {start_episode} (step {global_step})")
        bar = metrics.progress_bar(config, start_episode) if config.run.progress else None
        if bar is not None:
            cleanup.callback(bar.close)
        learner.start(global_step)
        learner.copy_weights_to(actor)
        losses_seen, first_step, first_wall_time = learner.loss_totals(), global_step, wall_time

        # --- the training loop: collect here, learn there
        t_start, cpu_start = time.perf_counter(), time.process_time()
        for episode in range(start_episode, config.episodes):
            epsilon = epsilon_at(config.schedule, episode)
            learner.learning_rate = learning_rate_at(config.schedule, episode)
            seed, ret, length = episode_seed(config.seed, episode), 0.0, 0
            t0 = time.perf_counter()

            obs, _ = env.reset(seed=seed)
            x = experience.begin(obs)
            while True:
                if rng.random() < epsilon:
                    action = int(rng.integers(n_actions))
                else:
                    action = act(x)
                obs, reward, terminated, truncated, info = env.step(action)
                reward, terminated = float(reward), bool(terminated)
                x = experience.step(action, reward, obs, terminated)
                global_step += 1
                learner.collected(global_step)  # the learner may now make the updates due; waits if it lags
                if global_step % config.run.fast_sync_steps == 0:
                    learner.copy_weights_to(actor)
                ret += reward
                length += 1
                if terminated or truncated:
                    break

            last = episode + 1 == config.episodes
            checkpoint = (episode + 1) % config.run.checkpoint_every == 0 or last
            if checkpoint:
                learner.catch_up()  # every update due so far, as many as the single-process loop makes
            elapsed = time.perf_counter() - t0
            wall_time += elapsed
            loss_sum, loss_count = learner.loss_totals()
            losses = [(loss_sum - losses_seen[0]) / (loss_count - losses_seen[1])] if loss_count > losses_seen[1] else []
            losses_seen = (loss_sum, loss_count)
            result = Episode(seed, ret, length, info, terminated, outcome_of(info, terminated))
            metrics.log(episode, global_step, result, losses, epsilon, learner.learning_rate, elapsed, wall_time,
                        None, bar)
            if checkpoint:
                counts = dict(episode=episode + 1, global_step=global_step, wall_time_s=wall_time)
                save_checkpoint(run_dir, config, counts, learner, experience, rng, n_actions)
                metrics.plot(run_dir, title=config.task)
        if bar is not None:
            bar.close()
        if config.episodes > start_episode:
            seconds, steps = wall_time - first_wall_time, global_step - first_step
            print(f"fast mode: {config.episodes - start_episode} episodes, {steps} steps, {learner.updates} updates "
                  f"in {seconds:.1f} s of training ({steps / seconds:.0f} steps/s; "
                  f"{time.perf_counter() - t_start:.1f} s with checkpoints); CPU time: collector "
                  f"{time.process_time() - cpu_start:.1f} s (waiting {learner.waited_s:.1f} s for the learner), "
                  f"learner {learner.cpu_s:.1f} s")
    return run_dir
