"""Work and memory of a command, estimated from its sizes before any of the work is done.

Every size-like input (load cases, a ``--grid``, the rig's beam nodes, ``--workers``, ``--samples``,
a sensitivity design) goes through :func:`check_workload`: above the memory this machine has available
(:func:`available_memory_bytes`) or above :data:`MAX_WORK_S` of estimated work,
it raises :class:`WorkloadError` with the estimate and a suggestion; above :data:`REPORT_AFTER_S`
the caller prints the estimate (:meth:`Workload.describe`) before it starts.

The per-unit costs are fitted to measurements on the development machine (benchmarks/RESULTS.md, blocks
"geometry/model/workload.py: measured per-unit costs", "bench_montecarlo.py" and "bench_durable_sweep.py");
other machines differ by a small factor, which is what an estimate is for.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from rvcoax.errors import RvcoaxError
from rvcoax.fem.memory import available_memory_bytes

__all__ = ["available_memory_bytes", "BASE_BYTES", "BEAM_ELEMENT_SEGMENT_S", "BEAM_NODE_BYTES", "BEAM_NODE_S", "BEAM_NODE_SPRING_S",
           "BeamSize", "MAX_WORK_S", "REPORT_AFTER_S", "SAMPLE_BYTES", "SAMPLE_CASE_S", "SAMPLE_CASE_S_SOLID",
           "SWEEP_CASE_BYTES", "SWEEP_CASE_S", "WORKER_BYTES", "Workload", "WorkloadError", "beam_size", "check_workload",
           "check_cases", "check_study", "check_workers", "count_text", "duration_text", "rig_problem", "size_text",
           "study_workload", "sweep_workload"]

MAX_WORK_S = 6 * 3600.0  # one command estimated to run longer than this is refused (split it)
REPORT_AFTER_S = 5.0  # work estimated longer than this is announced before it starts

# Per-unit costs. Each value is fitted to a measurement in benchmarks/RESULTS.md, block
# "geometry/model/workload.py: measured per-unit costs" (and, for the samples, "bench_montecarlo.py");
# the table there gives the run behind each constant. Re-measure there, not here.
BASE_BYTES = 0.2e9  # interpreter, numpy/scipy/rich and the rig's beam model: a 1-case sweep's peak RSS
SWEEP_CASE_S = 4.5e-3  # sweep end to end per load case: superposition, equilibrium check, journal, result files
SWEEP_CASE_BYTES = 46e3  # … and its memory per load case
BEAM_NODE_S = 0.48e-3  # beam model per node: assembly, support and sag checks, factorisation, unit solves
BEAM_NODE_BYTES = 9.0e3  # … and its memory per node
BEAM_NODE_SPRING_S = 5.8e-7  # … plus a term in nodes × springs (node look-ups per spring)
BEAM_ELEMENT_SEGMENT_S = 1.5e-7  # … plus a term in elements × segments of a part (segment look-ups)
WORKER_BYTES = 0.25e9  # a local Dask worker process: distributed, rvcoax and the study's beam model, resident
# a Monte Carlo / sensitivity sample, per load case, by reuse strategy (beam model; serial)
SAMPLE_CASE_S = {"loads": 2.5e-3, "frame": 10.8e-3, "full": 40.2e-3}
SAMPLE_CASE_S_SOLID = 7.3  # … hybrid or solid model (4 mm mesh), per load case
SAMPLE_BYTES = 2e3  # per sample and load case: what its record keeps in memory


class WorkloadError(RvcoaxError, ValueError):
    """Work or memory beyond what this machine can do: the message has the estimate and a suggestion."""


@dataclass(frozen=True)
class Workload:
    """The estimated cost of a piece of work.

    Attributes
    ----------
    what : str
        The work in the user's terms (``"9,000,000 load cases (--grid: 3,000 × 3,000)"``).
    seconds : float
        Estimated time on this machine class.
    bytes_needed : float
        Estimated peak memory.
    """

    what: str
    seconds: float
    bytes_needed: float

    def describe(self) -> str:
        """``"about 12 min and 3.2 GB"``."""
        return f"about {duration_text(self.seconds)} and {size_text(self.bytes_needed)}"


def duration_text(seconds: float) -> str:
    """A duration for people: ``4.2 s``, ``12 min``, ``3.5 h``, ``41 days``, ``3e+08 years``."""
    if seconds < 60:
        return f"{seconds:.2g} s"
    if seconds < 3600:
        return f"{seconds / 60:.0f} min"
    if seconds < 86400 * 2:
        return f"{seconds / 3600:.2g} h"
    if seconds < 86400 * 365 * 2:
        return f"{seconds / 86400:.0f} days"
    return f"{seconds / (86400 * 365):.2g} years"


def size_text(n_bytes: float) -> str:
    """A memory size: ``350 MB``, ``3.2 GB``, ``1.4e+04 GB``."""
    return f"{n_bytes / 1e6:.0f} MB" if n_bytes < 1e9 else f"{n_bytes / 1e9:.3g} GB"


def count_text(n: float) -> str:
    """``9,000,000``, or ``1e+15`` beyond what a thousands separator makes readable.

    Parameters
    ----------
    n : float
        A count.

    Returns
    -------
    str
        The count with thousands separators, or in exponent notation when very large.
    """
    return f"{n:,.0f}" if n < 1e12 else f"{n:.3g}"


def check_workload(workload: Workload, subject: str, suggestion: str) -> Workload:
    """Raise :class:`WorkloadError` when ``workload`` exceeds the memory available or :data:`MAX_WORK_S`.

    Parameters
    ----------
    workload : Workload
        The estimate.
    subject : str
        The input that asks for the work (file or option).
    suggestion : str
        What to do instead, appended to the message.

    Returns
    -------
    Workload
        ``workload``, when it fits.

    Raises
    ------
    WorkloadError
        With the estimate, what is available and ``suggestion``.
    """
    room = available_memory_bytes()
    if room is not None and workload.bytes_needed > room:
        why = f"only {size_text(room)} of memory are available"
    elif workload.seconds > MAX_WORK_S:
        why = f"more than the {duration_text(MAX_WORK_S)} one command may take"
    else:
        return workload
    raise WorkloadError(f"{subject}: {workload.what} would take {workload.describe()} (estimated from measured "
                        f"per-unit costs), {why}; {suggestion}. Nothing was solved.")


def sweep_workload(n_cases: int, what: str | None = None) -> Workload:
    """A sweep of ``n_cases`` load cases on the beam model (solving, journal, result files).

    Parameters
    ----------
    n_cases : int
        How many load cases.
    what : str, optional
        The cases in the user's terms; default ``"N load cases"``.

    Returns
    -------
    Workload
        Estimated time and peak memory.
    """
    return Workload(what or f"{count_text(n_cases)} load cases", SWEEP_CASE_S * n_cases,
                    BASE_BYTES + SWEEP_CASE_BYTES * n_cases)


def check_cases(n_cases: int, subject: str, what: str | None = None) -> Workload:
    """Refuse a sweep of ``n_cases`` that would not fit (before the cases are built, for a grid).

    Parameters
    ----------
    n_cases : int
        How many load cases.
    subject : str
        The input that asks for them (``--grid``, a load-case file), for the message.
    what : str, optional
        The cases in the user's terms; default ``"N load cases"``.

    Returns
    -------
    Workload
        The estimate, when it fits.

    Raises
    ------
    WorkloadError
        Naming ``subject``, the estimate and how many cases would fit.
    """
    fitting = _largest_fitting(sweep_workload)
    return check_workload(sweep_workload(n_cases, what), subject,
                          f"split the load cases into sweeps of at most {count_text(fitting)} cases (each with its own --out)")


def _largest_fitting(workload_of) -> int:
    """The largest n whose ``workload_of(n)`` fits in memory and time (bisection on a monotone cost)."""
    room = available_memory_bytes()
    low, high = 0, 1
    while high < 10**18 and _fits(workload_of(high), room):
        low, high = high, high * 2
    while high - low > 1:
        middle = (low + high) // 2
        low, high = (middle, high) if _fits(workload_of(middle), room) else (low, middle)
    return low


def _fits(workload: Workload, room: float | None) -> bool:
    return (room is None or workload.bytes_needed <= room) and workload.seconds <= MAX_WORK_S


# ------------------------------------------------------------------------------------------ rig


@dataclass(frozen=True)
class BeamSize:
    """The beam model of a rig, counted from its geometry without building it."""

    nodes: int
    springs: int
    element_segment_pairs: float  # Σ over parts of (elements × segments)

    def workload(self, element_length_mm: float) -> Workload:
        seconds = (BEAM_NODE_S * self.nodes + BEAM_NODE_SPRING_S * self.nodes * self.springs
                   + BEAM_ELEMENT_SEGMENT_S * self.element_segment_pairs)
        return Workload(f"a beam model of about {count_text(self.nodes)} nodes ({count_text(self.springs)} springs, "
                        f"max_element_length_mm = {element_length_mm:g} mm)", seconds,
                        BASE_BYTES + BEAM_NODE_BYTES * self.nodes)


def beam_size(rig) -> BeamSize:
    """Nodes, springs and element × segment look-ups of ``rig``'s beam model (an upper estimate).

    Each part has a node at each segment end and at each place something refers to, and elements
    at most ``mesh.max_element_length_mm`` long in between: counted, not built.

    Parameters
    ----------
    rig : Rig
        A validated rig; its beam model is counted, not built.

    Returns
    -------
    BeamSize
        Nodes, springs and element × segment pairs; ``.workload(max_element_length_mm)`` estimates the build.
    """
    length = rig.mesh.max_element_length_mm
    springs = len(rig.bearings) + len(rig.mounts) + len(rig.couplings) + len(rig.joints)
    # every spring end, load and path station may add a node; bounded by the springs and a few per part
    nodes = 2.0 * springs + 64.0
    pairs = 0.0
    for part in rig.parts:
        elements = sum(max(1.0, math.ceil((s.x_mm[1] - s.x_mm[0]) / length - 1e-9)) for s in part.segments)
        nodes += elements + 1.0
        pairs += elements * len(part.segments)
    return BeamSize(int(min(nodes, 1e30)), springs, pairs)


def rig_problem(rig) -> str | None:
    """Why ``rig``'s beam model is too large to build here (with the estimate and a suggestion), or None.

    Parameters
    ----------
    rig : Rig
        A validated rig, before its beam model is built.

    Returns
    -------
    str or None
        The reason, naming the rig-file keys that set the size; None when the model fits.
    """
    size = beam_size(rig)
    length = rig.mesh.max_element_length_mm
    workload = size.workload(length)
    fitting = _largest_fitting(lambda nodes: BeamSize(nodes, size.springs, 0).workload(length))
    coarser = length * size.nodes / max(fitting, 1)
    suggestion = (f"raise [mesh] max_element_length_mm to {coarser:.2g} mm or more (5 mm is the default), "
                  "or describe the rig with fewer parts and segments")
    try:
        check_workload(workload, "the rig's parts, segments and [mesh] max_element_length_mm", suggestion)
    except WorkloadError as error:
        return str(error)
    return None


# ------------------------------------------------------------------------------------------ studies


def check_workers(workers: int | None, option: str = "--workers") -> int | None:
    """Refuse more local Dask workers than this machine has cores for, or memory for.

    Parameters
    ----------
    workers : int or None
        Requested local worker processes; None leaves the choice to Dask.
    option : str
        The option, for the message.

    Returns
    -------
    int or None
        ``workers``, when the machine can run them.

    Raises
    ------
    WorkloadError
        Naming the option, the cores and memory available, and a number that fits.
    """
    if workers is None:
        return None
    cores = os.cpu_count() or 1
    room = available_memory_bytes()
    by_memory = int(max(room - BASE_BYTES, 0) // WORKER_BYTES) if room is not None else workers
    limit = max(1, min(4 * cores, by_memory))
    if workers > limit:
        raise WorkloadError(f"{option} {workers}: this machine has {cores} core(s) and {size_text(room or 0)} of memory "
                            f"available; each worker process needs about {size_text(WORKER_BYTES)} and more workers "
                            f"than cores do not run faster; use --workers {min(cores, limit)} (or at most {limit})")
    return workers


def study_workload(n_solves: int, n_parameters: int, n_cases: int, what: str, model: str = "beam",  # noqa: PLR0913
                   *, strategy: str = "full") -> Workload:
    """A Monte Carlo or sensitivity study of ``n_solves`` samples, each solving ``n_cases`` load cases
    (``strategy``: what a sample re-assembles, :data:`rvcoax.results.studies.montecarlo.STRATEGIES`)."""
    per_case = SAMPLE_CASE_S.get(strategy, SAMPLE_CASE_S["full"]) if model == "beam" else SAMPLE_CASE_S_SOLID
    return Workload(what, per_case * n_solves * max(n_cases, 1),
                    BASE_BYTES + n_solves * (SAMPLE_BYTES * max(n_cases, 1) + 8.0 * (3 * n_parameters + 8)))


def check_study(n_solves: int, n_parameters: int, n_cases: int, option: str, what: str, *, model: str = "beam",  # noqa: PLR0913
                strategy: str = "full") -> Workload:
    """Refuse a study design too large for this machine, before it is drawn.

    Parameters
    ----------
    n_solves : int
        Samples (Monte Carlo) or model runs (sensitivity design).
    n_parameters : int
        Toleranced parameters.
    n_cases : int
        Load cases each sample solves.
    option : str
        The option that sets the size (``--samples``), for the message.
    what : str
        The study in the user's terms.
    model : str
        ``beam``, ``hybrid`` or ``solid``.
    strategy : str
        What a sample re-assembles (``loads``, ``frame``, ``full``).

    Returns
    -------
    Workload
        Time and memory of the whole study, when they fit.

    Raises
    ------
    WorkloadError
        Naming ``option``, the estimate and the largest size that fits.
    """
    fitting = _largest_fitting(lambda n: study_workload(n, n_parameters, n_cases, "", model, strategy=strategy))
    return check_workload(study_workload(n_solves, n_parameters, n_cases, what, model, strategy=strategy), option,
                          f"use a smaller {option} (at most about {count_text(fitting)} solves here), or run the study on a "
                          "Dask cluster in parts with --resume")
