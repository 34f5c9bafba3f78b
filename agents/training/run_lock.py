"""One writer per run directory: a lock that a second process finds taken.

    with RunDirLock(run_dir):      # RunDirBusy if another live process holds it
        ...                        # train, resume or test into run_dir

The lock is the file ``<run>/.lock``, held with ``fcntl.flock`` while the writer runs; it holds
the writer's pid and host for the error message. The kernel releases a flock when its process
ends, however it ends (SIGKILL included), so the lock of a killed run never blocks a later
``--resume``: the file it leaves behind is simply taken over. A clean exit removes the file.
"""

from __future__ import annotations

import errno
import fcntl
import os
import socket
import sys
from pathlib import Path

from agents.files import disk_full_error, is_disk_full, write_fully

LOCK = ".lock"
"""the lock file inside a run directory"""
UNSUPPORTED = (errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOSYS)
"""flock errors of file systems without locks (some network file systems)"""


class RunDirBusy(ValueError):
    """Another live process is writing the run directory."""


class RunDirLock:
    """The exclusive lock of one run directory (a context manager; ``acquire`` / ``release``)."""

    def __init__(self, run_dir: str | Path):
        self.run_dir = Path(run_dir)
        self.path = self.run_dir / LOCK
        self.fd: int | None = None

    def _holder(self, fd: int) -> str:
        """Who holds the lock, as its file says ("process 123 on host")."""
        try:
            pid, _, host = os.pread(fd, 256, 0).decode(errors="replace").strip().partition(" ")
        except OSError:
            pid, host = "", ""
        return f"process {pid} on {host}" if pid.isdigit() else "another process"

    def acquire(self) -> "RunDirLock":
        """Take the lock or raise ``RunDirBusy`` naming the directory and the process holding it."""
        while True:
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
            except OSError as err:
                if is_disk_full(err):
                    raise disk_full_error(err, self.path, 64) from err
                raise
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = self._holder(fd)
                os.close(fd)
                raise RunDirBusy(f"{self.run_dir} is being written by {holder} (lock file {self.path}); wait "
                                 f"for it to finish or stop it, or use another run directory") from None
            except OSError as err:
                os.close(fd)
                if err.errno not in UNSUPPORTED:
                    raise
                print(f"warning: {self.run_dir}: this file system has no locks; nothing stops a second "
                      f"process from writing this run directory", file=sys.stderr)
                return self
            if self._still_the_lock_file(fd):
                break
            os.close(fd)  # its holder removed it between our open and our flock: take the new one
        try:
            os.ftruncate(fd, 0)
            write_fully(fd, f"{os.getpid()} {socket.gethostname()}\n".encode())
        except OSError as err:
            self.path.unlink(missing_ok=True)
            os.close(fd)
            if is_disk_full(err):
                raise disk_full_error(err, self.path, 64) from err
            raise
        self.fd = fd
        return self

    def _still_the_lock_file(self, fd: int) -> bool:
        try:
            return os.fstat(fd).st_ino == os.stat(self.path).st_ino
        except FileNotFoundError:
            return False

    def release(self) -> None:
        """Remove the lock file and drop the lock (removing first: a process waiting on this file
        finds it gone and opens the next one)."""
        if self.fd is None:
            return
        try:
            self.path.unlink(missing_ok=True)
        finally:
            os.close(self.fd)
            self.fd = None

    def __enter__(self) -> "RunDirLock":
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()
