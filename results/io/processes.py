"""Helper programs (headless Chromium, an off-screen rendering probe) run in a process group of their own.

A browser that is killed alone at its timeout leaves its renderer, GPU and zygote children running
(they are in its process group, not the killer's). :func:`run_group` starts the program as the
leader of a new session and, at the timeout, ends the whole group: SIGTERM, then SIGKILL after a grace
period for whatever is still alive.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess

__all__ = ["GRACE_S", "run_group"]

GRACE_S = 3.0  # seconds the group has to end after SIGTERM before it is killed


def _signal_group(group: int, number: int) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(group, number)


def run_group(command: list[str], timeout_s: float, env: dict | None = None) -> subprocess.CompletedProcess:
    """:func:`subprocess.run` with text output captured, in a new process group that is ended as a whole.

    The group is ended when the timeout passes (then :class:`subprocess.TimeoutExpired` is raised, as
    ``subprocess.run`` raises it), and also when the program ends normally but left children behind.

    Parameters
    ----------
    command : list of str
        The program and its arguments.
    timeout_s : float
        Seconds the program may take.
    env : dict, optional
        Its environment (default: this process's).

    Returns
    -------
    subprocess.CompletedProcess
        Exit status, stdout and stderr (text).
    """
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                               start_new_session=True)
    group = process.pid  # the leader of its own session and group
    try:
        stdout, stderr = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        _signal_group(group, signal.SIGTERM)
        try:
            process.communicate(timeout=GRACE_S)
        except subprocess.TimeoutExpired:
            pass
        _signal_group(group, signal.SIGKILL)
        process.communicate()
        raise
    except BaseException:  # interrupted (Ctrl-C): the helper's group goes with us
        _signal_group(group, signal.SIGKILL)
        process.wait()
        raise
    _signal_group(group, signal.SIGKILL)  # children the program left behind (its own exit did not end them)
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr)
