"""Episodes labelled by the teacher: the full-state planner says what it would do in every state.

``play(env, teacher, student, beta, seed)`` plays one episode of a task. In every state the
teacher (``dynnav_tasks.baselines.state_planner.PlannerController``, which reads the task's
world and full state) gives its action, the *label*; with probability ``beta`` the teacher's
action is the one taken, else the student's (DAgger's mixture, Ross et al. 2011: ``beta = 1``
is a demonstration, ``beta = 0`` lets the student drive). The teacher plans every step even
when the student drives, because its forecast of the boxes follows them from step to step.

The episode comes back as an ``agents.core.demonstrations.Rollout``: the task's observations
(the egocentric state, unscaled), the actions taken, the labels, the rewards and how it ended.
"""

from __future__ import annotations

import time
from typing import Callable, Optional

import numpy as np

from agents.core.demonstrations import Rollout
from dynnav_tasks.baselines.state_planner import PlannerController
from dynnav_tasks.outcomes import outcome_of


def play(env, teacher: PlannerController, student: Optional[Callable[[np.ndarray], int]], beta: float,
         seed: int, options: Optional[dict] = None, start: Optional[Callable[[], None]] = None) -> Rollout:
    """One episode of ``env`` (a ``NumpyWrapper``-wrapped dynnav task on the discrete drive) from
    ``seed``: in each state the teacher labels, and its action is taken with probability ``beta``
    (drawn from ``seed``), else ``student(observation)``'s (``student`` may be None only with
    ``beta`` 1; with memory, it sees every observation: it is asked in every state, whoever
    acts). ``start()``, if given, is called after the reset (a student with memory forgets)."""
    if student is None and beta < 1.0:
        raise ValueError("a rollout with beta < 1 needs a student to act")
    rng = np.random.default_rng([seed, 0xDA66E7])
    obs, _ = env.reset(seed=seed, options=options)
    task = env.unwrapped
    teacher.start(task)
    if start is not None:
        start()
    observations, actions, labels, rewards, planning = [obs], [], [], [], 0.0
    while True:
        t = time.perf_counter()
        label = int(teacher.act(task))
        planning += time.perf_counter() - t
        own = int(student(obs)) if student is not None else label  # a student with memory reads every step
        action = label if rng.random() < beta else own
        obs, reward, terminated, truncated, info = env.step(action)
        observations.append(obs)
        actions.append(action)
        labels.append(label)
        rewards.append(float(reward))
        if terminated or truncated:
            break
    world_seed = getattr(task, "world_seed", None)
    return Rollout(
        seed=int(seed), difficulty=str(getattr(task, "world_difficulty", env.spec.id if env.spec else "")),
        world_seed=-1 if world_seed is None else int(world_seed), beta=float(beta),
        observations=np.asarray(observations, dtype=np.float32), actions=np.asarray(actions, dtype=np.int64),
        labels=np.asarray(labels, dtype=np.int64), rewards=np.asarray(rewards, dtype=np.float32),
        terminated=bool(terminated), truncated=bool(truncated), outcome=outcome_of(info, bool(terminated)),
        label_seconds=planning,
    )
