"""The fast mode (run.fast): collecting and learning in two processes, same run directory."""

import csv
import multiprocessing as mp
from dataclasses import replace

import numpy as np
import pytest

from agents.dqn import train
from agents.training import checkpoint as ckpt
from agents.training import loop
from agents.training.config_io import load_yaml, make
from agents.training.learner_process import updates_due
from agents.training.shared_replay import SharedReplayMemory
from agents.training.test_phase import evaluate


def small(tmp_path, **overrides):
    values = dict(task="DynNav-MovingTarget-v1", reward_mode="distance", episodes=6, learning_starts=64,
                  batch_size=32, hidden_sizes=(32, 32), buffer_size=5000, checkpoint_every=3,
                  target_update_interval=50, epsilon_decay_episodes=4, runs_dir=str(tmp_path / "runs"),
                  progress=False, eval_after_training=False, seed=3, fast=True)
    values.update(overrides)
    return make(**values).validate()


def metrics(run_dir):
    with open(run_dir / "metrics.csv", newline="") as f:
        return list(csv.DictReader(f))


def test_updates_due_counts_the_single_process_loops_updates():
    for learning_starts, batch, frequency in [(1000, 128, 2), (64, 128, 1), (0, 32, 4), (999, 512, 8)]:
        config = make(learning_starts=learning_starts, batch_size=batch, train_frequency=frequency)
        made, stored = 0, 0
        for step in range(1, 3000):  # the condition of agents/training/loop.py, memory not yet full
            stored += 1
            if step > learning_starts and step % frequency == 0 and stored >= batch:
                made += 1
            assert updates_due(config, step) == made, (learning_starts, batch, frequency, step)


def _sample_in_child(memory, out):
    batch_rows = memory.obs[: memory.size].sum(axis=1)
    out.put((memory.size, memory.pos, batch_rows.tolist()))


def test_shared_replay_memory_is_seen_by_another_process():
    memory = SharedReplayMemory(4, 3)
    for i in range(6):  # wraps around
        memory.add(np.full(3, i, np.float32), i % 3, float(i), np.full(3, i + 1, np.float32), i == 5)
    assert (len(memory), memory.pos) == (4, 2)
    ctx = mp.get_context("spawn")
    out = ctx.Queue()
    child = ctx.Process(target=_sample_in_child, args=(memory, out))
    child.start()
    size, pos, sums = out.get(timeout=60)
    child.join()
    assert (size, pos) == (4, 2)
    assert sums == [12.0, 15.0, 6.0, 9.0]  # rows 4, 5, 2, 3 (3 values each)
    state = memory.state_dict()
    copy = SharedReplayMemory(4, 3)
    copy.load_state_dict(state)
    assert (copy.size, copy.pos) == (4, 2) and np.array_equal(copy.rewards, memory.rewards)


def test_fast_mode_learns_the_demo(tmp_path):
    """make demo's run (800 episodes, about 60,000 steps), tested on 50
    episodes: at least 90% successes (seeds 1-5 gave 98-100% on 100)."""
    config = load_yaml("configs/demo.yaml")
    assert config.run.fast, "configs/demo.yaml trains in the fast mode"
    config = replace(config, run=replace(config.run, runs_dir=str(tmp_path), progress=False),
                     test=replace(config.test, eval_after_training=False)).validate()
    run_dir = train(config)
    rows = metrics(run_dir)
    assert len(rows) == 800 and rows[-1]["loss"]
    summary = evaluate(run_dir, episodes=50, picture=False, verbose=False)
    assert summary["success_rate"] >= 0.9, summary


def test_fast_run_directory_resumes_and_tests(tmp_path):
    run_dir = train(small(tmp_path, episodes=3))
    assert [int(r["episode"]) for r in metrics(run_dir)] == [0, 1, 2]
    assert load_yaml(run_dir / "config.yaml").run.fast
    state = ckpt.load(run_dir)
    assert state["episode"] == 3 and state["memory"]["size"] == state["global_step"]
    resumed = train(replace(small(tmp_path, episodes=6), resume=str(run_dir)))
    assert resumed == run_dir
    rows = metrics(run_dir)
    assert [int(r["episode"]) for r in rows] == list(range(6))
    assert any(r["loss"] for r in rows[3:]), "the resumed run made no update"
    state = ckpt.load(run_dir)
    assert state["episode"] == 6 and int(rows[-1]["global_step"]) == state["global_step"]
    summary = evaluate(run_dir, episodes=2, picture=False, verbose=False)
    assert summary["episodes"] == 2


def test_pixel_runs_train_in_the_fast_mode(tmp_path):
    run_dir = train(small(tmp_path, task="DynNav-VisualMovingTargets-v1", camera_frames=4, camera_input="pixels",
                          episodes=2, learning_starts=40, batch_size=16, buffer_size=500))
    rows = metrics(run_dir)
    assert len(rows) == 2 and rows[-1]["loss"], "the learner made no update"
    state = ckpt.load(run_dir)
    frames = state["memory"]["frames"]
    assert frames.shape[1:] == (32, 32, 4) and frames.any(), "the frames did not reach the checkpoint"
    assert state["global_step"] == int(rows[-1]["global_step"])


def test_bad_fast_combinations_are_clear_errors(tmp_path):
    with pytest.raises(ValueError, match="state-vector and pixel runs"):
        small(tmp_path, task="DynNav-VisualMovingTargets-v1", camera_frames=4, camera_input="latent")
    with pytest.raises(ValueError, match="does not record"):
        small(tmp_path, rerun=str(tmp_path / "x.rrd"))
    with pytest.raises(ValueError, match="does not record"):  # a config not validated is checked by the fast loop too
        train(replace(small(tmp_path), run=replace(small(tmp_path).run, rerun=str(tmp_path / "x.rrd"))))
    with pytest.raises(ValueError, match="single-process loop"):
        loop.train(small(tmp_path))
    with pytest.raises(ValueError, match="fast_sync_steps"):
        small(tmp_path, fast_sync_steps=0)
    with pytest.raises(ValueError, match="feed-forward Q-networks; recurrent 'gru'"):
        small(tmp_path, recurrent="gru")
    assert not (tmp_path / "runs").exists(), "a refused run wrote files"
    # testing a fast run's checkpoint with a recording is no training: allowed
    assert make(eval=True, checkpoint="runs/x", fast=True, rerun=str(tmp_path / "x.rrd")).validate().run.fast
