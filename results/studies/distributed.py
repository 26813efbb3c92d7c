"""Running independent samples on Dask: a local cluster, an existing cluster, or in this process.

Every sample is one task, ``function(shared, values)``, whose result (a JSON-able dict) is written
to its own file in ``folder`` as soon as it arrives (``sample_000123.json``, atomically), so a run
that stops can be resumed: with ``resume=True`` the samples already on disk are kept (when they
belong to the same study and have the same values) and only the others are computed.

``scheduler``:

``"local"``         a :class:`distributed.LocalCluster` on this machine: ``workers`` processes
                    (default: one per core), one thread each, on the loopback interface.
``"tcp://HOST:PORT"`` an existing Dask scheduler (``dask scheduler`` / ``dask worker``); the
                    workers need the same rvcoax installed.
``"serial"``        no Dask: the samples run one after another in this process.
``"auto"``          serial, or a local cluster when the work pays for it (:func:`choose_scheduler`):
                    the first two samples run in this process and time the set-up and a sample.

A worker that dies loses only its in-flight samples: Dask re-runs them on the other workers, and a
sample that Dask gives up on (``KilledWorker`` after repeated deaths) is submitted again, up to
``retries`` times. The results are returned in sample order, so they do not depend on the number
of workers or on the order in which the samples finish.
"""

from __future__ import annotations

import json
import logging
import os
import time
from collections.abc import Callable
from concurrent.futures import CancelledError
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.results.io.writers import write_json_atomic

__all__ = ["CLUSTER_START_SECONDS", "CLUSTER_STEADY_CORES", "ClusterError", "MANIFEST", "PAYS_BELOW", "ResumeError",
           "RunReport", "SAMPLE_PATTERN", "SampleError", "SchedulerChoice", "TASK_OVERHEAD_SECONDS", "choose_scheduler",
           "future_outcome", "run_samples", "sample_path"]

SAMPLE_PATTERN = "sample_*.json"
MANIFEST = "study.json"

CLUSTER_START_SECONDS = 3.0
"""Start of a local cluster to its first result, without the model's set-up in the workers (measured:
2.8–2.9 s for 1 and 2 workers on 2 cores, benchmarks/RESULTS.md, bench_montecarlo.py)."""
CLUSTER_STEADY_CORES = 1
"""Cores the client and scheduler take from the workers in steady state (measured on 2 cores: 2 workers gave
0.71× the serial rate on beam samples and 0.79× on hybrid ones, i.e. about one core's worth of work)."""
TASK_OVERHEAD_SECONDS = 0.007
"""Per sample on a cluster, on top of its work (measured: 1 worker, steady 34.8 samples/s against 46.2/s in
process for 12.6 ms beam samples)."""
PAYS_BELOW = 0.8
"""The cluster is chosen only when its estimated time is below this fraction of the serial estimate."""


class SampleError(RvcoaxError, RuntimeError):
    """A sample whose evaluation failed (not a lost worker: the model itself raised)."""

    def __init__(self, index: int, reason: str):
        self.index = index
        super().__init__(f"sample {index} failed: {reason}")


class ResumeError(RvcoaxError, ValueError):
    """``resume`` on a folder that holds another study's samples."""


class ClusterError(RvcoaxError, RuntimeError):
    """No Dask cluster to run on (unreachable scheduler, no workers)."""


@dataclass(frozen=True)
class RunReport:
    """How a run went: samples taken from disk, computed, resubmitted after lost workers, seconds; for
    ``scheduler="auto"`` the choice and its estimate (``choice``, else None)."""

    scheduler: str
    workers: int
    n_samples: int
    resumed: int
    computed: int
    resubmitted: int
    seconds: float
    choice: SchedulerChoice | None = None


@dataclass(frozen=True)
class SchedulerChoice:
    """Serial or a local cluster, from the estimated time of each (seconds) for the samples left."""

    scheduler: str
    serial_seconds: float
    cluster_seconds: float
    workers: int

    def describe(self) -> str:
        other = "local cluster" if self.scheduler == "serial" else "serial"
        mine, theirs = ((self.serial_seconds, self.cluster_seconds) if self.scheduler == "serial"
                        else (self.cluster_seconds, self.serial_seconds))
        return (f"{self.scheduler} (estimated {mine:.1f} s for the samples left, {other} {theirs:.1f} s "
                f"with {self.workers} worker(s))")


def choose_scheduler(n_samples: int, seconds_per_sample: float, setup_seconds: float, workers: int | None = None,
                     cores: int | None = None) -> SchedulerChoice:
    """Serial, or a local cluster when it is estimated to take less than :data:`PAYS_BELOW` of the serial time.

    Serial: n t. Cluster: :data:`CLUSTER_START_SECONDS` + the model's set-up in every worker
    + n (t + :data:`TASK_OVERHEAD_SECONDS`) / w_eff, w_eff = min(workers, cores − :data:`CLUSTER_STEADY_CORES`). On 2 cores w_eff = 1 and serial always wins,
    as measured; the cluster pays on more cores for studies whose total work is well above its start-up.

    Parameters
    ----------
    n_samples : int
        Samples left to compute.
    seconds_per_sample, setup_seconds : float
        Measured in this process: one sample on the set-up model, and the model's set-up.
    workers : int, optional
        Local workers (default: one per core).
    cores : int, optional
        Default: ``os.cpu_count()``.
    """
    cores = cores or os.cpu_count() or 1
    workers = workers or cores
    effective = max(1, min(workers, cores - CLUSTER_STEADY_CORES))
    serial = n_samples * seconds_per_sample
    cluster = CLUSTER_START_SECONDS + setup_seconds + n_samples * (seconds_per_sample + TASK_OVERHEAD_SECONDS) / effective
    chosen = "local" if cluster < PAYS_BELOW * serial else "serial"
    return SchedulerChoice(chosen, serial, cluster, workers)


def sample_path(folder: Path, index: int) -> Path:
    return folder / f"sample_{index:06d}.json"


def _load_existing(folder: Path, fingerprint: str, rows: np.ndarray) -> dict[int, dict]:
    """Samples on disk that belong to this study and have this study's values."""
    manifest = folder / MANIFEST
    if manifest.exists():
        try:
            recorded = json.loads(manifest.read_text(encoding="utf-8")).get("fingerprint")
        except (OSError, ValueError, AttributeError):
            recorded = None
        if recorded != fingerprint:
            raise ResumeError(f"--resume: {folder} holds the samples of another study (different tolerance file, "
                              "rig, model, load cases, sampling, seed or number of samples); use another --out "
                              "folder, or run without --resume to start again")
    done = {}
    for path in sorted(folder.glob(SAMPLE_PATTERN)):
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
            index = int(record["index"])
        except (OSError, ValueError, KeyError, TypeError):
            continue  # unreadable: computed again
        if (record.get("fingerprint") == fingerprint and 0 <= index < len(rows)
                and record.get("values") == [float(v) for v in rows[index]]):
            done[index] = record["result"]
    return done


def _start(folder: Path, fingerprint: str, rows: np.ndarray, resume: bool) -> dict[int, dict]:
    folder.mkdir(parents=True, exist_ok=True)
    done = _load_existing(folder, fingerprint, rows) if resume else {}
    if not resume:
        for path in folder.glob(SAMPLE_PATTERN):
            path.unlink()
    write_json_atomic(folder / MANIFEST, {"fingerprint": fingerprint, "n_samples": len(rows)})
    return done


def _connect(stack: ExitStack, scheduler: str, workers: int | None):
    """A Dask client for ``scheduler`` (``local`` or an address), closed with ``stack``."""
    from distributed import Client, LocalCluster

    try:
        if scheduler == "local":
            cluster = stack.enter_context(LocalCluster(
                n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                host="127.0.0.1", dashboard_address=None, silence_logs=logging.ERROR))
            return stack.enter_context(Client(cluster))
        client = stack.enter_context(Client(scheduler, timeout="20s"))
    except (OSError, TimeoutError) as error:
        raise ClusterError(f"cannot connect to the Dask scheduler at {scheduler}: {error}") from None
    if not client.scheduler_info().get("workers"):
        try:
            client.wait_for_workers(1, timeout=60)
        except TimeoutError:
            raise ClusterError(f"the Dask scheduler at {scheduler} has no workers (start some with "
                               f"`dask worker {scheduler}`)") from None
    return client


def _timed_choice(run_here, first: list[int], remaining: int, setup_seconds: float | None,
                  workers: int | None) -> SchedulerChoice:
    """``"auto"``: run the ``first`` samples (up to two) here, timed, and choose where the ``remaining`` ones run.

    The first builds the model (when not built yet), the second reuses it: the second's time is a sample's, the
    difference the set-up every cluster worker would repeat (unless ``setup_seconds`` gives it).
    """
    timed = []
    for index in first:
        begin = time.perf_counter()
        run_here(index)
        timed.append(time.perf_counter() - begin)
    per_sample = timed[-1] if timed else 0.0
    if setup_seconds is None:
        setup_seconds = max(timed[0] - per_sample, 0.0) if timed else 0.0
    return choose_scheduler(remaining, per_sample, setup_seconds, workers)


def run_samples(function: Callable[[object, np.ndarray], dict], shared, rows: np.ndarray, folder: str | Path,  # noqa: PLR0913
                fingerprint: str, *, scheduler: str = "local", workers: int | None = None, resume: bool = False,
                progress: Callable[[int, int], None] | None = None, retries: int = 3,
                on_result: Callable[[int, dict], None] | None = None,
                setup_seconds: float | None = None) -> tuple[list[dict], RunReport]:
    """Evaluate ``function(shared, rows[i])`` for every row; results in row order.

    Parameters
    ----------
    function : callable
        A module-level (picklable) function returning a JSON-able dict.
    shared : object
        Sent once to every worker (e.g. the study).
    rows : (n, d) array
        The sample values.
    folder : path
        Where the per-sample files go.
    fingerprint : str
        Names the study; a resumed sample must carry the same.
    scheduler, workers, resume, retries
        See the module docstring (``"auto"``: :func:`choose_scheduler`).
    progress : callable, optional
        ``progress(done, total)`` after each sample (resumed ones count as done).
    on_result : callable, optional
        ``on_result(index, result)`` after each computed sample is written.
    setup_seconds : float, optional
        ``"auto"`` only: the model's set-up time (every cluster worker repeats it), when the caller has
        measured it (the model is then already set up here); default: the first sample's time less the second's.

    Returns
    -------
    (list of dict, RunReport)
        The results in row order, and how the run went.
    """
    folder = Path(folder)
    rows = np.atleast_2d(np.asarray(rows, dtype=float))
    start = time.perf_counter()
    results = _start(folder, fingerprint, rows, resume)
    resumed = len(results)
    pending = [i for i in range(len(rows)) if i not in results]
    total = len(rows)

    def store(index: int, result: dict) -> None:
        write_json_atomic(sample_path(folder, index), {"fingerprint": fingerprint, "index": index,
                                                       "values": [float(v) for v in rows[index]], "result": result},
                          durable=False)  # a file cut short by a crash is unreadable and computed again
        results[index] = result
        if on_result is not None:
            on_result(index, result)
        if progress is not None:
            progress(len(results), total)

    if progress is not None:
        progress(len(results), total)
    resubmitted, n_workers, choice = 0, 1, None

    def run_here(index: int) -> None:
        try:
            outcome = function(shared, rows[index])
        except Exception as error:  # the model raised: name the sample
            raise SampleError(index, f"{type(error).__name__}: {error}") from error
        store(index, outcome)

    computed_here = 0
    if scheduler == "auto":
        choice = _timed_choice(run_here, pending[:2], len(pending) - len(pending[:2]), setup_seconds, workers)
        computed_here, pending, scheduler = len(pending[:2]), pending[2:], choice.scheduler
    if scheduler == "serial":
        for index in pending:
            run_here(index)
    elif pending:
        with ExitStack() as stack:
            client = _connect(stack, scheduler, workers)
            n_workers = len(client.scheduler_info()["workers"])
            resubmitted = _run_on_cluster(client, function, shared, rows, pending, fingerprint=fingerprint, store=store, retries=retries)
    report = RunReport(scheduler=scheduler, workers=n_workers, n_samples=total, resumed=resumed,
                       computed=computed_here + len(pending), resubmitted=resubmitted,
                       seconds=time.perf_counter() - start, choice=choice)
    return [results[i] for i in range(total)], report


def future_outcome(future) -> tuple[object, BaseException | None]:
    """The result of a completed Dask future, or the error that ended it: ``(result, None)`` or ``(None, error)``.

    The future's state is read again here rather than trusted from the moment it completed: a
    worker that dies right after finishing a task loses the result it held, the future goes back to
    ``lost``/``pending`` and the scheduler computes it again, so ``result()`` waits for that second
    run instead of the sample being taken for failed.
    """
    try:
        return future.result(), None
    except (CancelledError, Exception) as error:  # the task raised, its workers died, or it was dropped
        return None, error


def _run_on_cluster(client, function, shared, rows, pending, *, fingerprint, store, retries) -> int:  # noqa: PLR0913
    """Submit every pending sample, store results as they complete; returns the number resubmitted."""
    from distributed import KilledWorker, as_completed

    remote_shared = client.scatter(shared, broadcast=True, hash=False)
    attempts = dict.fromkeys(pending, 0)

    def submit(index: int):
        key = f"rvcoax-sample-{fingerprint[:16]}-{index}-{attempts[index]}"
        return client.submit(function, remote_shared, rows[index], key=key, pure=False, retries=0)

    owner = {}
    for index in pending:
        owner[submit(index)] = index
    resubmitted = 0
    queue = as_completed(list(owner))
    for future in queue:
        index = owner.pop(future)
        outcome, error = future_outcome(future)
        future.release()
        if error is None:
            store(index, outcome)
            continue
        if isinstance(error, (KilledWorker, CancelledError)) and attempts[index] < retries:
            attempts[index] += 1
            resubmitted += 1
            again = submit(index)
            owner[again] = index
            queue.add(again)
            continue
        hint = (" (are rvcoax and its dependencies installed on every worker?)"
                if isinstance(error, ModuleNotFoundError) else "")
        raise SampleError(index, f"{type(error).__name__}: {error}{hint}")
    return resubmitted
