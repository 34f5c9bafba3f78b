"""The settings of a teacher-student run, parsed by tyro from flags and a YAML file.

    python -m agents.imitation --config configs/imitation/generalist.yaml --seed 2

The student is a DQN run's Q-network: ``student`` names the training config (``agents.dqn``'s
YAML) that says its task, its observation and its network, so that the same file fine-tunes
it with reinforcement learning afterwards (``agents.dqn --init-from``). Everything else here is
the imitation's: how many episodes the teacher drives, the DAgger rounds, the fitting.
"""

from __future__ import annotations

import dataclasses
import numbers
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import yaml


@dataclass
class ImitationConfig:
    """Behaviour cloning on the full-state planner's episodes, then DAgger (agents.imitation)."""

    student: str = "configs/procedural/generalist.yaml"
    """the student's training config (agents.dqn YAML): task, task options, observation, network; a path
    relative to this file's folder when given in a YAML file"""
    name: Optional[str] = None
    """the run's name (default: the config file's stem, or "imitation")"""
    seed: int = 1
    """seeds the episodes (their worlds and the DAgger mixture), the network's start and the fitting"""
    teacher_episodes: int = 400
    """round 0: episodes the teacher drives (behaviour cloning's data)"""
    rounds: int = 4
    """DAgger rounds after round 0: the student drives, the teacher labels, the data grows, the student refits"""
    round_episodes: int = 200
    """episodes per DAgger round"""
    beta_decay: float = 0.5
    """in DAgger round i the teacher's action is taken with probability beta_decay ** i, else the student's
    (Ross et al. 2011's mixture; 0: the student always drives)"""
    teacher_human_margin: float = 0.0
    """personal space (m) the teacher keeps from pedestrians where it can (``PlannerController``'s
    human_margin): 0.2 keeps CrowdNav's discomfort distance"""
    epochs: int = 30
    """passes over the aggregated data at each fit"""
    fresh_fit: bool = False
    """each round's student is a new network fitted to every label so far (DAgger as Ross et al. 2011 give it);
    False: it continues from the last round's weights"""
    batch_size: int = 256
    """states per gradient step"""
    learning_rate: float = 0.001
    """Adam's learning rate"""
    validation_every: int = 10
    """every this many-th episode of the data is held out of the fit, to report the student's accuracy on
    states it did not fit (0: none)"""
    workers: int = 2
    """processes that play and label episodes (0: this process)"""
    runs_dir: str = "runs/imitation"
    """where run directories are made"""
    dataset: bool = True
    """write the demonstrations as a Minari data set (dataset/ in the run directory) at the end"""
    progress: bool = True
    """progress bars"""
    tensorboard: bool = False
    """also write TensorBoard scalars into tensorboard/ in the run directory: the imitation loss of every
    epoch, and per DAgger round its iteration, beta, success, states and accuracies (needs
    pip install 'dynnav[tensorboard]')"""
    resume: Optional[str] = None
    """continue the run in this directory from its last finished round"""

    def validate(self) -> "ImitationConfig":
        """This config, or ValueError naming every impossible value."""
        errors = []
        for name, low in (("seed", 0), ("teacher_episodes", 1), ("rounds", 0), ("round_episodes", 1), ("epochs", 1),
                          ("batch_size", 1), ("validation_every", 0), ("workers", 0)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < low:
                errors.append(f"{name} must be an integer >= {low}; got {v!r}")
        for name, lo, hi in (("beta_decay", 0.0, 1.0), ("learning_rate", 1e-12, 10.0), ("teacher_human_margin", 0.0, 1.0)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or not lo <= v <= hi:
                errors.append(f"{name} must be a number in [{lo}, {hi}]; got {v!r}")
        if self.validation_every == 1:
            errors.append("validation_every 1 would hold out every episode: use 0 (none) or >= 2")
        if not Path(self.student).is_file():
            errors.append(f"student: no training config at {self.student!r} (e.g. configs/procedural/generalist.yaml)")
        if self.tensorboard:
            from agents.training.tensorboard_log import check_available

            try:
                check_available()
            except ValueError as err:
                errors.append(str(err))
        if errors:
            raise ValueError("; ".join(errors))
        return self

    def beta(self, round_: int) -> float:
        """Probability that the teacher's action is taken in round ``round_`` (1 in round 0)."""
        return 1.0 if round_ == 0 else float(self.beta_decay) ** round_


FIELDS = {f.name for f in dataclasses.fields(ImitationConfig)}


def load_yaml(path: str | Path) -> dict:
    """The field values of an imitation YAML file (``student`` made relative to the working
    folder); ValueError for an unknown field."""
    path = Path(path)
    try:
        values = yaml.safe_load(path.read_text()) or {}
    except (OSError, yaml.YAMLError) as err:
        raise ValueError(f"cannot read the imitation config {str(path)!r}: {err}") from err
    if not isinstance(values, dict):
        raise ValueError(f"{str(path)!r} must hold a mapping of settings")
    values.pop("description", None)
    unknown = sorted(set(values) - FIELDS)
    if unknown:
        raise ValueError(f"{str(path)!r}: unknown setting(s) {', '.join(unknown)}; settings: {', '.join(sorted(FIELDS))}")
    if "student" in values:
        values["student"] = os.path.normpath(path.parent / values["student"])
    values.setdefault("name", path.stem)
    return values
