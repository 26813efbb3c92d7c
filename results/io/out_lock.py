"""One command at a time per output folder: an exclusive lock on ``OUT/.rvcoax.lock``.

Two commands writing into the same ``--out`` would mix or delete each other's files (a second
``sweep`` clears the first one's journal). :func:`output_folder_lock` takes a non-blocking
``fcntl.flock`` on ``OUT/.rvcoax.lock`` and writes its PID there; a second command refuses at once
with :class:`FolderLockedError`, naming the folder and the PID that holds it. Refusing rather than
waiting: a command that waits looks hung, and when it finally ran it would overwrite the first
one's results anyway. The operating system releases the lock when the holder ends, even by
SIGKILL, so a stale lock file never blocks anything.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

from rvcoax.errors import RvcoaxError

__all__ = ["FolderLockedError", "LOCK_NAME", "output_folder_lock"]

LOCK_NAME = ".rvcoax.lock"

try:
    import fcntl
except ImportError:  # not POSIX: no locking
    fcntl = None


class FolderLockedError(RvcoaxError, RuntimeError):
    """Another rvcoax command is writing into the same output folder."""


def _holder(path: Path) -> str:
    try:
        text = path.read_text(encoding="ascii", errors="replace").strip()
    except OSError:
        return "another process"
    return f"process {text}" if text.isdigit() else "another process"


def _locked(path: Path, folder: Path, option: str) -> int:
    """A descriptor of ``path`` holding its exclusive lock (the file that is at ``path`` now, not one
    that a finishing holder has just removed)."""
    while True:
        handle = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(handle)
            raise FolderLockedError(
                f"{option} {folder}: another rvcoax command ({_holder(path)}) is writing into this folder (lock file "
                f"{path}); wait for it to finish, or give another {option} folder") from None
        try:
            if os.fstat(handle).st_ino == os.stat(path).st_ino:
                return handle
        except FileNotFoundError:
            pass
        os.close(handle)  # the holder removed the file between our open and our lock: lock the new one


@contextlib.contextmanager
def output_folder_lock(folder: Path, option: str = "--out") -> Iterator[Path]:
    """Hold the exclusive lock of ``folder`` (created if needed) while the body runs.

    Raises :class:`FolderLockedError` when another process holds it. A folder that this call
    created and that is still empty afterwards (the command failed before writing) is removed.

    Parameters
    ----------
    folder : Path
        The output folder.
    option : str
        The option that named it, for the message.

    Yields
    ------
    Path
        ``folder``, locked.
    """
    folder = Path(folder)
    created = not folder.exists()
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / LOCK_NAME
    if fcntl is None:
        yield folder
        return
    handle = _locked(path, folder, option)
    try:
        os.ftruncate(handle, 0)
        os.pwrite(handle, f"{os.getpid()}\n".encode("ascii"), 0)
        try:
            yield folder
        finally:
            os.ftruncate(handle, 0)
            if created and [p.name for p in folder.iterdir()] == [LOCK_NAME]:
                path.unlink(missing_ok=True)  # still locked: nobody else can hold this file now
                with contextlib.suppress(OSError):
                    folder.rmdir()
    finally:
        os.close(handle)
