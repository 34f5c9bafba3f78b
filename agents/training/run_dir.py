"""What a training run writes besides its checkpoint: the run directory, metrics.csv with its
progress bar and curves, and the camera runs' auto-encoder files; and the check that a
resumed run is the same run."""

from __future__ import annotations

import csv
import io
import os
import time
from collections import deque
from pathlib import Path

import numpy as np

from agents.files import atomic_write_bytes, disk_full_error, is_disk_full, write_fully
from agents.training.config_io import get

METRICS = ["episode", "global_step", "return", "length", "success", "collision", "timeout", "loss",
           "epsilon", "learning_rate", "steps_per_s", "wall_time_s"]
FIXED_ON_RESUME = ("task", "reward_mode", "reward_params", "task_kwargs", "normalize_obs", "hidden_sizes", "q_network",
                   "buffer_size", "camera_frames", "camera_input", "camera_state", "ae_latent", "ae_conv_channels",
                   "ae_dense", "recurrent", "recurrent_size")
"""settings a resumed run must share with the checkpoint: they decide the task, the networks and the memory"""


def episode_seed(seed: int, episode: int) -> int:
    """The reset seed of training episode ``episode`` (a hash of both: distinct from test seeds)."""
    return int(np.random.SeedSequence([seed, episode]).generate_state(1)[0])


def new_run_dir(config) -> Path:
    """A new, empty ``runs/<task>__<name>__<seed>__<time>`` folder (``-1``, ``-2``, ... if taken)."""
    stamp = time.strftime("%Y%m%d-%H%M%S")
    base = Path(config.run.runs_dir) / f"{config.task.replace('/', '-')}__{config.name}__{config.seed}__{stamp}"
    base.parent.mkdir(parents=True, exist_ok=True)
    run_dir, k = base, 1
    while True:
        try:
            run_dir.mkdir()  # fails if it exists, even when another process made it a moment ago
            return run_dir
        except FileExistsError:
            run_dir, k = Path(f"{base}-{k}"), k + 1


def check_resumable(config, saved) -> None:
    """ValueError listing the settings that differ from the checkpoint's and cannot change on resume."""
    changed = [name for name in FIXED_ON_RESUME if get(config, name) != get(saved, name)]
    if changed:
        flags = ", ".join(f"--{n.replace('_', '-')} {get(config, n)!r} (the run: {get(saved, n)!r})" for n in changed)
        raise ValueError(f"--resume {config.resume}: {flags}; a resumed run keeps its task, networks and memory "
                         f"(start a new run to change them)")


class MetricsLog:
    """metrics.csv (one row per episode, appended as the episode ends), the progress bar and the
    Rerun training curves."""

    def __init__(self, path: Path, keep_episodes: int | None = None, tensorboard=None):
        self.path = path
        self.tensorboard = tensorboard
        """a ``tensorboard_log.TensorBoardLog`` that also receives every row (None: none)"""
        if keep_episodes is not None:
            self._keep_rows(keep_episodes)
        self.pending = io.StringIO()
        """rows not yet in the file"""
        self.writer = csv.DictWriter(self.pending, fieldnames=METRICS, lineterminator="\n")
        if not path.exists():
            self.writer.writeheader()
            self.flush()
        self.recent_success, self.recent_return = deque(maxlen=100), deque(maxlen=100)

    def _keep_rows(self, episodes: int) -> None:
        """Drop the rows of episodes after the checkpoint a resumed run continues from (and a row
        cut short by a kill or a full disk)."""
        if not self.path.exists():
            return
        with open(self.path, newline="") as f:
            rows = [r for r in csv.DictReader(f) if None not in r.values() and None not in r
                    and r["episode"].isdigit() and int(r["episode"]) < episodes]
        out = io.StringIO()
        writer = csv.DictWriter(out, fieldnames=METRICS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        atomic_write_bytes(self.path, out.getvalue().encode())

    @staticmethod
    def progress_bar(config, start_episode: int):
        """A tqdm bar over the run's episodes, starting at ``start_episode``."""
        from tqdm import tqdm

        return tqdm(total=config.episodes, initial=start_episode, desc=config.task, unit="ep", dynamic_ncols=True,
                    mininterval=0.5)

    def log(self, episode: int, global_step: int, result, losses: list, epsilon: float, learning_rate: float,
            elapsed: float, wall_time: float, recorder=None, bar=None) -> None:
        """Write one episode's row (appended to the file at once), update the bar and the Rerun curves."""
        info, success = result.info, result.outcome == "success"
        self.writer.writerow(dict(
            episode=episode, global_step=global_step, **{"return": round(result.ret, 4)}, length=result.length,
            success=int(success), collision=int(bool(info.get("collision", False))),
            timeout=int(result.outcome == "timeout"), loss=f"{np.mean(losses):.6g}" if losses else "",
            epsilon=round(epsilon, 5), learning_rate=f"{learning_rate:.6g}",
            steps_per_s=round(result.length / elapsed, 1), wall_time_s=round(wall_time, 2),
        ))
        self.flush()
        self.recent_success.append(success)
        self.recent_return.append(result.ret)
        if self.tensorboard is not None:
            self.tensorboard.scalars(global_step, {
                "charts/episodic_return": result.ret, "charts/episodic_length": result.length,
                "charts/success": success, "charts/success_rate": float(np.mean(self.recent_success)),
                "charts/collision": bool(info.get("collision", False)),
                "losses/td_loss": np.mean(losses) if losses else None, "charts/epsilon": epsilon,
                "charts/learning_rate": learning_rate, "charts/SPS": result.length / elapsed})
        if recorder is not None:
            recorder.log_training(episode, episode_return=result.ret, loss=np.mean(losses) if losses else None,
                                  epsilon=epsilon, success_rate=float(np.mean(self.recent_success)))
        if bar is not None:
            bar.update(1)
            bar.set_postfix(success=f"{np.mean(self.recent_success):.0%}", ret=f"{np.mean(self.recent_return):.1f}",
                            eps=f"{epsilon:.2f}", sps=f"{result.length / elapsed:.0f}", refresh=False)

    def flush(self) -> None:
        """Append the pending rows to the file; a full disk is a ``DiskFullError``."""
        data = self.pending.getvalue().encode()
        if not data:
            return
        try:
            fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
            try:
                write_fully(fd, data)
            finally:
                os.close(fd)
        except OSError as err:
            if is_disk_full(err):
                raise disk_full_error(err, self.path, len(data)) from err
            raise
        self.pending.seek(0)
        self.pending.truncate()

    def plot(self, run_dir: Path, title: str) -> None:
        """Redraw reward.png and loss.png from metrics.csv into ``run_dir``."""
        from agents.training.plots import plot_learning_curves

        plot_learning_curves(self.path, run_dir, title=title)

    def close(self) -> None:
        """Append the pending rows (and close the TensorBoard files)."""
        self.flush()
        if self.tensorboard is not None:
            self.tensorboard.close()


def update_state_representation(srl, memory, rng, episodes_done: int, config, run_dir: Path) -> None:
    """After an episode: the scheduled auto-encoder update (Alg. 2) and the reconstruction pictures."""
    from agents.srl import pictures as pics

    if srl.due(episodes_done):
        losses = srl.update(memory, rng, progress=config.run.progress)
        pics.append_srl_losses(run_dir / "srl_loss.csv", srl.updates_done, episodes_done, losses)
        pics.plot_srl_losses(run_dir / "srl_loss.csv", run_dir / "srl_loss.png", title=config.task)
    if srl.trained and episodes_done % config.camera.ae_pictures_every == 0:
        # eight observations from the end of the memory, three steps apart
        slots = (memory.last - 3 * np.arange(min(8, 1 + (memory.size - 1) // 3))) % memory.capacity
        frames = memory.frames[slots[::-1]]
        pics.save_reconstruction_pairs(frames, srl.reconstruct(frames),
                                       run_dir / "reconstructions" / f"episode_{episodes_done:05d}.png")
