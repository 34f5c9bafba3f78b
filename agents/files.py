"""Files that readers never see half-written: the one place every module writes through.

``atomic_write_bytes`` writes to a temporary file in the same folder, flushes it to disk and
renames it over the target, so a reader (or a run killed mid-write) sees the old content or the
new one, nothing else. ``save_figure`` does the same for a matplotlib figure or a PIL image.

A full disk (``ENOSPC``, or ``EDQUOT``: a full quota) is a ``DiskFullError``: its one-line
message names the file, how much was being written and how much is free there, so that the
command line can stop with it instead of a traceback.
"""

from __future__ import annotations

import errno
import io
import os
import shutil
import tempfile
from pathlib import Path

FULL_DISK = (errno.ENOSPC, errno.EDQUOT)
"""the errno values of a full file system or a full quota"""


class DiskFullError(OSError):
    """A write failed because its file system (or the user's quota) is full; ``str()`` says
    which path, how many bytes it needed and how many are free."""

    def __str__(self) -> str:
        return str(self.strerror)


def megabytes(n: int) -> str:
    """``n`` bytes as a short human-readable size ("512 kB", "3.2 MB", "81.2 GB")."""
    if n >= 1e9:
        return f"{n / 1e9:.1f} GB"
    return f"{n / 1e6:.1f} MB" if n >= 100_000 else f"{max(n, 1) / 1e3:.0f} kB"


def is_disk_full(err: BaseException) -> bool:
    """Whether ``err`` is an OSError of a full file system or quota."""
    return isinstance(err, OSError) and err.errno in FULL_DISK


def disk_full_error(err: OSError, path: str | Path, needed: int, what: str = "") -> DiskFullError:
    """The ``DiskFullError`` of ``err`` (a full disk) while writing ``needed`` bytes to ``path``;
    ``what`` adds what stays intact or what to do next (e.g. about the previous checkpoint)."""
    path = Path(path)
    try:
        free = megabytes(shutil.disk_usage(path.parent).free)
    except OSError:
        free = "unknown"
    kind = "quota exceeded" if err.errno == errno.EDQUOT else "no space left on device"
    message = (f"{path}: {kind} while writing {megabytes(needed)} ({free} free, see `df -h {path.parent}`); "
               f"free at least {megabytes(needed)} there and run again")
    return DiskFullError(err.errno, f"{message}; {what}" if what else message)


def umask() -> int:
    """The process's file-creation mask (read without changing it)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_fully(fd: int, data: bytes) -> None:
    """Write all of ``data`` to the open file descriptor ``fd`` (``os.write`` may write less)."""
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]


def write_synced(path: str | Path, data: bytes, mode: int = 0o666) -> None:
    """Create ``path`` (it must not exist) holding ``data``, flushed to disk: the building block of
    atomic writes, whose callers rename the file into place afterwards."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, mode)
    try:
        write_fully(fd, data)
        os.fsync(fd)
    finally:
        os.close(fd)


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` so that readers see the old or the new content, nothing else.

    A full disk raises ``DiskFullError`` (the old content stays)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        try:
            os.fchmod(fd, 0o666 & ~umask())  # mkstemp makes 0600; give the file the usual mode
            write_fully(fd, data)
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except BaseException as err:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if is_disk_full(err):
            raise disk_full_error(err, path, len(data)) from err
        raise


def replace_folder(staged: str | Path, target: str | Path) -> None:
    """Rename the finished folder ``staged`` to ``target``, replacing a folder there: the old one is
    moved aside first and deleted after, so ``target`` is never half-written."""
    staged, target = Path(staged), Path(target)
    if target.exists():
        aside = target.parent / f".{target.name}.old-{os.urandom(4).hex()}"
        os.replace(target, aside)
        os.replace(staged, target)
        shutil.rmtree(aside, ignore_errors=True)
    else:
        os.replace(staged, target)


def save_figure(figure, path: str | Path, **kwargs) -> None:
    """Save a matplotlib figure (``kwargs`` go to ``savefig``) or a PIL image as a PNG at ``path``,
    atomically."""
    buffer = io.BytesIO()
    if hasattr(figure, "savefig"):
        figure.savefig(buffer, format="png", **kwargs)
    else:
        figure.save(buffer, format="PNG")
    atomic_write_bytes(path, buffer.getvalue())
