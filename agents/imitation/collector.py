"""Labelled episodes on several processes: the planner's tens of milliseconds per label, on every core.

The teacher plans for 25 ms (medium worlds) to 85 ms (hard ones) per state here
(``benchmarks/imitation_labels.py`` measures it), a student step takes a fraction of a
millisecond: labelling is the cost of imitation. A ``Collector`` keeps ``workers`` processes,
each with its own task, teacher and a copy of the student's network, and plays the episodes it
is given on all of them (``workers=0``: in this process, for tests and small runs)::

    with Collector(student_config, workers=2) as collector:
        rollouts = collector.play([(seed, beta), ...], student_weights, progress=True)

The student's weights go to the workers with each batch of episodes; the episodes come back in
the order they were asked for, so a run gives the same data whatever the number of workers.
"""

from __future__ import annotations

import multiprocessing as mp
from concurrent.futures import ProcessPoolExecutor
from typing import Optional, Sequence

import numpy as np
import torch
from tqdm import tqdm

from agents.core.demonstrations import Rollout
from agents.core.networks import q_values_of
from agents.core.policy import build_q_network
from agents.core.recurrent import RecurrentQNetwork
from agents.imitation.rollouts import play
from agents.training.config_io import config_from_dict
from agents.training.envs import make_env_from
from agents.training.experience import make_features
from agents.training.threads import limit_threads
from dynnav_tasks.baselines.state_planner import PlannerController

CHUNK = 4
"""episodes per job sent to a worker (fewer: more weight copies; more: a worse split of the last ones)"""


class EpisodePlayer:
    """A task, its teacher and the student's network: plays labelled episodes (one per process)."""

    def __init__(self, config_values: dict, human_margin: float = 0.0):
        limit_threads(1)
        config = config_from_dict(config_values, source="the student's config")
        self.env = make_env_from(config)
        self.features = make_features(self.env, config)
        self.net = build_q_network(config, self.features.input_specs, int(self.env.action_space.n))
        self.teacher = PlannerController(human_margin=human_margin)
        self.hidden = None  # a recurrent student's state in the current episode

    def start(self) -> None:
        """An episode starts: a recurrent student forgets the last one."""
        self.hidden = None

    def act(self, obs: np.ndarray) -> int:
        """The student's greedy action (a recurrent student's hidden state moves one step on)."""
        if isinstance(self.net, RecurrentQNetwork):
            q, self.hidden = self.net.step(self.features(obs), self.hidden)
            return int(np.argmax(q))
        return int(np.argmax(q_values_of(self.net, self.features(obs))))

    def play(self, jobs: Sequence[tuple[int, float]], weights: Optional[dict]) -> list[Rollout]:
        """One episode per (seed, beta) of ``jobs``, the student holding ``weights`` (None: no
        student; every beta must then be 1)."""
        if weights is not None:
            self.net.load_state_dict({k: torch.as_tensor(v) for k, v in weights.items()})
        student = self.act if weights is not None else None
        return [play(self.env, self.teacher, student, beta, seed, start=self.start) for seed, beta in jobs]

    def close(self) -> None:
        self.env.close()


_PLAYER: Optional[EpisodePlayer] = None  # a worker process's player


def _start_worker(config_values: dict, human_margin: float) -> None:
    global _PLAYER
    _PLAYER = EpisodePlayer(config_values, human_margin)


def _play_in_worker(jobs, weights) -> list[Rollout]:
    return _PLAYER.play(jobs, weights)


class Collector:
    """Labelled episodes of the student's task on ``workers`` processes (see the module docstring)."""

    def __init__(self, config_values: dict, workers: int = 2, human_margin: float = 0.0):
        """``human_margin``: the personal space the teacher keeps from pedestrians (``PlannerController``)."""
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
            raise ValueError(f"workers must be a non-negative integer (0: play in this process); got {workers!r}")
        self.workers = workers
        self._local = EpisodePlayer(config_values, human_margin) if workers == 0 else None
        self._pool = None
        if workers:
            self._pool = ProcessPoolExecutor(workers, mp_context=mp.get_context("spawn"), initializer=_start_worker,
                                             initargs=(config_values, human_margin))

    def play(self, jobs: Sequence[tuple[int, float]], weights: Optional[dict] = None, progress: bool = False,
             description: str = "episodes") -> list[Rollout]:
        """One ``Rollout`` per (seed, beta) in ``jobs``, in their order; ``weights``: the student's
        ``state_dict`` (None when every beta is 1: the teacher drives)."""
        jobs = [(int(s), float(b)) for s, b in jobs]
        if weights is None and any(b < 1.0 for _, b in jobs):
            raise ValueError("episodes the student drives (beta < 1) need the student's weights")
        plain = None if weights is None else {k: v.detach().cpu().numpy() for k, v in weights.items()}
        chunks = [jobs[i:i + CHUNK] for i in range(0, len(jobs), CHUNK)]
        bar = tqdm(total=len(jobs), desc=description, unit="ep", disable=not progress, leave=False)
        out: list[list[Rollout]] = []
        try:
            if self._local is not None:
                for chunk in chunks:
                    out.append(self._local.play(chunk, plain))
                    bar.update(len(chunk))
            else:
                futures = [self._pool.submit(_play_in_worker, chunk, plain) for chunk in chunks]
                for future, chunk in zip(futures, chunks):
                    out.append(future.result())
                    bar.update(len(chunk))
        finally:
            bar.close()
        return [r for chunk in out for r in chunk]

    def close(self) -> None:
        """Stop the workers (or close the local task)."""
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
        if self._local is not None:
            self._local.close()
            self._local = None

    def __enter__(self) -> "Collector":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
