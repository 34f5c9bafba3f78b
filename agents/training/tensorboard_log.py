"""TensorBoard scalars of a run, as CleanRL and Stable-Baselines3 users watch long training.

    python -m agents.dqn --config configs/procedural/generalist.yaml --tensorboard
    tensorboard --logdir runs/            # every run's tensorboard/ folder

With ``run.tensorboard`` (``--tensorboard``) a run also writes TensorBoard event files into
``<run>/tensorboard/``, one point per episode at its global step, under CleanRL's names:

==============================  ===============================================================
``charts/episodic_return``      the episode's return
``charts/episodic_length``      its steps
``charts/success``              1 on success, 0 otherwise; ``charts/success_rate``: the last 100
``charts/collision``            1 on a collision, 0 otherwise
``losses/td_loss``              the mean loss of the episode's updates (none before the first)
``charts/epsilon``              exploration
``charts/learning_rate``        Adam's learning rate
``charts/SPS``                  environment steps per second in the episode
==============================  ===============================================================

``agents.imitation`` writes ``imitation/loss`` (each epoch of each fit), and per DAgger round
``imitation/dagger_iteration``, ``imitation/beta``, ``imitation/success``, ``imitation/states``,
``imitation/train_accuracy`` and ``imitation/validation_accuracy``.

TensorBoard is an optional extra (``pip install 'dynnav[tensorboard]'``): asking for it without
the package installed is an error before the run starts. A resumed run appends to its event files.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

FOLDER = "tensorboard"
"""the event files' folder in a run directory"""


def check_available() -> None:
    """ValueError unless the ``tensorboard`` package (which writes the event files) is installed."""
    if importlib.util.find_spec("tensorboard") is None:
        raise ValueError("tensorboard: the tensorboard package is not installed; pip install 'dynnav[tensorboard]' "
                         "(or pip install tensorboard), or drop --tensorboard")


class TensorBoardLog:
    """Scalars into ``<run_dir>/tensorboard/`` (see the module docstring)."""

    def __init__(self, run_dir: str | Path):
        check_available()
        from torch.utils.tensorboard import SummaryWriter

        self.writer = SummaryWriter(log_dir=str(Path(run_dir) / FOLDER))

    def scalars(self, step: int, values: dict) -> None:
        """One point of each named scalar (None values are left out) at ``step``."""
        for name, value in values.items():
            if value is not None:
                self.writer.add_scalar(name, float(value), int(step))

    def flush(self) -> None:
        self.writer.flush()

    def close(self) -> None:
        self.writer.close()
