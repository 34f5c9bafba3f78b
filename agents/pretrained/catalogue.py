"""Which run each pretrained navigator comes from: per numbered cell of the study, its best row
(RESULTS.md, "The study's numbered cells") and, of that row's seeds in results/runs.csv.gz, the
one with the best test success.

The table is written out rather than derived: the run table grows, and a model stays what it
was trained as (its card names the row and the seed). ``wall_s`` is the recorded training time
of that run, which orders the training cheapest first.

One cell takes its row's second-best seed: 5.3-potential-0.85's seed 2 (96% in the table),
retrained with today's code, reached 4% on the test episodes (22% training success in its last
500 episodes), so its model is seed 1's.

The three cells whose best row has memory (5.5a-camera, 5.5b-laser-camera-pos, 5.5c-frames-4: rows
ending in ``-gru``) were exported from the memory sweep's own runs (agents/study/REPRODUCE.md), so
their cards test the very networks of the table's rows.

``procedural`` is the generalist (docs/generalist.md): the reinforcement-learning fine-tune of a
student cloned from the planner, so its run needs the same seed's imitation run first
(``Source.before``); it trains in the fast mode, as its row was.

``crowd`` is the look-ahead Double DQN among 5 pedestrians crossing a circle (docs/crowds.md, *A
look-ahead over the value*), its row's best seed; it trains in the fast mode, as its row was.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


@dataclass(frozen=True)
class Source:
    """The run a cell's model is trained as."""

    row: str
    """the experiment: configs/study/<row>.yaml"""
    seed: int
    """its seed with the best test success in the run table"""
    success: float
    """that run's test success in the run table (100 test episodes of its own test)"""
    wall_s: float
    """that run's recorded training time in seconds"""
    folder: str = "study"
    """the folder of configs/ that holds the experiment's config"""
    fast: bool = False
    """whether the run trains in the fast mode (``--fast``)"""
    before: str = ""
    """the command whose run this one starts from (its ``demos`` settings find it), if any"""
    tested_on: str = ""
    """the task options of the run's own test (its row's ``tested_on``): empty for the study's
    runs, which test on their own task as it is"""

    @property
    def config(self) -> Path:
        """The experiment's config file."""
        return ROOT / "configs" / self.folder / f"{self.row}.yaml"

    def training_args(self, config: str | Path | None = None) -> list[str]:
        """The ``agents.dqn`` arguments of the run (``--runs-dir`` and the progress bar aside), with
        ``config`` (default: the config's full path) as its config."""
        return (["--config", str(self.config if config is None else config), "--seed", str(self.seed),
                 "--no-eval-after-training"] + (["--fast"] if self.fast else []))

    def command(self) -> str:
        """The training commands that reproduce the run (from the repository's root)."""
        args = self.training_args(self.config.relative_to(ROOT).as_posix())
        dqn = " ".join(["python -m agents.dqn", *args[:4], "--runs-dir runs/pretrained", *args[4:]])
        return f"{self.before} && {dqn}" if self.before else dqn


CELLS: dict[str, Source] = {
    "5.2": Source("5.2-turn-forward-ddqn-lr-decay-4000ep", 1, 1.00, 1253),
    "5.3": Source("5.3-g0.1-two-states-ddqn-lr-decay-12000ep", 4, 0.99, 4330),
    "5.3-orientation-always": Source("5.3-orientation-always-g0.1-two-states-ddqn-lr-decay-12000ep", 3, 0.96, 1121),
    "5.3-potential-0.85": Source("5.3-potential-0.85-8000ep", 1, 0.93, 1259),  # seed 2 retrained: 4%
    "5.3-potential-0.9": Source("5.3-potential-0.9-ddqn-lr-decay-12000ep-hold-4000ep", 2, 0.99, 5980),
    "5.3-potential-0.95": Source("5.3-potential-0.95-ddqn-lr-decay-8000ep", 3, 0.98, 816),
    "5.3-potential-1.0": Source("5.3-potential-1.0", 1, 0.89, 397),
    "5.5a-camera": Source("5.5a-camera-g0.1-turn-forward-gru", 2, 0.97, 1382),
    "5.5b-laser-pos": Source("5.5b-laser-pos", 1, 1.00, 378),
    "5.5b-camera-pos": Source("5.5b-camera-pos-rare-colours", 5, 0.77, 808),
    "5.5b-laser-camera-pos": Source("5.5b-laser-camera-pos-g0.1-turn-forward-gru", 2, 1.00, 1088),
    "5.5c-frames-1": Source("5.5c-frames-1-g0.1", 1, 0.78, 808),
    "5.5c-frames-2": Source("5.5c-frames-2-g0.1", 4, 0.79, 1818),
    "5.5c-frames-4": Source("5.5c-frames-4-g0.1-gru", 3, 0.93, 1747),
    "procedural": Source("generalist-finetune", 1, 0.76, 540, folder="procedural", fast=True,
                         before="python -m agents.imitation --config configs/imitation/generalist.yaml --seed 1",
                         tested_on="difficulty=medium,split=test"),
    "crowd": Source("circle-crossing-lookahead", 1, 0.946, 1442, folder="crowd", fast=True),
}
"""cell -> the run its model is trained as"""


def source_of(cell: str) -> Source:
    """The run of ``cell``; ValueError listing the cells for another name."""
    if cell not in CELLS:
        raise ValueError(f"{cell!r} is not a cell of the study with a pretrained model; the cells: {', '.join(CELLS)}")
    return CELLS[cell]


def cheapest_first(cells=None) -> list[str]:
    """``cells`` (default: all) ordered by their run's recorded training time."""
    return sorted(CELLS if cells is None else cells, key=lambda c: source_of(c).wall_s)
