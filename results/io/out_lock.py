"""One command at a time per output folder: an exclusive lock on ``OUT/.rvcoax.lock``.

Two commands writing into the same ``--out`` would mix or delete each other's files (a second
``sweep`` clears the first one's journal). :func:`output_folder_lock` takes a non-blocking
``fcntl.flock`` on ``OUT/.rvcoax.lock`` and writes its PID there; a second command refuses at once
with :class:`FolderLockedError`, naming the folder and the PID that holds it. Refusing rather than
waiting: a command that waits looks hung, and when it finally ran it would overwrite the first
one's results anyway. The operating system releases the lock when the holder ends, even by
SIGKILL, so a stale lock file never blocks anything.

The lock file is opened without following a symbolic link, and only a small regular file with one
name is used as one: ``OUT/.rvcoax.lock`` made a link to another file (symbolic or hard), a FIFO or a
device is refused with a message, so that taking the lock never writes into a file that is not the
lock. It is never truncated: the PID is written over a fixed-width field.
"""

from __future__ import annotations

import contextlib
import os
import stat
from collections.abc import Iterator
from pathlib import Path

from rvcoax.errors import RvcoaxError

__all__ = ["FolderLockedError", "LOCK_NAME", "output_folder_lock"]

LOCK_NAME = ".rvcoax.lock"
PID_WIDTH = 20  # the lock file holds the holder's PID, right-aligned in this many characters and a newline

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


def _not_a_lock(path: Path, folder: Path, option: str, what: str) -> FolderLockedError:
    return FolderLockedError(f"{option} {folder}: the lock file {path} is {what}, not a lock file of rvcoax; "
                             "nothing was written into it. Remove it (rvcoax creates its own), or give another "
                             f"{option} folder")


def _open_lock_file(path: Path, folder: Path, option: str) -> int:
    """A read-write descriptor of the lock file ``path``, opened without following a link and checked to
    be a small regular file with a single name (so that nothing written to it lands in another file)."""
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        handle = os.open(path, flags, 0o644)
    except OSError as error:
        if os.path.islink(path):
            raise _not_a_lock(path, folder, option, f"a symbolic link to {os.readlink(path)}") from None
        if error.errno is not None and error.filename is None:
            raise OSError(error.errno, error.strerror, str(path)) from None
        raise
    status = os.fstat(handle)
    problem = None
    if not stat.S_ISREG(status.st_mode):
        problem = "not a regular file (a FIFO, device or socket)"
    elif status.st_nlink != 1:
        problem = f"a file with {status.st_nlink} names (a hard link to another file)"
    elif status.st_size > PID_WIDTH + 1:
        problem = f"a file of {status.st_size} bytes (a lock file holds only a process id)"
    if problem is not None:
        os.close(handle)
        raise _not_a_lock(path, folder, option, problem)
    return handle


def _locked(path: Path, folder: Path, option: str) -> int:
    """A descriptor of ``path`` holding its exclusive lock (the file that is at ``path`` now, not one
    that a finishing holder has just removed)."""
    while True:
        handle = _open_lock_file(path, folder, option)
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
        try:
            os.pwrite(handle, f"{os.getpid():>{PID_WIDTH}}\n".encode("ascii"), 0)
        except OSError as error:  # a full file system: ENOSPC from write() names no file
            raise OSError(error.errno, error.strerror, str(path)) from None
        try:
            yield folder
        finally:
            with contextlib.suppress(OSError):
                os.pwrite(handle, f"{'':>{PID_WIDTH}}\n".encode("ascii"), 0)  # no holder now
            if created and [p.name for p in folder.iterdir()] == [LOCK_NAME]:
                path.unlink(missing_ok=True)  # still locked: nobody else can hold this file now
                with contextlib.suppress(OSError):
                    folder.rmdir()
    finally:
        os.close(handle)
