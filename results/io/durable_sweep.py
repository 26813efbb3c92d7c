"""A sweep that survives interruption: each case is journalled as soon as it is solved, and a resumed
sweep solves only the cases its journal does not already hold (checksums and input hashes verified).

Nothing read back is trusted as it is: a journal line's checksum is no signature (anyone can write a
line and its SHA-256), so every reused record is also checked for values a solve cannot give
(:func:`rvcoax.results.io.sweep_files.record_problem`), and then solved again where that is cheap:
every reused case of a linear sweep (one factorisation, a back-substitution per case), and
:data:`SPOT_CHECKS` of a nonlinear one (a Newton solve per case) — and every reused case when one of those
disagrees. A recomputed value that differs from the journal's replaces it, and the sweep says how many.

A pure function of (rig, load cases, settings, rig text, journal folder): the command ``rvcoax sweep``
calls it, and so can a notebook or a Dask worker that writes into its own folder.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io import records
from rvcoax.results.io.sweep_files import CaseStore, JournalReading, case_inputs, inputs_sha256, sweep_inputs
from rvcoax.results.sweep import PreparedModel, Sweep, SweepSettings, prepare_model, run_sweep

__all__ = ["DurableSweep", "SPOT_CHECKS", "records_agree", "run_durable_sweep"]

SPOT_CHECKS = 3
"""Reused cases of a nonlinear sweep solved again to check the journal (first, middle and last)."""
RELATIVE_AGREEMENT = 1e-6
"""A recomputed value agrees with the journal's within this fraction of the largest value of its kind."""


@dataclass(frozen=True, eq=False)
class DurableSweep:
    """What :func:`run_durable_sweep` did.

    Attributes
    ----------
    records : list of dict
        The JSON record of every case, in the order of the load cases (reused or solved now).
    model : dict
        The ``model`` section of ``sweep.json`` (:func:`rvcoax.results.io.records.model_section`).
    sweep : Sweep or None
        The sweep of the cases solved now; None when every case came from the journal.
    reading : JournalReading
        What the journal held (empty without ``resume``), with the entries it refused and why.
    solved : tuple of int
        The indices of the cases solved now (missing from the journal, or solved again to check it).
    checked : tuple of int
        The reused cases solved again to check the journal.
    disagreed : tuple of int
        Those of them whose journalled record differed from the recomputation (the recomputed one is used).
    """

    records: list[dict]
    model: dict
    sweep: Sweep | None
    reading: JournalReading
    solved: tuple[int, ...]
    checked: tuple[int, ...] = field(default=())
    disagreed: tuple[int, ...] = field(default=())


def run_durable_sweep(rig: Rig, cases: tuple[LoadCase, ...], settings: SweepSettings, rig_text: str,  # noqa: PLR0913
                      store: CaseStore, *, resume: bool = False,
                      prepare: Callable[[Rig, SweepSettings], PreparedModel] = prepare_model,
                      progress: Callable[[int, int], None] | None = None,
                      on_plan: Callable[[JournalReading, int, int], None] | None = None) -> DurableSweep:
    """Solve ``cases`` on ``rig``, journalling each case in ``store`` as it is solved.

    Parameters
    ----------
    rig, cases, settings
        As for :func:`rvcoax.run_sweep`.
    rig_text : str
        The rig file's text: its SHA-256 is part of every case's input hash.
    store : CaseStore
        The journal (``OUT/cases``). Without ``resume`` it is cleared first.
    resume : bool
        Reuse the journalled cases whose inputs are unchanged and solve only the others.
    prepare : callable
        ``prepare(rig, settings)`` → PreparedModel, called only when a case is left to solve.
    progress : callable, optional
        ``progress(done, total)`` over the cases solved now.
    on_plan : callable, optional
        ``on_plan(reading, n_missing, n_checked)`` once the journal is read, before anything is solved:
        the cases to solve and the reused cases that are solved again to check them.

    Returns
    -------
    DurableSweep
        The record of every case (reused from the journal or solved now), the sweep of the cases solved now,
        and what the journal held.
    """
    from rvcoax.geometry.model.nonlinear_bearings import nonlinear_bearing_names

    sha = records.text_sha256(rig_text)
    common = sweep_inputs(sha, settings)
    case_hashes = [inputs_sha256(case_inputs(sha, case, settings, common)) for case in cases]
    model_hash = inputs_sha256(common)
    if resume:
        torques = [(case.input_torque_Nm, case.output_torque_Nm) for case in cases]
        reading = store.load(case_hashes, model_hash, torques)
    else:
        store.clear()
        reading = JournalReading()
    done, model = reading.cases, reading.model
    missing = [i for i in range(len(cases)) if i not in done]
    reused = sorted(done)
    linear = not nonlinear_bearing_names(rig)
    checked = reused if linear else _spread(reused, SPOT_CHECKS)
    if on_plan is not None:
        on_plan(reading, len(missing), len(checked))
    result, disagreed = None, []
    if missing or checked or model is None:
        prepared = prepare(rig, settings)
        with store:
            def solve(indices: list[int], report=None):
                def save(k: int, case_result) -> None:
                    i, record = indices[k], records.case_record(case_result)
                    if i in done and i not in disagreed and not records_agree(done[i], record):
                        disagreed.append(i)
                    if i not in done or i in disagreed:
                        store.save(i, case_hashes[i], record)
                    done[i] = record
                # a linear sweep is solved in one call: its factorisation goes once the unit loads are solved
                return run_sweep(rig, tuple(cases[i] for i in indices), settings, progress=report, prepared=prepared,
                                 on_case=save, release_solver=linear)

            to_solve = sorted(set(missing) | set(checked))
            result = solve(to_solve, progress)
            if disagreed and not linear and set(reused) - set(checked):
                # a spot check failed: trust none of the journal's cases, and solve them all in one sweep (whose
                # model section then holds every case, as an uninterrupted run's does)
                checked = reused
                to_solve = sorted(set(missing) | set(reused))
                result = solve(to_solve)
            model = _with_every_case(records.model_section(result), done, cases)
            store.save_model(model_hash, model)
    else:
        to_solve = []
    return DurableSweep(records=[done[i] for i in range(len(cases))], model=model, sweep=result, reading=reading,
                        solved=tuple(to_solve), checked=tuple(checked), disagreed=tuple(sorted(disagreed)))


OPERATING_POINT_KEYS = ("ball_bearing_operating_points", "rolling_bearing_operating_points")


def _with_every_case(model: dict, done: dict[int, dict], cases: tuple[LoadCase, ...]) -> dict:
    """``model`` whose bearings' operating points list the rest state and every case, in the order of the load
    cases, as an uninterrupted run lists them: the sweep solved now holds the cases it solved, the journal's
    records (``bearing_operating_points``) the others. A reused record of an older rvcoax without them is left out."""
    for key in OPERATING_POINT_KEYS:
        section = model.get(key)
        if not section:
            continue
        listed = {}
        for name, points in section.items():
            solved = {p["case"]: p for p in points}
            journal = (done[i].get("bearing_operating_points", {}).get(name) for i in range(len(cases)))
            listed[name] = [p for p in [solved.get("at rest")]
                            + [solved.get(case.label) or point for case, point in zip(cases, journal)] if p is not None]
        model[key] = listed
    return records.canonical(model)


def _spread(indices: list[int], count: int) -> list[int]:
    """Up to ``count`` of ``indices``, evenly spread (first, …, last)."""
    if len(indices) <= count:
        return list(indices)
    return sorted({indices[round(k * (len(indices) - 1) / (count - 1))] for k in range(count)})


def records_agree(journalled: dict, recomputed: dict, relative: float = RELATIVE_AGREEMENT) -> bool:
    """Whether a journalled case record holds the values a new solve gives (same fields, same texts; numbers
    within ``relative`` of the largest magnitude of their field, so that rounding noise of another BLAS
    does not count and an edited value does).

    Parameters
    ----------
    journalled, recomputed : dict
        Case records (:func:`rvcoax.results.io.records.case_record`).
    relative : float
        The tolerance, as a fraction of the field's scale.

    Returns
    -------
    bool
        True when every field agrees.
    """
    mine, theirs = _flatten(journalled), _flatten(recomputed)
    if mine.keys() != theirs.keys():
        return False
    scale: dict[str, float] = {}
    for key, value in theirs.items():
        if isinstance(value, float | int) and not isinstance(value, bool):
            field_name = key[1]
            other = mine[key] if isinstance(mine[key], float | int) and not isinstance(mine[key], bool) else 0.0
            # the field's scale from its finite values (an unloaded bearing's infinite life would excuse every other)
            scale[field_name] = max([scale.get(field_name, 0.0)] + [abs(v) for v in (value, other) if math.isfinite(v)])
    for key, value in theirs.items():
        other = mine[key]
        if other == value:  # (also an unloaded bearing's infinite life in both)
            continue
        if isinstance(value, float | int) and not isinstance(value, bool):
            if not (isinstance(other, float | int) and not isinstance(other, bool) and math.isfinite(other)):
                return False
            if abs(other - value) > relative * scale[key[1]]:
                return False
        elif other != value:
            return False
    return True


def _flatten(value, path: tuple = ()) -> dict:
    """{(full path, field name without list indices): scalar} of a JSON value."""
    flat: dict = {}
    stack = [(value, path, "")]
    while stack:
        item, where, name = stack.pop()
        if isinstance(item, dict):
            stack.extend((v, (*where, k), f"{name}.{k}") for k, v in item.items())
        elif isinstance(item, list):
            stack.extend((v, (*where, i), f"{name}[]") for i, v in enumerate(item))
        else:
            flat[(where, name)] = item
    return flat
