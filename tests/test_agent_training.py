"""Training runs: reproducibility, checkpoints, resuming a stopped run, the test phase."""

import csv
import json
import pickle

import gymnasium as gym
import numpy as np
import pytest

from agents import checkpoint as ckpt
from agents.config import Config, load_yaml
from agents.dqn import main, train
from agents.evaluate import evaluate, wilson_interval
from agents.qnetwork import QLearner
from agents.replay import ReplayMemory

TIMING = {"steps_per_s", "wall_time_s"}


def small(tmp_path, **overrides) -> Config:
    values = dict(task="DynNav-MovingTarget-v1", reward_mode="distance", episodes=6, learning_starts=64,
                  batch_size=32, hidden_sizes=(32, 32), buffer_size=5000, checkpoint_every=3,
                  target_update_interval=50, epsilon_decay_episodes=4, runs_dir=str(tmp_path / "runs"),
                  progress=False, eval_after_training=False, seed=3)
    values.update(overrides)
    return Config(**values).validate()


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
    for name in ("config.yaml", "metrics.csv", "checkpoint.pkl", "reward.png", "loss.png"):
        assert (run / name).is_file(), name
    assert load_yaml(run / "config.yaml") == small(tmp_path, name="files")
    assert [int(r["episode"]) for r in rows(run)] == list(range(6))
    assert not list(run.glob(".*tmp*")), "temporary files left behind"


def test_checkpoint_round_trip(tmp_path):
    run = train(small(tmp_path))
    state = ckpt.load(run)
    assert (state["episode"], state["config"]["episodes"]) == (6, 6)
    assert state["global_step"] == sum(int(r["length"]) for r in rows(run))
    learner = QLearner(state["obs_dim"], state["n_actions"], (32, 32), 32, rng=np.random.default_rng(0))
    learner.load_state_dict(state["learner"])
    memory = ReplayMemory(5000, state["obs_dim"])
    memory.load_state_dict(state["memory"])
    again = dict(state, learner=learner.state_dict(), memory=memory.state_dict())
    ckpt.save(tmp_path / "copy.pkl", again)
    copy = ckpt.load(tmp_path / "copy.pkl")
    for key in ("q", "target", "adam_m", "adam_v"):
        np.testing.assert_array_equal(copy["learner"][key], state["learner"][key])
    assert copy["learner"]["adam_step"] == state["learner"]["adam_step"] > 0
    np.testing.assert_array_equal(copy["memory"]["obs"], state["memory"]["obs"])
    assert len(memory) == state["global_step"]
    assert copy["rng"] == state["rng"]


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


def test_missing_and_corrupt_checkpoints_are_clear_errors(tmp_path, capsys):
    with pytest.raises(ckpt.CheckpointError, match="no checkpoint"):
        ckpt.load(tmp_path / "nothing.pkl")
    run = train(small(tmp_path, episodes=3))
    data = (run / "checkpoint.pkl").read_bytes()
    (run / "checkpoint.pkl").write_bytes(data[: len(data) // 2])
    with pytest.raises(ckpt.CheckpointError, match="corrupt"):
        ckpt.load(run)
    with pytest.raises(SystemExit, match="corrupt"):
        main(["--resume", str(run), "--no-progress"])
    (tmp_path / "other.pkl").write_bytes(pickle.dumps({"weights": [1, 2]}))
    with pytest.raises(ckpt.CheckpointError, match="not a dynnav DQN checkpoint"):
        ckpt.load(tmp_path / "other.pkl")
    with pytest.raises(SystemExit, match="no checkpoint"):
        main(["--eval", "--checkpoint", str(tmp_path / "missing"), "--no-eval-picture"])
    with pytest.raises(SystemExit, match="does not exist"):
        main(["--resume", str(tmp_path / "no_run")])


def test_wilson_interval():
    lo, hi = wilson_interval(100, 100)
    assert hi == pytest.approx(1.0) and lo == pytest.approx(0.963, abs=1e-3)
    lo, hi = wilson_interval(50, 100)
    assert (lo, hi) == (pytest.approx(0.4038, abs=1e-3), pytest.approx(0.5962, abs=1e-3))
    assert wilson_interval(0, 10)[0] == 0.0


def test_test_phase_reports_and_writes_results(tmp_path):
    run = train(small(tmp_path, episodes=3))
    summary = evaluate(run / "checkpoint.pkl", episodes=5, picture=False, verbose=False)
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
    memory = ckpt.load(train(Config(task="test/CorridorNoGoal-v0", **common)))["memory"]
    assert memory["size"] == 6 * 8 and memory["not_done"].min() == 1.0
    memory = ckpt.load(train(Config(task="test/Corridor-v0", **common)))["memory"]
    ended = memory["not_done"] == 0.0
    assert ended.any()
    np.testing.assert_array_equal(memory["next_obs"][ended, 0], 4.0)  # exactly the steps onto the goal
    assert (memory["not_done"][memory["next_obs"][:, 0] != 4.0] == 1.0).all()


def test_trajectory_picture(tmp_path):
    """The test trajectories are drawn on the task's own top-down render (about 15 s: the first render)."""
    from PIL import Image

    from agents.evaluate import OUTCOME_COLORS

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
