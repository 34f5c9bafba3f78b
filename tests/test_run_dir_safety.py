"""Run-directory safety: one writer per run directory (a live second process is refused, a killed
one does not block ``--resume``), and a full disk is a one-line error that leaves the last
complete checkpoint loadable."""

import errno
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from agents.dqn import main, train
from agents.training import checkpoint as ckpt
from agents.training.config_io import make
from agents.training.run_lock import LOCK, RunDirBusy, RunDirLock

ROOT = Path(__file__).resolve().parents[1]
HOLD = "import sys, time; from agents.training.run_lock import RunDirLock; RunDirLock(sys.argv[1]).acquire(); " \
       "print('locked', flush=True); time.sleep(600)"
QUIET = ["--no-progress", "--no-eval-after-training"]


def small(tmp_path, **overrides):
    values = dict(task="DynNav-MovingTarget-v1", reward_mode="distance", episodes=2, learning_starts=32,
                  batch_size=16, hidden_sizes=(16,), buffer_size=5000, checkpoint_every=1,
                  epsilon_decay_episodes=4, runs_dir=str(tmp_path / "runs"), progress=False,
                  eval_after_training=False, seed=1)
    values.update(overrides)
    return make(**values).validate()


@pytest.fixture(scope="module")
def trained(tmp_path_factory) -> Path:
    """A run of two episodes with a checkpoint after each (copied by the tests that change it)."""
    return train(small(tmp_path_factory.mktemp("trained")))


def copy_of(run: Path, tmp_path: Path) -> Path:
    return Path(shutil.copytree(run, tmp_path / run.name))


def python(*args, **kwargs) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, *args], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, **kwargs)


def wait_for_lock(run: Path, pid: int, process: subprocess.Popen, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        lock = run / LOCK
        if lock.exists() and lock.read_text().startswith(f"{pid} "):
            return
        assert process.poll() is None, f"the holder ended early: {process.communicate()}"
        time.sleep(0.2)
    raise AssertionError(f"{run}: process {pid} never took the lock")


def kill(process: subprocess.Popen) -> None:
    process.send_signal(signal.SIGKILL)
    process.communicate(timeout=60)


# ---------------------------------------------------------------------------------------- the lock
def test_the_lock_of_a_live_process_refuses_and_the_lock_of_a_killed_one_does_not(trained, tmp_path):
    run = copy_of(trained, tmp_path)
    holder = python("-c", HOLD, str(run))
    try:
        assert holder.stdout.readline().strip() == "locked"
        busy = f"{run} is being written by process {holder.pid} on {os.uname().nodename} (lock file {run / LOCK})"
        with pytest.raises(RunDirBusy, match=re.escape(busy)):
            RunDirLock(run).acquire()
        for args in (["--resume", str(run), "--episodes", "3", *QUIET], ["--eval", "--checkpoint", str(run)]):
            with pytest.raises(SystemExit, match=re.escape(f"error: {busy}; wait for it to finish")):
                main(args)
    finally:
        kill(holder)  # no clean-up: the lock file stays behind
    assert (run / LOCK).read_text().startswith(f"{holder.pid} ")
    with RunDirLock(run) as lock:
        assert (run / LOCK).read_text().startswith(f"{os.getpid()} ")
        with pytest.raises(RunDirBusy):  # a second lock in the same process is refused too
            RunDirLock(run).acquire()
    assert lock.fd is None and not (run / LOCK).exists(), "a clean exit removes the lock file"
    assert ckpt.load(run, memory=False)["episode"] == 2, "the refused runs wrote nothing"


def test_a_second_resume_of_a_live_run_is_refused_and_a_killed_run_resumes(trained, tmp_path):
    """With real training processes: both would otherwise write the same files."""
    run = copy_of(trained, tmp_path)
    first = python("-m", "agents.dqn", "--resume", str(run), "--episodes", "100000", *QUIET)
    try:
        wait_for_lock(run, first.pid, first)
        second = python("-m", "agents.dqn", "--resume", str(run), "--episodes", "100001", *QUIET)
        out, err = second.communicate(timeout=300)
        assert second.returncode != 0, out
        assert err.strip() == f"error: {run} is being written by process {first.pid} on {os.uname().nodename} " \
                              f"(lock file {run / LOCK}); wait for it to finish or stop it, or use another run " \
                              f"directory", err
    finally:
        kill(first)
    assert (run / LOCK).exists(), "SIGKILL leaves the lock file behind"
    done = ckpt.load(run, memory=False)["episode"]
    main(["--resume", str(run), "--episodes", str(done + 1), *QUIET])
    assert ckpt.load(run, memory=False)["episode"] == done + 1
    assert not (run / LOCK).exists()


# ---------------------------------------------------------------------------------------- a full disk
def full_disk_at(monkeypatch, when) -> list[str]:
    """Make ``os.write`` fail with ENOSPC once: at the first write for which ``when(n, path)`` holds
    (n counts the writes from 1, path is the written file). Returns the paths written so far."""
    real, written = os.write, []

    def write(fd, data):
        written.append(os.readlink(f"/proc/self/fd/{fd}"))
        if not failed and when(len(written), written[-1]):
            failed.append(written[-1])
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(fd, data)

    failed = []
    monkeypatch.setattr(os, "write", write)
    return failed


def size_in(message: str) -> float:
    """The size "while writing 1.2 MB" of a full-disk message, in bytes."""
    value, unit = re.search(r"while writing ([\d.]+) (MB|kB)", message).groups()
    return float(value) * (1e6 if unit == "MB" else 1e3)


@pytest.mark.parametrize("target", ["weights.pt", "memory.npz", "meta.json", "metrics.csv", "config.yaml"])
def test_a_full_disk_is_one_line_and_the_last_checkpoint_stays(trained, tmp_path, monkeypatch, target):
    run = copy_of(trained, tmp_path)
    before = ckpt.load(run)
    failed = full_disk_at(monkeypatch, lambda n, path: Path(path).name.startswith((target, f".{target}.")))
    with pytest.raises(SystemExit) as stop:
        main(["--resume", str(run), "--episodes", "4", *QUIET])
    monkeypatch.undo()
    assert failed, f"nothing wrote {target}"
    message = str(stop.value.code)
    assert "\n" not in message and message.startswith("error: "), message
    assert "no space left on device" in message and "free at least" in message and "df -h" in message
    if target in ("weights.pt", "memory.npz", "meta.json"):
        checkpoint = run / "checkpoint"
        assert f"error: {checkpoint}: no space left" in message
        assert message.endswith(f"; the previous checkpoint is intact: continue with --resume {run}")
        saved = sum(f.stat().st_size for f in checkpoint.iterdir())
        assert saved <= size_in(message) < 2 * saved  # the new checkpoint: the old one and a bit more memory
    else:
        assert f"error: {run / target}: no space left" in message
    after = ckpt.load(run)
    assert (after["episode"], after["global_step"]) == (before["episode"], before["global_step"]) == (2, before["global_step"])
    assert not [p.name for p in run.iterdir() if p.name.startswith(".")], "temporary files left behind"
    main(["--resume", str(run), "--episodes", "4", *QUIET])  # once there is space again
    assert ckpt.load(run, memory=False)["episode"] == 4


def test_a_full_disk_at_any_write_of_a_resumed_run(trained, tmp_path, monkeypatch):
    """Whichever write of a resumed run meets the full disk, the error is one line naming a file of
    the run, and the run keeps a loadable checkpoint."""
    run = copy_of(trained, tmp_path)
    written = []
    real = os.write
    monkeypatch.setattr(os, "write", lambda fd, data: written.append(fd) or real(fd, data))
    main(["--resume", str(run), "--episodes", "3", *QUIET])
    monkeypatch.undo()
    assert len(written) >= 6  # lock, config, metrics, checkpoint (3 files), curves
    for n in range(1, len(written) + 1):
        failed = full_disk_at(monkeypatch, lambda i, path: i == n)
        with pytest.raises(SystemExit) as stop:
            main(["--resume", str(run), "--episodes", str(3 + n), *QUIET])
        monkeypatch.undo()
        message = str(stop.value.code)
        assert failed and "\n" not in message and message.startswith(f"error: {run}/"), (n, failed, message)
        assert "no space left on device" in message, message
        assert ckpt.load(run)["episode"] >= 3
        assert not (run / LOCK).exists()
