"""Export a finished run as a pretrained model: its Q-network (and auto-encoder) as
safetensors, its resolved config, and a card with the test of the exported model.

    python -m agents.pretrained export runs/pretrained/<run> --cell 5.3

The files are written to a staging folder in the models' folder, the model is loaded back from
there exactly as ``pretrained:<cell>`` will load it and tested on ``episodes`` test episodes
(seeds 1_000_000 on, as the test phase's), the card is written, and only then the folder is
renamed into place (a model already there is replaced). A cell of the catalogue only takes the
run the catalogue names (its row and seed).
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np

from agents.files import replace_folder
from agents.pretrained import card
from agents.pretrained.catalogue import CELLS
from agents.training import pretrained_files as files
from agents.training.config_io import to_yaml_dict
from agents.training.policy_loading import load_policy, policy_from_state, read_state
from agents.training.stats import summarize
from agents.training.test_phase import run_episodes
from agents.training.threads import limit_threads
from dynnav_tasks.generation import DIFFICULTIES
from dynnav_tasks.task_options import options_name
from dynnav_tasks.tasks.procedural import MIXED

PROCEDURAL_TASK = "DynNav-Procedural-v1"

TEST_SEED = 1_000_000
"""first test episode's seed (the test phase's default)"""


def check_source(run_dir, cell: str) -> dict:
    """The run's saved state (without memory) once it is known to fit ``cell``: a cell of the
    catalogue takes only the row and seed the catalogue names. ValueError otherwise."""
    files.check_name(cell)
    _, state = read_state(run_dir)
    config = state["config"]
    name, seed = config.get("name"), config.get("seed")
    if cell in CELLS and (CELLS[cell].row, CELLS[cell].seed) != (name, seed):
        want = CELLS[cell]
        raise ValueError(f"{run_dir} is {name!r} seed {seed}; cell {cell!r} is {want.row!r} seed {want.seed} "
                         f"(train it with: {want.command()})")
    return state


def export(run_dir: str | Path, cell: str, episodes: int = 100, root: str | Path | None = None,
           verbose: bool = True) -> dict:
    """Export the run in ``run_dir`` as model ``cell`` of ``root`` (default: the repository's
    pretrained/), tested on ``episodes`` test episodes; returns the card's facts."""
    if episodes < 1:
        raise ValueError(f"episodes: the exported model is tested on at least one episode, got {episodes}")
    state = check_source(run_dir, cell)
    limit_threads(1)
    root = Path(root) if root is not None else files.models_root()
    root.mkdir(parents=True, exist_ok=True)
    source = load_policy(run_dir)
    try:
        srl = getattr(source.features, "srl", None)
        config = to_yaml_dict(source.config)
        staging = Path(tempfile.mkdtemp(dir=root, prefix=".export-"))
        try:
            files.write_model(staging / cell, source.q_network.state_dict(), config, state["episode"],
                              srl.encoder_weights() if srl is not None else None)
        except BaseException:
            shutil.rmtree(staging, ignore_errors=True)
            raise
    finally:
        source.env.close()
    try:
        facts = measure(staging, cell, config, state["episode"], episodes, verbose)
        card.write(staging / cell, facts)
        install(staging / cell, root / cell)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    if verbose:
        size = card.folder_size(root / cell)
        print(f"{root / cell}: {size / 1e6:.2f} MB, test success {facts['test']['success']:.0%}")
    return facts


def test_cells(config: dict) -> list[dict]:
    """The task options of each test a model's card measures: a procedural model's each difficulty's
    held-out test worlds (all three for ``difficulty: mixed``), any other model's own task."""
    if config["task"] != PROCEDURAL_TASK:
        return [{}]
    own = config["env"]["task_kwargs"].get("difficulty", "easy")
    return [dict(difficulty=d, split="test") for d in (DIFFICULTIES if own == MIXED else (own,))]


def _test(folder: Path, state: dict, episodes: int, options: dict, verbose: bool) -> dict:
    policy = policy_from_state(folder, state, **options)
    try:
        if verbose:
            print(f"testing the exported model {folder.name} on {episodes} test episodes {options or ''} ...")
        records = run_episodes(policy, episodes, TEST_SEED)
    finally:
        policy.env.close()
    summary, first = summarize(records), records[: card.CHECK_EPISODES]
    return dict(episodes=episodes, seed=TEST_SEED, success=summary["success_rate"], collision=summary["collision_rate"],
                timeout=summary["timeout_rate"],
                success_first_check=sum(r["outcome"] == "success" for r in first) / len(first))


def measure(staging: Path, cell: str, config: dict, trained_episodes: int, episodes: int, verbose: bool) -> dict:
    """Load the staged model as ``pretrained:`` loads it, test it, and return its card's facts: one
    test, or for a procedural model one per difficulty (``tests``, by task options) and their mean (``test``)."""
    folder, state = files.read_model(cell, staging)
    cells = test_cells(config)
    tests = {options_name(o): _test(folder, state, episodes, o, verbose) for o in cells}
    mean = lambda key: float(np.mean([t[key] for t in tests.values()]))  # noqa: E731
    test = next(iter(tests.values())) if len(tests) == 1 and not cells[0] else dict(
        episodes=episodes * len(tests), seed=TEST_SEED, success=mean("success"), collision=mean("collision"),
        timeout=mean("timeout"), success_first_check=mean("success_first_check"))
    known = CELLS.get(cell)
    facts = dict(
        cell=cell, row=config["name"], seed=config["seed"], task=config["task"], trained_episodes=trained_episodes,
        autoencoder=(folder / files.AUTOENCODER).is_file(), test=test,
        table_success=known.success if known is not None else None,
        reproduce=(known.command() if known is not None else
                   f"python -m agents.dqn --config <config of {config['name']}> --seed {config['seed']}"),
    )
    if cells[0]:
        facts["tests"] = tests
    return facts


def install(staged: Path, target: Path) -> None:
    """Rename the staged model folder to ``target``, replacing a model there."""
    replace_folder(staged, target)
