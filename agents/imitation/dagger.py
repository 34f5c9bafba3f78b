"""Teacher-student learning: behaviour cloning on the planner's episodes, then DAgger.

    python -m agents.imitation --config configs/imitation/generalist.yaml

``train`` reads top to bottom. Check everything and build the student (the training config's
Q-network and the features that scale its observations). Then, round by round:

1. play episodes on the collector's processes, every state labelled by the teacher (the
   full-state planner). Round 0: the teacher drives (``teacher_episodes``). Round i >= 1
   (DAgger): the teacher's action is taken with probability ``beta_decay ** i``, else the
   student's (``round_episodes``), so the data holds the states the student itself reaches;
2. add them to the aggregated data (every round's episodes are kept);
3. fit the student to every label so far (``fit.py``; it continues from its last weights, or
   with ``fresh_fit`` starts anew), holding out every ``validation_every``-th episode and keeping
   the epoch that agrees best with their labels;
4. write the round: a row of ``rounds.csv``, the data (``demonstrations.npz``), the student as a
   DQN checkpoint (``checkpoint/``: ``agents.dqn --eval --checkpoint <run>`` tests it and
   ``agents.dqn --init-from <run>`` fine-tunes it) and the round reached (``imitation.json``).

A killed run continues from its last finished round (``--resume <run>``). At the end the data
is also written as a Minari data set (``dataset/``, ``offline_dataset.py``), the student takes the
test phase its training config sets (``eval.json``, ``tests/``), and ``sweep_run.json`` makes the
run a row of the run table (``record.py``: experiment ``<name>-dagger``, training time the rounds').

The run directory ``runs/imitation/<task>__<name>__<seed>__<time>/`` holds ``imitation.yaml``
(these settings), ``config.yaml`` (the student's), and the files above.
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import io
import json
import time
from pathlib import Path

import numpy as np
import torch
import yaml
from gymnasium.envs.registration import EnvSpec

from agents.core.policy import build_q_network
from agents.files import atomic_write_bytes
from agents.imitation.collector import Collector
from agents.imitation.config import ImitationConfig
from agents.core.demonstrations import Demonstrations
from agents.imitation.fit import fit_rollouts
from agents.imitation.offline_dataset import dataset_bytes, write_minari
from agents.imitation.record import write_metrics, write_record
from agents.training import checkpoint as ckpt
from agents.training.config import Config
from agents.training.config_io import config_from_dict, load_yaml, save_yaml, to_yaml_dict
from agents.training.envs import is_dynnav, make_env_from
from agents.training.experience import make_features
from agents.training.run_dir import episode_seed, new_run_dir
from agents.training.run_lock import RunDirLock
from agents.training.test_phase import evaluate_as_configured
from agents.training.tensorboard_log import TensorBoardLog
from agents.training.threads import limit_threads

STATE_FILE, SETTINGS_FILE, ROUNDS_FILE, DATA_FILE, DATASET_DIR = (
    "imitation.json", "imitation.yaml", "rounds.csv", "demonstrations.npz", "dataset")
ROUND_COLUMNS = ("round", "beta", "episodes", "success", "collision", "timeout", "states", "label_ms", "fit_loss",
                 "train_accuracy", "validation_accuracy", "seconds")
ROUND_STRIDE = 1_000_000
"""episode k of round r plays seed ``episode_seed(seed, r * ROUND_STRIDE + k)``"""


def student_config(cfg: ImitationConfig) -> Config:
    """The student's training config with this run's seed and name; ValueError if the teacher
    cannot label its task (a dynnav task on the discrete drive, a state-vector observation)."""
    config = load_yaml(cfg.student)
    config = dataclasses.replace(config, seed=cfg.seed, name=cfg.name or config.name,
                                 run=dataclasses.replace(config.run, runs_dir=cfg.runs_dir))
    config.validate()
    if not is_dynnav(config.task):
        raise ValueError(f"{cfg.student}: the teacher (the full-state planner) plans in dynnav tasks; task "
                         f"{config.task!r} is not one")
    if config.camera.camera_frames or config.env.state_frames != 1:
        raise ValueError(f"{cfg.student}: the student reads one state vector per step (no camera_frames or "
                         f"state_frames > 1 yet; recurrent remembers the steps before)")
    if config.env.task_kwargs.get("control_mode", "discrete_drive") != "discrete_drive":
        raise ValueError(f"{cfg.student}: the teacher drives the discrete drive; control_mode must be discrete_drive")
    return config


def _split(data: Demonstrations, every: int) -> tuple[list, list]:
    """(fitted rollouts, held-out rollouts): every ``every``-th episode held out (none with 0)."""
    fitted, held = [], []
    for i, r in enumerate(data.rollouts):
        (held if every and i % every == every - 1 else fitted).append(r)
    return fitted, held


def saved_settings(run_dir: str | Path) -> dict:
    """The settings an imitation run was started with (its imitation.yaml), for ``--resume``; ValueError
    if ``run_dir`` is not an imitation run."""
    path = Path(run_dir) / SETTINGS_FILE
    if not path.is_file():
        raise ValueError(f"--resume {run_dir}: not an imitation run directory (no {SETTINGS_FILE})")
    values = yaml.safe_load(path.read_text())
    values["resume"] = str(run_dir)
    return values


def _resume(cfg: ImitationConfig, cleanup: contextlib.ExitStack):
    """(run directory, student config, data, next round) of the run ``cfg.resume`` names, locked."""
    run_dir = Path(cfg.resume)
    if not (run_dir / STATE_FILE).is_file():
        raise ValueError(f"--resume {cfg.resume}: not an imitation run directory (no {STATE_FILE})")
    cleanup.enter_context(RunDirLock(run_dir))
    state = json.loads((run_dir / STATE_FILE).read_text())
    config = config_from_dict(yaml.safe_load((run_dir / "config.yaml").read_text()), source=str(run_dir / "config.yaml"))
    return run_dir, config, Demonstrations.load(run_dir / DATA_FILE), int(state["round"]) + 1


def train(cfg: ImitationConfig) -> Path:
    """Run (or continue) the teacher-student run ``cfg`` describes; return its run directory."""
    limit_threads(1)
    with contextlib.ExitStack() as cleanup:
        # --- checks and the student, before any file is written
        cfg.validate()
        if cfg.resume:  # cfg: the run's imitation.yaml with what the caller changed (e.g. more rounds)
            run_dir, config, data, start = _resume(cfg, cleanup)
            atomic_write_bytes(run_dir / SETTINGS_FILE, yaml.safe_dump(
                {**dataclasses.asdict(cfg), "resume": None}, sort_keys=False).encode())
        else:
            config, data, start, run_dir = student_config(cfg), Demonstrations(), 0, None
        env = make_env_from(config)
        cleanup.callback(env.close)
        features = make_features(env, config)
        net = build_q_network(config, features.input_specs, int(env.action_space.n))
        if run_dir is not None:
            net.load_state_dict(ckpt.load(run_dir, memory=False)["learner"]["q"])
        if run_dir is None:
            run_dir = new_run_dir(config)
            cleanup.enter_context(RunDirLock(run_dir))
            atomic_write_bytes(run_dir / SETTINGS_FILE, yaml.safe_dump(dataclasses.asdict(cfg), sort_keys=False).encode())
            save_yaml(config, run_dir / "config.yaml")
        print(f"imitation run: {run_dir} (rounds {start} to {cfg.rounds})")

        # --- the rounds
        board = TensorBoardLog(run_dir) if cfg.tensorboard else None
        if board is not None:
            cleanup.callback(board.close)
        epochs_done = start * cfg.epochs  # the x axis of the imitation loss: epochs over every fit
        collector = cleanup.enter_context(Collector(to_yaml_dict(config), cfg.workers, cfg.teacher_human_margin))
        for round_ in range(start, cfg.rounds + 1):
            t0 = time.perf_counter()
            beta, n = cfg.beta(round_), cfg.teacher_episodes if round_ == 0 else cfg.round_episodes
            jobs = [(episode_seed(cfg.seed, round_ * ROUND_STRIDE + k), beta) for k in range(n)]
            rollouts = collector.play(jobs, None if round_ == 0 else net.state_dict(), progress=cfg.progress,
                                      description=f"round {round_} (beta {beta:.2f})")
            data.add(rollouts, round_)
            fitted, held = _split(data, cfg.validation_every)
            if cfg.fresh_fit:  # a new network, the same start every round (the config's seed)
                net = build_q_network(config, features.input_specs, int(env.action_space.n))

            def on_epoch(loss: float) -> None:
                nonlocal epochs_done
                epochs_done += 1
                if board is not None:
                    board.scalars(epochs_done, {"imitation/loss": loss})

            report = fit_rollouts(net, features, fitted, held, cfg.epochs, cfg.batch_size, cfg.learning_rate,
                                  np.random.default_rng([cfg.seed, round_]), on_epoch)
            outcomes = [r.outcome for r in rollouts]
            labels = sum(r.steps for r in rollouts)
            row = dict(round=round_, beta=round(beta, 4), episodes=n, success=outcomes.count("success") / n,
                       collision=outcomes.count("collision") / n, timeout=outcomes.count("timeout") / n,
                       states=len(data), label_ms=1000 * sum(r.label_seconds for r in rollouts) / max(labels, 1),
                       fit_loss=report.loss, train_accuracy=report.train_accuracy,
                       validation_accuracy=report.validation_accuracy, seconds=time.perf_counter() - t0)
            _write_round(run_dir, config, data, net, features, int(env.action_space.n), row)
            if board is not None:
                board.scalars(round_, {"imitation/dagger_iteration": round_, "imitation/beta": beta,
                                       "imitation/success": row["success"], "imitation/states": len(data),
                                       "imitation/train_accuracy": report.train_accuracy,
                                       "imitation/validation_accuracy": report.validation_accuracy})
                board.flush()
            unseen = "" if report.validation_accuracy is None else f", held-out {report.validation_accuracy:.3f}"
            print(f"round {round_}: {n} episodes at beta {beta:.2f}: success {row['success']:.0%}; "
                  f"{len(data)} states; accuracy {report.train_accuracy:.3f}{unseen}; {row['seconds']:.0f} s")

        if cfg.dataset:
            spec = EnvSpec(**_spec_fields(env, config))
            folder = write_minari(data.rollouts, run_dir / DATASET_DIR, spec, env.observation_space, env.action_space,
                                  description=f"{len(data.rollouts)} episodes of {config.task} "
                                              f"{config.env.task_kwargs}, labelled by the full-state planner")
            print(f"Minari data set: {folder} ({len(data.rollouts)} episodes, {len(data)} states, "
                  f"{dataset_bytes(folder) / 1e6:.1f} MB)")
    # --- the student's test phase, as a DQN run's (eval.json, tests/), once the run directory is unlocked
    t0 = time.perf_counter()
    if config.test.eval_after_training:
        evaluate_as_configured(config, run_dir, only_missing=True, verbose=False)
    with open(run_dir / ROUNDS_FILE, newline="") as f:
        train_s = sum(float(r["seconds"]) for r in csv.DictReader(f))
    write_record(run_dir, f"{config.name}-dagger", train_s=train_s, eval_s=time.perf_counter() - t0,
                 workers=cfg.workers, episodes=len(data.rollouts), states=len(data))
    return run_dir


def _spec_fields(env, config: Config) -> dict:
    """The fields of a gymnasium spec that makes the student's task as the episodes saw it (the
    plain env, its options included) from a string entry point, as Minari stores it."""
    kwargs = {**env.spec.kwargs, "task_id": config.task}  # the options the task was made with
    return dict(id=config.task, entry_point="dynnav_tasks.registration:make_plain_task", kwargs=kwargs)


def _write_round(run_dir: Path, config: Config, data: Demonstrations, net, features, n_actions: int,
                 row: dict) -> None:
    """A finished round's files: data, student checkpoint, rounds.csv row, then the round reached."""
    atomic_write_bytes(run_dir / DATA_FILE, data.to_npz())
    episodes = len(data.rollouts)
    ckpt.save(run_dir, dict(
        config=to_yaml_dict(config), episode=episodes, global_step=len(data), wall_time_s=0.0,
        input_shapes=[list(shape) for shape, _ in features.input_specs], n_actions=n_actions,
        learner=dict(q={k: v.detach().clone() for k, v in net.state_dict().items()}),
    ))
    rows = []
    if (run_dir / ROUNDS_FILE).is_file() and row["round"] > 0:
        with open(run_dir / ROUNDS_FILE, newline="") as f:
            rows = [r for r in csv.DictReader(f) if int(r["round"]) < row["round"]]
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=ROUND_COLUMNS)
    writer.writeheader()
    writer.writerows(rows + [{k: row[k] for k in ROUND_COLUMNS}])
    atomic_write_bytes(run_dir / ROUNDS_FILE, buffer.getvalue().encode())
    write_metrics(run_dir, data.rollouts, data.rounds, rows + [{k: str(v) for k, v in row.items()}])
    atomic_write_bytes(run_dir / STATE_FILE, json.dumps(dict(round=row["round"], episodes=episodes,
                                                             states=len(data))).encode())
