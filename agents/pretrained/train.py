"""Train a cell's run (the catalogue's row and seed) and export it, in one go.

    nice -n 19 python -m agents.pretrained train 5.3          # one cell
    nice -n 19 python -m agents.pretrained train --missing    # every cell without a model, cheapest first

The run goes to ``runs/pretrained/`` (``--runs-dir``). A run of the cell already there is used
again: a finished one is exported as it is, a stopped one continues (``--resume``) first. Runs
are made one after the other, in this process.
"""

from __future__ import annotations

from pathlib import Path

from agents.pretrained.catalogue import source_of
from agents.pretrained.export import export
from agents.training import checkpoint as ckpt
from agents.training.config_io import parse_args
from agents.training.loop import train

RUNS_DIR = "runs/pretrained"


def existing_run(cell: str, runs_dir: str | Path = RUNS_DIR) -> tuple[Path | None, int]:
    """The newest run directory of ``cell``'s row and seed in ``runs_dir`` with a checkpoint, and
    the episodes its checkpoint has done (None, 0 if there is none)."""
    s = source_of(cell)
    runs = sorted((p for p in Path(runs_dir).glob(f"*__{s.row}__{s.seed}__*") if ckpt.exists(p)),
                  key=lambda p: p.stat().st_mtime)
    if not runs:
        return None, 0
    return runs[-1], int(ckpt.load(runs[-1], memory=False)["episode"])


def training_args(cell: str, runs_dir: str | Path = RUNS_DIR, progress: bool = True) -> list[str]:
    """The ``agents.dqn`` arguments that train ``cell``'s run (the test comes with the export)."""
    return [*source_of(cell).training_args(), "--runs-dir", str(runs_dir), "--progress" if progress else "--no-progress"]


def train_and_export(cell: str, runs_dir: str | Path = RUNS_DIR, episodes: int = 100, root=None,
                     progress: bool = True) -> dict:
    """Train ``cell``'s run (or finish the one in ``runs_dir``), export it; returns the card's facts."""
    args = training_args(cell, runs_dir, progress)
    config = parse_args(args)
    run, done = existing_run(cell, runs_dir)
    if run is None:
        print(f"{cell}: training {source_of(cell).row} seed {source_of(cell).seed} into {runs_dir}/")
        run = train(config)
    elif done < config.episodes:
        print(f"{cell}: continuing {run} from episode {done}")
        run = train(parse_args(["--resume", str(run), "--progress" if progress else "--no-progress"]))
    else:
        print(f"{cell}: {run} has finished its {done} episodes")
    return export(run, cell, episodes=episodes, root=root)

