"""Demonstrations: episodes with a teacher's action (its *label*) in every state they visited.

A ``Rollout`` is one such episode: the observations, the actions taken (the teacher's, or a
student's in DAgger), the labels, the rewards and how it ended. ``Demonstrations`` holds many,
each with the round that gathered it (``agents.imitation``: round 0 the teacher's own
episodes, then one per DAgger round), and gives them two ways:

* ``states()``: every state an episode acted in and its label, what a student imitates;
* ``transitions()``: every (s, a, r, s', 1 - terminated, label), what a replay memory of
  demonstrations keeps (``demo_replay.DemoReplay``, DQfD).

``to_npz()`` and ``load(path)`` are its file: one ``.npz`` of numpy arrays, read without pickle.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class Rollout:
    """One labelled episode (``observations`` has one row more than the steps: the last state)."""

    seed: int
    """the reset's seed"""
    difficulty: str
    """the world's difficulty (``world_difficulty`` of the procedural task; the task id elsewhere)"""
    world_seed: int
    """the world's seed (-1 for a world given in the reset's options)"""
    beta: float
    """probability with which the teacher's action was taken in each state"""
    observations: np.ndarray
    """(steps + 1, d) float32: every state seen, the first after the reset, the last at the end"""
    actions: np.ndarray
    """(steps,) int64: the action taken in each state"""
    labels: np.ndarray
    """(steps,) int64: the teacher's action in each state"""
    rewards: np.ndarray
    """(steps,) float32"""
    terminated: bool
    truncated: bool
    outcome: str
    """success, collision or timeout"""
    label_seconds: float
    """time the teacher spent choosing its labels in this episode"""

    @property
    def steps(self) -> int:
        """Number of steps (actions) in the episode."""
        return len(self.actions)

_EPISODE_FIELDS = ("seed", "world_seed", "beta", "terminated", "truncated", "label_seconds", "round")
_TEXT_FIELDS = ("difficulty", "outcome")


class Demonstrations:
    """Labelled episodes by round (see the module docstring)."""

    def __init__(self):
        self.rollouts: list[Rollout] = []
        self.rounds: list[int] = []

    def add(self, rollouts: list[Rollout], round_: int) -> None:
        """Add one round's episodes."""
        self.rollouts += rollouts
        self.rounds += [int(round_)] * len(rollouts)

    def __len__(self) -> int:
        """Number of labelled states."""
        return sum(r.steps for r in self.rollouts)

    def states(self) -> tuple[np.ndarray, np.ndarray]:
        """(observations (n, d) float32, labels (n,) int64) of every labelled state."""
        if not self.rollouts:
            raise ValueError("no demonstrations yet")
        return (np.concatenate([r.observations[:-1] for r in self.rollouts]),
                np.concatenate([r.labels for r in self.rollouts]))

    def transitions(self) -> dict[str, np.ndarray]:
        """Every step as a transition: obs, next_obs (n, d) float32, actions, labels (n,) int64,
        rewards, not_done (n,) float32 (0 after the step that terminated an episode; a timeout
        still bootstraps, as in the replay memory)."""
        if not self.rollouts:
            raise ValueError("no demonstrations yet")
        not_done = [np.concatenate([np.ones(r.steps - 1), [0.0 if r.terminated else 1.0]]) for r in self.rollouts]
        return dict(
            obs=np.concatenate([r.observations[:-1] for r in self.rollouts]),
            next_obs=np.concatenate([r.observations[1:] for r in self.rollouts]),
            actions=np.concatenate([r.actions for r in self.rollouts]),
            labels=np.concatenate([r.labels for r in self.rollouts]),
            rewards=np.concatenate([r.rewards for r in self.rollouts]).astype(np.float32),
            not_done=np.concatenate(not_done).astype(np.float32),
        )

    def to_npz(self) -> bytes:
        """Every episode as the bytes of one compressed ``.npz`` (``load`` reads it back)."""
        steps = np.array([r.steps for r in self.rollouts], dtype=np.int64)
        arrays = dict(
            steps=steps,
            observations=np.concatenate([r.observations for r in self.rollouts]),
            actions=np.concatenate([r.actions for r in self.rollouts]),
            labels=np.concatenate([r.labels for r in self.rollouts]),
            rewards=np.concatenate([r.rewards for r in self.rollouts]),
        )
        for name in _EPISODE_FIELDS:
            values = self.rounds if name == "round" else [getattr(r, name) for r in self.rollouts]
            arrays[name] = np.asarray(values)
        for name in _TEXT_FIELDS:
            arrays[name] = np.asarray([getattr(r, name) for r in self.rollouts], dtype=str)
        buffer = io.BytesIO()
        np.savez_compressed(buffer, **arrays)
        return buffer.getvalue()

    @classmethod
    def load(cls, path: str | Path) -> "Demonstrations":
        """The episodes ``to_npz`` gave; ValueError naming the file if it is unreadable."""
        try:
            with np.load(path, allow_pickle=False) as npz:
                a = {k: npz[k] for k in npz.files}
        except (OSError, ValueError, EOFError, KeyError) as err:
            raise ValueError(f"{str(path)!r} is not a readable demonstrations file ({err})") from err
        out = cls()
        obs_at = np.concatenate([[0], np.cumsum(a["steps"] + 1)])
        step_at = np.concatenate([[0], np.cumsum(a["steps"])])
        for i in range(len(a["steps"])):
            s, o = slice(step_at[i], step_at[i + 1]), slice(obs_at[i], obs_at[i + 1])
            rollout = Rollout(
                seed=int(a["seed"][i]), difficulty=str(a["difficulty"][i]), world_seed=int(a["world_seed"][i]),
                beta=float(a["beta"][i]), observations=a["observations"][o], actions=a["actions"][s],
                labels=a["labels"][s], rewards=a["rewards"][s], terminated=bool(a["terminated"][i]),
                truncated=bool(a["truncated"][i]), outcome=str(a["outcome"][i]),
                label_seconds=float(a["label_seconds"][i]),
            )
            out.add([rollout], int(a["round"][i]))
        return out
