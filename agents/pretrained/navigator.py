"""A pretrained navigator in Python: ``load("5.3")`` gives its greedy policy on its own task.

    from agents.pretrained import load

    with load("5.5b-laser-pos") as navigator:
        obs, _ = navigator.env.reset(seed=0)
        navigator.reset()  # a model with memory starts each episode from a zero hidden state
        obs, reward, terminated, truncated, info = navigator.env.step(navigator.act(obs))
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from agents.core.policy import Policy
from agents.pretrained import card
from agents.training import pretrained_files as files
from agents.training.policy_loading import policy_from_state


@dataclass
class Navigator:
    """A pretrained model's greedy policy, its environment (the task and settings it was trained
    on) and its card."""

    name: str
    """the model's name (``5.3``), as in ``pretrained:5.3``"""
    policy: Policy
    """the loaded policy (Q-network, features, config)"""
    card: dict
    """the facts of its card (``agents.pretrained.card``)"""

    @property
    def env(self):
        """The model's task, made with its config (a gymnasium env: numpy observations)."""
        return self.policy.env

    def reset(self) -> None:
        """Start the next episode: a model with memory (a recurrent Q-network) forgets the last one.
        Call it after each ``env.reset``; a model without memory is unaffected."""
        self.policy.reset()

    def q_values(self, obs) -> np.ndarray:
        """The Q-values of an observation of ``env``, one per action (a model with memory also
        remembers the observation)."""
        return self.policy.q_values(obs)

    def act(self, obs) -> int:
        """The greedy action for an observation of ``env``."""
        return int(np.argmax(self.policy.q_values(obs)))

    def close(self) -> None:
        """Close the environment."""
        self.policy.env.close()

    def __enter__(self) -> "Navigator":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def load(name: str, device: Optional[str] = None, root: str | Path | None = None, **task_kwargs) -> Navigator:
    """The pretrained model ``name`` (``5.3`` or ``pretrained:5.3``) from ``root`` (default: the
    repository's ``pretrained/``, or ``$DYNNAV_PRETRAINED``); ``task_kwargs`` are added to its
    task's options (e.g. ``obs_mode``). An unknown name is a ValueError listing the models."""
    folder, state = files.read_model(name, root)
    policy = policy_from_state(folder, state, device, **task_kwargs)
    return Navigator(folder.name, policy, card.read(folder) if (folder / files.CARD).is_file() else {})


def available(root: str | Path | None = None) -> list[str]:
    """The names of the pretrained models in ``root`` (default: the repository's)."""
    return files.available(root)
