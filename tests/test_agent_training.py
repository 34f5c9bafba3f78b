"""Training runs: reproducibility, checkpoints, resuming a stopped run, the test phase."""

import csv
import json
import pickle
import shutil

import gymnasium as gym
import numpy as np
import pytest

import torch

from agents.training import checkpoint as ckpt
from agents.training.config import Config
from agents.training.config_io import load_yaml, make
from agents.dqn import main, train
from agents.training.test_phase import evaluate
from agents.core.networks import MLPQNetwork
from agents.training.policy_loading import load_policy
from agents.training.stats import wilson_interval

TIMING = {"steps_per_s", "wall_time_s"}


def small(tmp_path, **overrides) -> Config:
    values = dict(task="DynNav-MovingTarget-v1", reward_mode="distance", episodes=6, learning_starts=64,
                  batch_size=32, hidden_sizes=(32, 32), buffer_size=5000, checkpoint_every=3,
                  target_update_interval=50, epsilon_decay_episodes=4, runs_dir=str(tmp_path / "runs"),
                  progress=False, eval_after_training=False, seed=3)
    values.update(overrides)
    return make(**values).validate()


def rows(run_dir):
    with open(run_dir / "metrics.csv", newline="") as f:
        return [{k: v for k, v in r.items() if k not in TIMING} for r in csv.DictReader(f)]


def test_same_seed_same_losses_and_returns(tmp_path):
    a, b = rows(train(small(tmp_path, name="a"))), rows(train(small(tmp_path, name="b")))
    assert len(a) == 6
    assert any(r["loss"] for r in a), "the run made no update"
    assert a == b
    c = rows(train(small(tmp_path, name="c", seed=4)))
    assert [r["loss"] for r in c] != [r["loss"] for r in a]


def test_run_directory_contents(tmp_path):
    run = train(small(tmp_path, name="files"))
    assert run.name.startswith("DynNav-MovingTarget-v1__files__3__")
    for name in ("config.yaml", "metrics.csv", "checkpoint/meta.json", "checkpoint/weights.pt", "checkpoint/memory.npz",
                 "reward.png", "loss.png"):
        assert (run / name).is_file(), name
    assert load_yaml(run / "config.yaml") == small(tmp_path, name="files")
    assert [int(r["episode"]) for r in rows(run)] == list(range(6))
    assert not list(run.glob(".*")), "temporary files left behind"


def test_checkpoint_opens_with_standard_tools(tmp_path):
    """Weights with torch.load(weights_only=True), metadata with json, the replay memory with numpy."""
    run = train(small(tmp_path))
    meta = json.loads((run / "checkpoint" / "meta.json").read_text())
    assert (meta["format"], meta["version"], meta["episode"], meta["config"]["task"]) == (
        ckpt.FORMAT, ckpt.VERSION, 6, "DynNav-MovingTarget-v1")
    assert meta["global_step"] == sum(int(r["length"]) for r in rows(run))
    weights = torch.load(run / "checkpoint" / "weights.pt", weights_only=True)
    q = MLPQNetwork(20, 3, (32, 32))
    q.load_state_dict({k.removeprefix("learner.q."): v for k, v in weights.items() if k.startswith("learner.q.")})
    policy = load_policy(run)
    obs, _ = policy.env.reset(seed=0)
    with torch.no_grad():
        mine = q(torch.from_numpy(policy.features(obs))[None])[0].numpy()
    np.testing.assert_allclose(mine, policy.q_values(obs), rtol=1e-6)
    policy.env.close()
    with np.load(run / "checkpoint" / "memory.npz", allow_pickle=False) as memory:
        assert len(memory["memory.actions"]) == meta["global_step"]
    state = ckpt.load(run)
    assert state["learner"]["optimizer"]["state"][0]["step"] > 0
    assert state["rng"] == meta["rng"]


def test_leftovers_of_killed_writes_are_cleaned_up(tmp_path):
    run = train(small(tmp_path, episodes=3))
    (run / ".checkpoint.tmp-dead").mkdir()
    (run / ".checkpoint.tmp-dead" / "weights.pt").write_bytes(b"half")
    (run / ".config.yaml.x1.tmp").write_text("half")
    # killed between moving the old checkpoint aside and renaming the new one into place
    (run / "checkpoint").rename(run / ".checkpoint.old-1234")
    assert ckpt.load(run)["episode"] == 3  # put back
    main(["--resume", str(run), "--episodes", "4", "--no-progress", "--no-eval-after-training"])
    assert ckpt.load(run)["episode"] == 4
    assert sorted(p.name for p in run.iterdir() if p.name.startswith(".")) == []


def test_resume_continues_where_the_stopped_run_left_off(tmp_path):
    whole = rows(train(small(tmp_path, name="whole")))
    # a run stopped after its checkpoint at episode 3, with one more episode logged after it
    stopped = train(small(tmp_path, name="stopped", episodes=3))
    with open(stopped / "metrics.csv", "a") as f:
        f.write("3,999,1.0,5,0,1,0,,0.5,0.003,100.0,1.0\n")
    main(["--resume", str(stopped), "--episodes", "6", "--no-progress", "--no-eval-after-training"])
    resumed = rows(stopped)
    assert [int(r["episode"]) for r in resumed] == list(range(6))
    assert resumed == whole  # same losses, returns and epsilons as the run that never stopped
    assert ckpt.load(stopped)["episode"] == 6


def test_missing_and_corrupt_checkpoints_are_clear_errors(tmp_path):
    with pytest.raises(ckpt.CheckpointError, match="no checkpoint"):
        ckpt.load(tmp_path / "nothing")
    run = train(small(tmp_path, episodes=3))
    good = tmp_path / "good"
    shutil.copytree(run / "checkpoint", good)

    def broken(name, data: bytes):
        shutil.rmtree(run / "checkpoint")
        shutil.copytree(good, run / "checkpoint")
        (run / "checkpoint" / name).write_bytes(data)

    weights = (good / "weights.pt").read_bytes()
    broken("weights.pt", weights[: len(weights) // 2])
    with pytest.raises(ckpt.CheckpointError, match=r"weights.pt' is corrupt"):
        ckpt.load(run)
    with pytest.raises(SystemExit, match="weights.pt' is corrupt"):
        main(["--resume", str(run), "--no-progress"])
    broken("meta.json", b'{"format": "dynnav-dqn')
    with pytest.raises(ckpt.CheckpointError, match=r"meta.json' is corrupt"):
        ckpt.load(run)
    broken("memory.npz", b"PK\x03\x04 not a zip")
    with pytest.raises(ckpt.CheckpointError, match=r"memory.npz' is corrupt"):
        ckpt.load(run)
    tensors = torch.load(good / "weights.pt", weights_only=True)
    tensors["learner.q.layers.0.weight"][0, 0] = float("nan")
    torch.save(tensors, tmp_path / "nan.pt")
    broken("weights.pt", (tmp_path / "nan.pt").read_bytes())
    with pytest.raises(ckpt.CheckpointError, match="'learner.q.layers.0.weight' holds non-finite values"):
        ckpt.load(run)
    meta = json.loads((good / "meta.json").read_text())
    broken("meta.json", json.dumps(dict(meta, version=1)).encode())
    with pytest.raises(ckpt.CheckpointError, match="format version 1"):
        ckpt.load(run)
    broken("meta.json", json.dumps({"weights": [1, 2]}).encode())
    with pytest.raises(ckpt.CheckpointError, match="not a dynnav DQN checkpoint"):
        ckpt.load(run)
    old_run = tmp_path / "old_run"
    old_run.mkdir()
    (old_run / "checkpoint.pkl").write_bytes(pickle.dumps({"format": "dynnav-dqn-checkpoint", "version": 1}))
    for path in (old_run, old_run / "checkpoint.pkl"):
        with pytest.raises(ckpt.CheckpointError, match="older dynnav version .* never unpickles"):
            ckpt.load(path)
    with pytest.raises(SystemExit, match="no checkpoint"):
        main(["--eval", "--checkpoint", str(tmp_path / "missing"), "--no-eval-picture"])
    with pytest.raises(SystemExit, match="does not exist"):
        main(["--resume", str(tmp_path / "no_run")])


def test_resume_with_another_task_fails_before_writing_anything(tmp_path):
    run = train(small(tmp_path, episodes=3))
    before = {p.name: p.read_bytes() for p in run.iterdir() if p.is_file()}
    with pytest.raises(SystemExit, match=r"--task 'DynNav-MovingObstacles-v1' \(the run: 'DynNav-MovingTarget-v1'\)"):
        main(["--resume", str(run), "--task", "DynNav-MovingObstacles-v1", "--no-progress"])
    with pytest.raises(SystemExit, match=r"--hidden-sizes"):
        main(["--resume", str(run), "--hidden-sizes", "64", "--no-progress"])
    assert {p.name: p.read_bytes() for p in run.iterdir() if p.is_file()} == before
    main(["--resume", str(run), "--episodes", "4", "--no-progress", "--no-eval-after-training"])  # still resumable
    assert ckpt.load(run)["episode"] == 4


def test_wilson_interval():
    lo, hi = wilson_interval(100, 100)
    assert hi == pytest.approx(1.0) and lo == pytest.approx(0.963, abs=1e-3)
    lo, hi = wilson_interval(50, 100)
    assert (lo, hi) == (pytest.approx(0.4038, abs=1e-3), pytest.approx(0.5962, abs=1e-3))
    assert wilson_interval(0, 10)[0] == 0.0


def test_test_phase_reports_and_writes_results(tmp_path):
    run = train(small(tmp_path, episodes=3))
    summary = evaluate(run / "checkpoint", episodes=5, picture=False, verbose=False)
    result = json.loads((run / "eval.json").read_text())
    assert result["summary"] == summary and len(result["episodes"]) == 5
    assert [e["seed"] for e in result["episodes"]] == [1_000_000 + i for i in range(5)]
    rates = summary["success_rate"] + summary["collision_rate"] + summary["timeout_rate"]
    assert summary["terminated_rate"] == 0.0
    assert rates == pytest.approx(1.0)
    for e in result["episodes"]:
        assert 0.0 <= e["spl"] <= 1.0 and (e["spl"] > 0) == (e["outcome"] == "success")
        assert e["shortest_path"] > 3.0  # the targets are 4-6 m from the start area, less the 0.3 m radius
        assert len(e["trajectory"]) == e["steps"] + 1
    assert "success rate" in (run / "eval.md").read_text()
    again = evaluate(run, episodes=5, picture=False, verbose=False)  # run directory works too
    assert again == summary
    # epsilon > 0: random actions drawn from the episode's seed, results in their own folder
    out = tmp_path / "eps"
    noisy = [evaluate(run, episodes=5, picture=False, verbose=False, epsilon=1.0, out_dir=out) for _ in range(2)]
    assert noisy[0] == noisy[1] and noisy[0]["epsilon"] == 1.0
    assert json.loads((run / "eval.json").read_text())["summary"] == summary  # the greedy test is kept
    random_paths = [e["trajectory"] for e in json.loads((out / "eval.json").read_text())["episodes"]]
    assert random_paths != [e["trajectory"] for e in result["episodes"]]
    assert "epsilon 1" in (out / "eval.md").read_text()


def test_a_crowd_tests_report_gives_its_social_metrics(tmp_path):
    """A navigator tested among pedestrians: each episode's social metrics in eval.json, their
    aggregate in the summary (discomfort pooled over the steps) and as rows of eval.md."""
    run = train(small(tmp_path, task="DynNav-Crowd-v1", episodes=2, task_kwargs={"humans": 5}))
    summary = evaluate(run, episodes=4, picture=False, verbose=False)
    episodes = json.loads((run / "eval.json").read_text())["episodes"]
    social = summary["social"]
    pooled = sum(e["discomfort_frequency"] * e["steps"] for e in episodes) / sum(e["steps"] for e in episodes)
    assert social["discomfort_frequency"] == pytest.approx(pooled, abs=1e-4)
    assert social["human_collision_rate"] == pytest.approx(np.mean([e["human_collision"] for e in episodes]))
    assert all(e["human_collision"] <= (e["outcome"] == "collision") for e in episodes)
    assert social["min_human_distance"] == pytest.approx(np.mean([e["min_human_distance"] for e in episodes]), abs=1e-4)
    report = (run / "eval.md").read_text()
    assert "discomfort frequency (a human within 0.2 m)" in report and "human collision rate" in report
    # a task without pedestrians keeps its report as it was
    plain = evaluate(train(small(tmp_path / "plain", episodes=1)), episodes=2, picture=False, verbose=False)
    assert "social" not in plain


class Corridor(gym.Env):
    """Walk right along 5 cells; the last cell terminates (if ``goal``), else only time runs out."""

    observation_space = gym.spaces.Box(0.0, 4.0, (1,), np.float32)
    action_space = gym.spaces.Discrete(2)

    def __init__(self, goal: bool = True):
        self.goal = goal

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x = 0
        return np.array([self.x], np.float32), {}

    def step(self, action):
        self.x = min(self.x + 1, 4) if action == 1 else max(self.x - 1, 0)
        done = self.goal and self.x == 4
        return np.array([self.x], np.float32), 1.0 if done else 0.0, done, False, {"success": done}


gym.register("test/Corridor-v0", entry_point=Corridor, max_episode_steps=8, kwargs={"goal": True})
gym.register("test/CorridorNoGoal-v0", entry_point=Corridor, max_episode_steps=8, kwargs={"goal": False})


def test_terminations_stop_bootstrapping_and_timeouts_do_not(tmp_path):
    """Any gymnasium env with Discrete actions trains; a timeout (truncation) is stored as not done."""
    common = dict(episodes=6, learning_starts=8, batch_size=8, hidden_sizes=(8,), checkpoint_every=6,
                  runs_dir=str(tmp_path), progress=False, eval_after_training=False, epsilon_start=1.0,
                  normalize_obs=False)
    memory = ckpt.load(train(make(task="test/CorridorNoGoal-v0", **common)))["memory"]
    assert memory["size"] == 6 * 8 and memory["not_done"].min() == 1.0
    memory = ckpt.load(train(make(task="test/Corridor-v0", **common)))["memory"]
    ended = memory["not_done"] == 0.0
    assert ended.any()
    np.testing.assert_array_equal(memory["next_obs"][ended, 0], 4.0)  # exactly the steps onto the goal
    assert (memory["not_done"][memory["next_obs"][:, 0] != 4.0] == 1.0).all()


def test_trajectory_picture(tmp_path):
    """The test trajectories are drawn on the task's own top-down render (about 15 s: the first render)."""
    from PIL import Image

    from agents.training.test_report import OUTCOME_COLORS

    run = train(small(tmp_path, episodes=2))
    evaluate(run, episodes=4, picture=True, verbose=False)
    img = np.asarray(Image.open(run / "trajectories.png").convert("RGB"))
    assert img.shape == (512, 512, 3)
    result = json.loads((run / "eval.json").read_text())
    arena = img[60:].astype(int)  # below the legend's colour swatches
    for outcome in {e["outcome"] for e in result["episodes"]}:
        color = np.array(OUTCOME_COLORS[outcome])
        assert (np.abs(arena - color).sum(axis=2) == 0).sum() > 20, f"no {outcome} path drawn"
    absent = set(OUTCOME_COLORS) - {e["outcome"] for e in result["episodes"]}
    for outcome in absent:
        assert (np.abs(arena - np.array(OUTCOME_COLORS[outcome])).sum(axis=2) == 0).sum() == 0
    assert img.reshape(-1, 3).std(axis=0).min() > 10  # a real render under the paths, not a blank canvas


def test_a_users_q_network_named_in_the_config_trains_and_reloads(tmp_path):
    """q_network: 'package.module:factory' plugs any module in; here the dueling example learns the corridor."""
    from agents.core.networks import DuelingMLP

    config = make(task="test/Corridor-v0", q_network="agents.core.networks:dueling_mlp", episodes=40, learning_starts=16,
                  batch_size=16, checkpoint_every=40, target_update_interval=20, epsilon_start=1.0, epsilon_end=0.1,
                  epsilon_decay_episodes=20, learning_rate=0.003, runs_dir=str(tmp_path), progress=False,
                  eval_after_training=False, normalize_obs=False)
    run = train(config)
    policy = load_policy(run)
    assert isinstance(policy.q_network, DuelingMLP)
    policy.env.close()
    summary = evaluate(run, episodes=3, verbose=False)
    assert summary["success_rate"] == 1.0 and summary["avg_steps_success"] == 4  # straight to the goal
    with pytest.raises(SystemExit, match="q_network 'agents.core.networks:nothing': agents.core.networks has no function"):
        main(["--task", "test/Corridor-v0", "--q-network", "agents.core.networks:nothing", "--runs-dir", str(tmp_path)])
