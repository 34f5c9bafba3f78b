"""The fast mode's second process: the (Double) DQN learner on its own core, reading a replay
memory in shared memory that the collecting process fills (Ape-X style, one collector).

    memory = SharedReplayMemory(capacity, obs_dim)        # the collector adds, the learner samples
                                                          # (SharedFrameReplay for pixel runs)
    with LearnerProcess(config, input_specs, n_actions, memory) as learner:
        learner.collected(global_step)                    # after every environment step
        learner.copy_weights_to(actor)                    # the collector's acting network, now and then
        learner.state_dict()                              # for a checkpoint (the learner pauses)

The learner keeps the single-process loop's replay ratio: after ``global_step`` collected steps
it has made the same number of updates as ``agents.training.loop`` would have (one every
``train_frequency`` steps once ``learning_starts`` steps are stored), never more; the collector
waits when the learner falls more than ``MAX_LAG_STEPS`` steps behind, and at the end until it
has caught up. Hard target copies fall on the same updates as in the single-process loop.
What differs is timing: the collector acts with weights at most ``fast_sync_steps`` steps (plus the
lag) old, so a fast run does not replay bit for bit.
"""

from __future__ import annotations

import contextlib
import os
import time
import traceback

import numpy as np
import torch
import torch.multiprocessing as mp

from agents.core.demo_replay import DemoReplay
from agents.core.policy import build_learner, build_q_network
from agents.training.shared_replay import SharedFrameReplay, SharedReplayMemory
from agents.training.teacher import initialise
from agents.training.threads import limit_threads

MAX_LAG_STEPS = 2000
"""the collector waits while the learner's updates are behind by more than this many steps' worth"""
PUBLISH_EVERY = 16
"""the learner publishes its online network's weights for the collector every this many updates"""
# slots of the shared control array (float64: exact for counts below 2**53)
STEPS, UPDATES, LR, LOSS_SUM, LOSS_COUNT, VERSION, FAILED, CPU_S = range(8)


def updates_due(config, steps: int) -> int:
    """The number of updates the single-process loop has made after ``steps`` environment steps:
    one at every step k > learning_starts with k % train_frequency == 0, once batch_size are stored."""
    d = config.dqn
    first = max(d.learning_starts, d.batch_size - 1)  # updates happen at steps k > first
    return max(0, steps // d.train_frequency - first // d.train_frequency)


def step_of_update(config, update: int) -> int:
    """The environment step at which the single-process loop makes its ``update``-th update (from 1)."""
    d = config.dqn
    first = max(d.learning_starts, d.batch_size - 1)
    return (first // d.train_frequency + update) * d.train_frequency


class LearnerProcess:
    """Runs ``learn`` in a child process and talks to it: the collector's side.

    It stands in for a ``DQNLearner`` where the training loop's helpers need one
    (``learning_rate``, ``state_dict``, ``load_state_dict``)."""

    def __init__(self, config, input_specs, n_actions: int, memory: SharedReplayMemory | SharedFrameReplay,
                 demos: DemoReplay | None = None, start_weights: dict | None = None):
        self.config = config
        ctx = mp.get_context("spawn")
        self.control = torch.zeros(8, dtype=torch.float64).share_memory_()
        self._control = self.control.numpy()
        self._control[LR] = config.schedule.learning_rate
        self.weights = [p.detach().clone().share_memory_()
                        for p in build_q_network(config, input_specs, n_actions).parameters()]
        """the online network's weights as the learner last published them"""
        self.lock = ctx.Lock()
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(target=learn, name="dqn-learner", daemon=True,
                                   args=(config, input_specs, n_actions, memory, self.control, self.weights,
                                         self.lock, child, os.getpid(), demos, start_weights))
        self.process.start()
        child.close()
        self._version = 0.0
        self._resumed = None
        self.waited_s = 0.0
        """seconds the collector spent waiting for the learner"""

    def __enter__(self) -> "LearnerProcess":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ------------------------------------------------------------------ commands
    def _ask(self, command: str, payload=None):
        self._check_alive()
        self.conn.send((command, payload))
        while not self.conn.poll(0.5):
            self._check_alive()
        kind, value = self.conn.recv()
        if kind == "error":
            raise RuntimeError(f"the learner process failed:\n{value}")
        return value

    def _check_alive(self) -> None:
        if not self.process.is_alive():
            raise RuntimeError(f"the learner process ended unexpectedly (exit code {self.process.exitcode})")

    def load_state_dict(self, state: dict) -> None:
        """Keep a checkpoint's networks and Adam state for ``start`` to load into the learner."""
        self._resumed = state

    def start(self, global_step: int) -> None:
        """Let the learner begin (with the state given to ``load_state_dict``, if any), ``global_step``
        steps into the run: the updates due for them count as made."""
        self._control[STEPS] = global_step
        self._ask("start", (self._resumed, global_step))

    def state_dict(self) -> dict:
        """The learner's networks and Adam state, as ``DQNLearner.state_dict`` (it pauses meanwhile)."""
        return self._ask("state")

    def close(self) -> None:
        """Stop the learner process."""
        if self.process.is_alive():
            try:
                self.conn.send(("stop", None))
            except (BrokenPipeError, OSError):
                pass
            self.process.join(10)
        if self.process.is_alive():
            self.process.terminate()
            self.process.join()
        self.conn.close()

    # ------------------------------------------------------------------ shared values
    @property
    def learning_rate(self) -> float:
        """Adam's learning rate: the collector sets it once per episode, the learner reads it every update."""
        return float(self._control[LR])

    @learning_rate.setter
    def learning_rate(self, value: float) -> None:
        self._control[LR] = value

    @property
    def updates(self) -> int:
        """Updates made so far."""
        return int(self._control[UPDATES])

    @property
    def cpu_s(self) -> float:
        """CPU seconds the learner process has used since its start-up (updated with every weights publication)."""
        return float(self._control[CPU_S])

    def loss_totals(self) -> tuple[float, int]:
        """Sum and count of every update's loss so far (the metrics take differences)."""
        return float(self._control[LOSS_SUM]), int(self._control[LOSS_COUNT])

    def collected(self, steps: int) -> None:
        """Tell the learner ``steps`` environment steps are stored; wait while it is too far behind."""
        self._control[STEPS] = steps
        lag = updates_due(self.config, steps) - self.updates
        if lag * self.config.dqn.train_frequency > MAX_LAG_STEPS:
            self.wait_for(lambda: (updates_due(self.config, steps) - self.updates) * self.config.dqn.train_frequency
                          <= MAX_LAG_STEPS // 2)

    def catch_up(self) -> None:
        """Wait until the learner has made every update due for the steps collected."""
        due = updates_due(self.config, int(self._control[STEPS]))
        self.wait_for(lambda: self.updates >= due)

    def wait_for(self, done) -> None:
        """Sleep in short steps until ``done()``; a learner that failed or ended is an error."""
        t0 = time.perf_counter()
        while not done():
            self._check_alive()
            if self._control[FAILED]:
                self._ask("state")  # raises with the learner's error
            time.sleep(0.0005)
        self.waited_s += time.perf_counter() - t0

    def copy_weights_to(self, module: torch.nn.Module) -> bool:
        """Copy the last published weights into ``module`` (the collector's network) if they are new."""
        if self._control[VERSION] == self._version:
            return False
        with self.lock, torch.no_grad():
            self._version = float(self._control[VERSION])
            torch._foreach_copy_(list(module.parameters()), self.weights)
        return True


# ---------------------------------------------------------------------------------------- the child
def learn(config, input_specs, n_actions, memory: SharedReplayMemory | SharedFrameReplay, control: torch.Tensor,
          weights, lock, conn, collector: int, demos: DemoReplay | None = None, start_weights: dict | None = None):
    """The learner process: update whenever an update is due, answer the collector's commands (the
    process ``collector``), end when it is gone. ``demos`` and ``start_weights``: a teacher's
    (``agents.training.teacher``), applied when a new run starts."""
    limit_threads(1)
    ctrl = control.numpy()
    try:
        d = config.dqn
        learner = build_learner(config, build_q_network(config, input_specs, n_actions), input_specs)
        rng = np.random.default_rng(np.random.SeedSequence([config.seed, 1]))
        sample_into = memory.sample_frames_into if isinstance(memory, SharedFrameReplay) else memory.sample_into
        params = list(learner.q.parameters())
        updates, loss_sum, loss_count = 0, 0.0, 0
        cpu0 = time.process_time()  # start-up (imports, networks) not counted

        def publish():
            with lock, torch.no_grad():
                torch._foreach_copy_(weights, [p.detach().cpu() for p in params])
                ctrl[VERSION] += 1
            ctrl[CPU_S] = time.process_time() - cpu0

        started = False
        while True:
            if conn.poll():
                command, payload = conn.recv()
                if command == "stop":
                    return
                if command == "start":
                    state, start_step = payload
                    if state is not None:
                        learner.load_state_dict(state)
                    else:
                        initialise(learner, config, start_weights, demos)
                    publish()
                    updates = updates_due(config, start_step)
                    ctrl[UPDATES], started = updates, True
                    conn.send(("ok", None))
                elif command == "state":
                    ctrl[CPU_S] = time.process_time() - cpu0
                    conn.send(("ok", learner.state_dict()))
                continue
            if not started or updates >= updates_due(config, int(ctrl[STEPS])):
                if os.getppid() != collector:  # the collector was killed
                    return
                time.sleep(0.0005)
                continue
            sample_into(learner.batch, rng)
            if demos is not None:
                demos.sample_into(learner.batch, rng)
            learner.learning_rate = ctrl[LR]
            loss = learner.update()
            updates += 1
            if d.target_update == "soft":
                learner.update_target(d.tau)
            elif step_of_update(config, updates) // d.target_update_interval \
                    != step_of_update(config, updates - 1) // d.target_update_interval:
                learner.update_target()  # a hard copy at the update where the single-process loop makes it
            loss_sum, loss_count = loss_sum + loss, loss_count + 1
            ctrl[LOSS_SUM], ctrl[LOSS_COUNT] = loss_sum, loss_count
            if updates % PUBLISH_EVERY == 0:
                publish()
                if os.getppid() != collector:
                    return
            ctrl[UPDATES] = updates
    except EOFError:  # the collector is gone
        return
    except Exception:  # noqa: BLE001 - reported to the collector, which raises it
        ctrl[FAILED] = 1
        message = traceback.format_exc()
        with contextlib.suppress(EOFError, OSError):
            while True:  # answer the collector's next command with the error
                command, _ = conn.recv()
                if command == "stop":
                    return
                conn.send(("error", message))
