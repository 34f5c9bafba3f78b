"""Reinforcement learning on top of a teacher: the cloned student as the start, its demonstrations kept.

An ``agents.imitation`` run leaves a student (a DQN checkpoint) and the teacher's labelled
episodes (``demonstrations.npz``). A DQN run fine-tunes them (``demos`` settings):

* ``init_from``: the run's online and target networks start as that checkpoint's Q-network;
* ``demonstrations``: the labelled episodes become a ``DemoReplay`` that fills ``demo_share``
  of every minibatch, the learner adding DQfD's large-margin loss on their labels
  (``DQNLearner.margin_weight``), and ``pretrain_updates`` updates on them alone come before the
  first episode (DQfD's pre-training: the Q-values learn the rewards' scale while the margin
  keeps the teacher's choices).

Either may name its run with a pattern: ``{seed}`` becomes the run's seed and ``*`` matches as in
a shell, the newest match (the run directories' names end in their start time) taken, so that
one config serves every seed of a sweep: ``runs/imitation/DynNav-Procedural-v1__generalist__{seed}__*``.
Both are read and checked before a run directory is made. The demonstrations must have been
gathered in this run's task with its observation (the same state size and task options but
for the worlds drawn) and its reward, or the stored rewards would teach another problem.
"""

from __future__ import annotations

import glob
from pathlib import Path
from typing import Optional

import numpy as np
import yaml

from agents.core.demo_replay import DemoReplay
from agents.core.demonstrations import Demonstrations
from agents.core.learner import DQNLearner
from agents.training import checkpoint as ckpt
from agents.training.config import Config

DATA_FILE = "demonstrations.npz"
"""the labelled episodes in an ``agents.imitation`` run directory"""
WORLD_OPTIONS = ("difficulty", "split")
"""task options that only choose which worlds are drawn: demonstrations may differ in them"""


def teacher_run(pattern: str, seed: int, setting: str) -> Path:
    """The folder ``pattern`` names for a run of ``seed`` (see the module docstring); ValueError if none."""
    path = pattern.replace("{seed}", str(seed))
    if not any(c in path for c in "*?["):
        return Path(path)
    matches = sorted(glob.glob(path))
    if not matches:
        raise ValueError(f"{setting}: no folder matches {path!r} (from {pattern!r}); run the teacher first, e.g. "
                         f"python -m agents.imitation --config configs/imitation/generalist.yaml --seed {seed}")
    return Path(matches[-1])


def start_weights(config: Config) -> Optional[dict]:
    """The Q-network weights ``demos.init_from`` names (None without it)."""
    source = config.demos.init_from
    if not source:
        return None
    return ckpt.load(teacher_run(source, config.seed, "init_from"), memory=False)["learner"]["q"]


def load_demonstrations(config: Config, features) -> Optional[DemoReplay]:
    """A ``DemoReplay`` of the ``demos.demonstrations`` run's episodes, observations turned into
    this run's network inputs by ``features`` (None without it); ValueError if they do not fit."""
    t = config.demos
    if not t.demonstrations:
        return None
    folder = teacher_run(t.demonstrations, config.seed, "demonstrations")
    if not (folder / DATA_FILE).is_file() or not (folder / "config.yaml").is_file():
        raise ValueError(f"demonstrations: {str(folder)!r} is not an agents.imitation run directory (it needs "
                         f"{DATA_FILE} and config.yaml)")
    theirs = yaml.safe_load((folder / "config.yaml").read_text())
    _check_same_problem(config, theirs, folder)
    data = Demonstrations.load(folder / DATA_FILE).transitions()
    width = features.input_specs[0][0][0]
    if data["obs"].shape[1] != width:
        raise ValueError(f"demonstrations: the states in {str(folder)!r} hold {data['obs'].shape[1]} values, this "
                         f"run's {width}")
    return DemoReplay(features(data["obs"]).astype(np.float32), features(data["next_obs"]).astype(np.float32),
                      data["actions"], data["rewards"], data["not_done"], data["labels"], share=t.demo_share)


def _check_same_problem(config: Config, theirs: dict, folder: Path) -> None:
    env = theirs.get("env", {})
    ours = {k: v for k, v in config.env.task_kwargs.items() if k not in WORLD_OPTIONS}
    their_options = {k: v for k, v in (env.get("task_kwargs") or {}).items() if k not in WORLD_OPTIONS}
    differences = [name for name, a, b in (
        ("task", theirs.get("task"), config.task),
        ("reward_mode", env.get("reward_mode"), config.env.reward_mode),
        ("reward_params", env.get("reward_params") or {}, dict(config.env.reward_params)),
        ("task_kwargs", their_options, ours),
    ) if a != b]
    if differences:
        raise ValueError(f"demonstrations: {str(folder)!r} was gathered with other {', '.join(differences)} than this "
                         f"run's (see its config.yaml); its rewards and states would teach another problem")


def initialise(learner: DQNLearner, config: Config, weights: Optional[dict], demos: Optional[DemoReplay]) -> None:
    """A new run's start: the networks from ``weights``, then ``pretrain_updates`` updates on the
    demonstrations alone (their own generator, so the run's stays as without them)."""
    if weights is not None:
        try:
            learner.q.load_state_dict(weights)
        except RuntimeError as err:
            raise ValueError(f"init_from {config.demos.init_from!r}: its Q-network does not fit this run's: {err}") from err
        learner.update_target()
    if demos is not None and config.demos.pretrain_updates:
        rng = np.random.default_rng(np.random.SeedSequence([config.seed, 2]))
        for _ in range(config.demos.pretrain_updates):
            demos.sample_into(learner.batch, rng, rows=learner.batch.size)
            learner.update()
            if config.dqn.target_update == "soft":
                learner.update_target(config.dqn.tau)
        learner.update_target()
