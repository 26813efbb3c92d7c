"""A sweep that survives interruption: each case is journalled as soon as it is solved, and a resumed
sweep solves only the cases its journal does not already hold (checksums and input hashes verified).

A pure function of (rig, load cases, settings, rig text, journal folder): the command ``rvcoax sweep``
calls it, and so can a notebook or a Dask worker that writes into its own folder.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io import records
from rvcoax.results.io.sweep_files import CaseStore, JournalReading, case_inputs, inputs_sha256, sweep_inputs
from rvcoax.results.sweep import PreparedModel, Sweep, SweepSettings, prepare_model, run_sweep

__all__ = ["DurableSweep", "run_durable_sweep"]


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
        The indices of the cases solved now.
    """

    records: list[dict]
    model: dict
    sweep: Sweep | None
    reading: JournalReading
    solved: tuple[int, ...]


def run_durable_sweep(rig: Rig, cases: tuple[LoadCase, ...], settings: SweepSettings, rig_text: str,  # noqa: PLR0913
                      store: CaseStore, *, resume: bool = False,
                      prepare: Callable[[Rig, SweepSettings], PreparedModel] = prepare_model,
                      progress: Callable[[int, int], None] | None = None,
                      on_plan: Callable[[JournalReading, int], None] | None = None) -> DurableSweep:
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
        ``on_plan(reading, n_to_solve)`` once the journal is read, before anything is solved.

    Returns
    -------
    DurableSweep
        The record of every case (reused from the journal or solved now), the sweep of the cases solved now,
        and what the journal held.
    """
    sha = records.text_sha256(rig_text)
    common = sweep_inputs(sha, settings)
    case_hashes = [inputs_sha256(case_inputs(sha, case, settings, common)) for case in cases]
    model_hash = inputs_sha256(common)
    if resume:
        reading = store.load(case_hashes, model_hash)
    else:
        store.clear()
        reading = JournalReading()
    done, model = reading.cases, reading.model
    missing = [i for i in range(len(cases)) if i not in done]
    if on_plan is not None:
        on_plan(reading, len(missing))
    result = None
    if missing or model is None:
        with store:
            def save(k: int, case_result) -> None:
                done[missing[k]] = records.case_record(case_result)
                store.save(missing[k], case_hashes[missing[k]], done[missing[k]])

            result = run_sweep(rig, tuple(cases[i] for i in missing), settings, progress=progress,
                               prepared=prepare(rig, settings), on_case=save)
            model = records.model_section(result)
            store.save_model(model_hash, model)
    return DurableSweep([done[i] for i in range(len(cases))], model, result, reading, tuple(missing))
