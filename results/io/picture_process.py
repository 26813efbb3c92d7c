"""The Y–T picture drawn in a second process, started early so that matplotlib is imported while the model is solved.

``rvcoax check`` spends most of its time on one core (assembly, calibration, files); importing matplotlib and
drawing the picture (about 0.45 s on the 2-core reference machine, benchmarks/RESULTS.md) can use the other one.
:class:`PictureProcess` starts a Python process that imports :mod:`rvcoax.results.io.pictures` and matplotlib at
once and then waits for one request: the picture's numbers (plain arrays, sent as JSON, which repeats every float
exactly) and its file. It calls :func:`rvcoax.results.io.pictures.plot_y_vs_torque` with them, the same function
the serial path calls, so the PNG is the same byte for byte, written atomically the same way.

What the user sees does not change with the process:

- an error while drawing (a file that cannot be written, bad numbers) is raised here, as the same ``OSError``
  (errno, reason, file) where it was one, else as :class:`PictureProcessError` with the worker's message;
- a worker that could not start, or ended without answering (killed, out of memory), is not an error of the
  picture: it is drawn in this process instead;
- nothing is left behind: :meth:`PictureProcess.close` (a ``with`` block calls it) ends a worker that is still
  running and waits for it; a worker whose parent dies reads the end of its input and exits;
- what the worker printed on its standard error (a matplotlib warning) is printed on this one's.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from rvcoax.errors import RvcoaxError

__all__ = ["ANSWER_TIMEOUT_S", "PictureProcess", "PictureProcessError", "picture_request"]

ANSWER_TIMEOUT_S = 300.0
"""Longest wait for the worker's answer once the request is sent (the reference picture takes about 0.2 s)."""

# the worker ends without the interpreter's teardown of matplotlib and numpy (about 0.1 s): the parent waits for its end
_WORKER = ("import os, sys; from rvcoax.results.io.picture_process import _serve; _serve(); "
           "sys.stdout.flush(); sys.stderr.flush(); os._exit(0)")
_ONE_THREAD = {name: "1" for name in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS")}


@contextlib.contextmanager
def _broken_pipe_as_error():
    """Writing to a worker that has ended raises ``BrokenPipeError`` inside this block, never SIGPIPE.

    Python ignores SIGPIPE at start-up, but a host program or a library may restore its default action (the
    test runner's worker processes had it), and then a write to a gone worker would end this process silently.
    Signal actions can be set in the main thread only; elsewhere the action is left as it is.
    """
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "SIGPIPE"):
        yield
        return
    previous = signal.signal(signal.SIGPIPE, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGPIPE, previous)


class PictureProcessError(RvcoaxError, RuntimeError):
    """The picture could not be drawn (the worker's own error, or no answer in :data:`ANSWER_TIMEOUT_S`)."""

    stage = "drawing the picture"


def _plain(rows) -> dict[str, list[float]] | list:
    """Rows as :func:`rvcoax.results.io.pictures.plot_y_vs_torque` reads them, in numbers JSON carries exactly."""
    from rvcoax.results.io.pictures import _series

    data, _ = _series(rows)
    return {key: np.asarray(values, dtype=float).tolist() for key, values in data.items()}


def picture_request(model_rows, path_png: str | Path, *, published=None, **options) -> dict:
    """The arguments of :func:`rvcoax.results.io.pictures.plot_y_vs_torque` as plain numbers (a JSON document).

    Parameters
    ----------
    model_rows, path_png, published
        As :func:`rvcoax.results.io.pictures.plot_y_vs_torque` takes them (Sweeps, CaseResults, PublishedRows, …);
        the rows become arrays, and the path lengths a Sweep carries become ``path_lengths_mm``, so the worker
        draws what the serial call would.
    **options
        That function's keyword arguments (``title``, ``micro``, ``published_label``, …).

    Returns
    -------
    dict
        The request for :meth:`PictureProcess.submit`.
    """
    from rvcoax.geometry import MEASURED_SHAFTS
    from rvcoax.results.io.pictures import _KEYS, _series

    several = isinstance(model_rows, Mapping) and not any(k in model_rows for k in _KEYS)
    groups = {str(k): v for k, v in model_rows.items()} if several else {"model": model_rows}
    series, lengths = {}, {}
    for label, rows in groups.items():
        data, found = _series(rows)
        series[label] = {key: np.asarray(values, dtype=float).tolist() for key, values in data.items()}
        lengths = lengths or found
    if options.get("path_lengths_mm") is None and lengths:
        options["path_lengths_mm"] = [float(lengths[s]) for s in MEASURED_SHAFTS]
    return {"model_rows": series if several else series["model"], "path_png": str(path_png),
            "published": None if published is None else _plain(published), **options}


def _draw(request: dict) -> Path:
    from rvcoax.results.io.pictures import plot_y_vs_torque

    arguments = dict(request)
    lengths = arguments.pop("path_lengths_mm", None)
    return plot_y_vs_torque(arguments.pop("model_rows"), arguments.pop("path_png"),
                            path_lengths_mm=None if lengths is None else tuple(lengths), **arguments)


def _serve() -> None:
    """The worker: import matplotlib now, then draw the one request read from standard input and answer on
    standard output (``{"path": …}`` or ``{"error": …}``); the end of the input without a request ends it."""
    import matplotlib.backends.backend_agg  # noqa: F401  (what savefig draws with)
    import matplotlib.figure  # noqa: F401

    import rvcoax.results.io.pictures  # noqa: F401

    line = sys.stdin.readline()
    if not line.strip():
        return
    try:
        answer = {"path": str(_draw(json.loads(line)))}
    except OSError as error:
        answer = {"error": "OSError", "errno": error.errno, "reason": error.strerror or str(error),
                  "file": None if error.filename is None else str(error.filename)}
    except Exception as error:  # noqa: BLE001  (every error goes back to the parent, which raises it)
        answer = {"error": type(error).__name__, "message": str(error)}
    sys.stdout.write(json.dumps(answer) + "\n")
    sys.stdout.flush()


class PictureProcess:
    """One Y–T picture drawn by a worker process started now (:mod:`module docs <rvcoax.results.io.picture_process>`).

    Use as a context manager around the work whose idle core it uses::

        with PictureProcess() as pictures:
            run = run_check(...)                       # the worker imports matplotlib meanwhile
            pictures.submit(picture_request(...))      # it draws while this process writes the other files
            ...
            path = pictures.result()                   # the PNG's path, or the drawing's error raised here
    """

    def __init__(self) -> None:
        self._request: dict | None = None
        try:
            self._process: subprocess.Popen | None = subprocess.Popen(
                [sys.executable, "-c", _WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                stderr=subprocess.PIPE, text=True, encoding="utf-8", env={**os.environ, **_ONE_THREAD})
        except OSError:
            self._process = None  # no second process here: drawn in this one

    def __enter__(self) -> PictureProcess:
        return self

    def __exit__(self, *_exc) -> None:
        self.close()

    @property
    def submitted(self) -> bool:
        """Whether a request was submitted."""
        return self._request is not None

    def submit(self, request: dict) -> None:
        """Send ``request`` (:func:`picture_request`); the worker draws it while the caller goes on (once only)."""
        if self._request is not None:
            raise ValueError("a picture was submitted already: one process draws one picture")
        self._request = request
        if self._process is None:
            return
        with _broken_pipe_as_error():
            try:
                if self._process.poll() is not None:
                    raise BrokenPipeError("the picture process has ended")
                self._process.stdin.write(json.dumps(request) + "\n")
                self._process.stdin.flush()
            except OSError:  # the worker is gone already (BrokenPipeError): result() draws here
                self._close_input(self._process)  # the unsent request is dropped here, not flushed later
                self._end()
                return
            self._close_input(self._process)

    @staticmethod
    def _close_input(process: subprocess.Popen) -> None:
        """Close the worker's input (its end of the request) and forget it, so that ``communicate`` waits for the
        output only (it would flush a closed input)."""
        stream, process.stdin = process.stdin, None
        if stream is not None:
            try:
                stream.close()
            except OSError:  # BrokenPipeError on the flush: the worker is gone, its answer says so
                pass

    def result(self) -> Path:
        """The submitted picture's path once it is written.

        Raises
        ------
        OSError
            The picture's file could not be written (as the serial call raises it).
        PictureProcessError
            Any other error of the drawing, or no answer within :data:`ANSWER_TIMEOUT_S`.
        """
        if self._request is None:
            raise ValueError("no picture was submitted")
        answer = self._answer()
        if answer is None:  # no worker, or it ended without answering: drawn here, as the serial path does
            return _draw(self._request)
        if "path" in answer:
            return Path(answer["path"])
        if answer["error"] == "OSError" and answer.get("errno") is not None:
            raise OSError(answer["errno"], answer["reason"], answer["file"])
        raise PictureProcessError(f"{answer['error']}: {answer.get('message') or answer.get('reason')}")

    def _answer(self) -> dict | None:
        if self._process is None:
            return None
        try:
            stdout, stderr = self._process.communicate(timeout=ANSWER_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self._end()
            raise PictureProcessError(f"the picture process did not answer within {ANSWER_TIMEOUT_S:g} s") from None
        self._process = None
        if stderr:
            sys.stderr.write(stderr)
        lines = [line for line in stdout.splitlines() if line.startswith("{")]
        try:
            return json.loads(lines[-1]) if lines else None
        except json.JSONDecodeError:
            return None

    def _end(self) -> None:
        """Kill the worker (if running) and wait for it: no zombie."""
        process, self._process = self._process, None
        if process is None:
            return
        process.kill()
        process.communicate()

    def close(self) -> None:
        """Let the worker finish (without a request it reads the end of its input and exits; with one it writes the
        picture) and wait for it; kill it where it does not end within 5 s. No zombie either way."""
        process = self._process
        if process is None:
            return
        try:
            self._close_input(process)
            process.communicate(timeout=5.0)
            self._process = None
        except (OSError, subprocess.TimeoutExpired):
            self._end()
