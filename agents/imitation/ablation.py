"""What the student's observation and encoders are worth: students fitted on one labelled data set.

    python -m agents.imitation.ablation --config configs/imitation/ablation.yaml --data runs/imitation/<run>

Every row of the ablation learns from the same teacher: the labelled episodes of one imitation
run (its ``demonstrations.npz``, from round 0 and every DAgger round). A row changes what the
student reads or how it encodes it (``variants`` in the config: task options such as
``laser_rays`` or ``way``, and ``dqn`` settings such as ``laser_encoder``); the episodes are seen
again through the row's sensors (``reobserve.py``: same seeds, same actions, same labels), a
student is fitted from scratch for each seed, and the DQN test phase tests it greedily on the
config's ``test_on`` worlds. Each row-seed is a run directory under ``runs_dir`` that
``python -m agents.study.table add`` records, named ``<experiment>-<variant>``; its training
time is the re-observation and the fit (the teacher's labels are the data run's, shared by all).

A finished row-seed (its ``eval.json`` written) is skipped when the command runs again.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
import yaml

from agents.core.demonstrations import Demonstrations
from agents.core.policy import build_q_network
from agents.files import atomic_write_bytes
from agents.imitation.fit import fit_rollouts
from agents.imitation.record import write_record
from agents.imitation.reobserve import reobserve
from agents.training import checkpoint as ckpt
from agents.training.config import Config
from agents.training.config_io import config_from_dict, save_yaml, to_yaml_dict
from agents.training.envs import make_env_from
from agents.training.experience import make_features
from agents.training.test_phase import evaluate
from agents.training.threads import limit_threads

HELD_OUT = 10
"""every this many-th episode is held out of a row's fit, to keep its best epoch (early stopping)"""
KEYS = ("description", "experiment", "seeds", "epochs", "batch_size", "learning_rate", "test_on", "test_episodes",
        "variants")


def read_config(path: str | Path) -> dict:
    """The ablation's settings; ValueError naming what is wrong."""
    values = yaml.safe_load(Path(path).read_text()) or {}
    unknown = sorted(set(values) - set(KEYS))
    if unknown:
        raise ValueError(f"{path}: unknown setting(s) {', '.join(unknown)}; settings: {', '.join(KEYS)}")
    missing = [k for k in KEYS if k not in values]
    if missing:
        raise ValueError(f"{path}: missing setting(s) {', '.join(missing)}")
    for name, changes in values["variants"].items():
        if not isinstance(changes, dict) or set(changes) - {"task_kwargs", "dqn"}:
            raise ValueError(f"{path}: variant {name!r} may change task_kwargs and dqn only")
    return values


def variant_config(base: Config, experiment: str, name: str, changes: dict, seed: int) -> Config:
    """The data run's student config with a variant's changes, as the row's own run config."""
    values = to_yaml_dict(base)
    values["env"]["task_kwargs"] = {**values["env"]["task_kwargs"], **changes.get("task_kwargs", {})}
    values["dqn"] = {**values["dqn"], **changes.get("dqn", {})}
    values.update(name=f"{experiment}-{name}", seed=seed, episodes=base.episodes)
    return config_from_dict(values, source=f"variant {name!r}").validate()


def run_variant(data: Demonstrations, base: Config, settings: dict, name: str, runs_dir: Path, progress: bool) -> None:
    """Every seed of one variant: re-observe (once), fit, test, record."""
    changes = settings["variants"][name]
    seeds = range(1, int(settings["seeds"]) + 1)
    todo = [s for s in seeds if not (runs_dir / f"{name}__{s}" / "eval.json").is_file()]
    if not todo:
        return
    t0 = time.perf_counter()
    probe = variant_config(base, settings["experiment"], name, changes, todo[0])
    rollouts = data.rollouts if changes.get("task_kwargs") in (None, {}) else reobserve(data.rollouts, probe, progress)
    states = sum(r.steps for r in rollouts)
    reobserve_s = time.perf_counter() - t0
    for seed in todo:
        config = variant_config(base, settings["experiment"], name, changes, seed)
        run_dir = runs_dir / f"{name}__{seed}"
        run_dir.mkdir(parents=True, exist_ok=True)
        env = make_env_from(config)
        try:
            features = make_features(env, config)
            t1 = time.perf_counter()
            net = build_q_network(config, features.input_specs, int(env.action_space.n))
            fitted = [r for i, r in enumerate(rollouts) if i % HELD_OUT != HELD_OUT - 1]
            held = [r for i, r in enumerate(rollouts) if i % HELD_OUT == HELD_OUT - 1]
            report = fit_rollouts(net, features, fitted, held, int(settings["epochs"]), int(settings["batch_size"]),
                                  float(settings["learning_rate"]), np.random.default_rng([seed, 7]))
            fit_s = time.perf_counter() - t1
            save_yaml(config, run_dir / "config.yaml")
            ckpt.save(run_dir, dict(config=to_yaml_dict(config), episode=len(data.rollouts), global_step=states,
                                    wall_time_s=0.0, input_shapes=[list(s) for s, _ in features.input_specs],
                                    n_actions=int(env.action_space.n),
                                    learner=dict(q={k: v.detach().clone() for k, v in net.state_dict().items()})))
        finally:
            env.close()
        t2 = time.perf_counter()
        first, *others = settings["test_on"]
        for options in others:
            evaluate(run_dir, episodes=settings["test_episodes"], picture=False, verbose=False,
                     out_dir=run_dir / "tests" / options, task_kwargs=_options(options))
        evaluate(run_dir, episodes=settings["test_episodes"], picture=False, verbose=False, task_kwargs=_options(first))
        write_record(run_dir, f"{settings['experiment']}-{name}", train_s=reobserve_s + fit_s,
                     eval_s=time.perf_counter() - t2, fit_accuracy=round(report.train_accuracy, 4),
                     held_out_accuracy=round(report.validation_accuracy, 4), best_epoch=report.best_epoch,
                     states=states)
        print(f"{name} seed {seed}: accuracy {report.train_accuracy:.3f}, held out {report.validation_accuracy:.3f} "
              f"(epoch {report.best_epoch}), fit {fit_s:.0f} s (+ {reobserve_s:.0f} s re-observing)")


def _options(entry: str) -> dict:
    from dynnav_tasks.task_options import parse_task_options

    return parse_task_options(entry)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", required=True, help="the ablation's settings (configs/imitation/ablation.yaml)")
    parser.add_argument("--data", required=True, help="an agents.imitation run directory: its labelled episodes")
    parser.add_argument("--runs-dir", default="runs/ablation", help="where each row-seed's run directory goes")
    parser.add_argument("--only", nargs="*", default=None, help="only these variants")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    limit_threads(1)
    try:
        settings = read_config(args.config)
        data_dir = Path(args.data)
        base = config_from_dict(yaml.safe_load((data_dir / "config.yaml").read_text()), source=str(data_dir))
        names = args.only or list(settings["variants"])
        unknown = sorted(set(names) - set(settings["variants"]))
        if unknown:
            raise ValueError(f"--only: no variant(s) {', '.join(unknown)} in {args.config}")
        data = Demonstrations.load(data_dir / "demonstrations.npz")
        runs_dir = Path(args.runs_dir)
        runs_dir.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(runs_dir / "ablation.yaml", yaml.safe_dump(dict(settings, data=str(data_dir))).encode())
        for name in names:
            run_variant(data, base, settings, name, runs_dir, not args.no_progress)
    except ValueError as err:
        raise SystemExit(f"error: {err}")


if __name__ == "__main__":
    main()
