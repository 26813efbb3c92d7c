"""The published-table check as one workflow: blind sweep → calibration → calibrated sweep → comparison → verdict.

A pure function of (rig, published rows, settings): the command ``rvcoax check``, a notebook and a
Dask worker all call :func:`run_check`; writing the files is :func:`rvcoax.results.reports.check_files.write_check`.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.geometry.builtin import is_reference_rig
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import PublishedRow, paper_table
from rvcoax.results.studies.calibration import (
    DEFAULT_PARAMETERS,
    Calibration,
    calibrate,
    loads_with_trials,
    solve_with_trials,
)
from rvcoax.results.studies.check import CheckVerdict, Comparison, Tolerance, Verdict, check_verdict, compare, verdict
from rvcoax.results.sweep import PreparedModel, Sweep, SweepSettings, prepare_model, run_sweep

__all__ = ["CalibrationError", "CheckRun", "MissingTableError", "NO_TABLE_HELP", "fit_output_torques", "held_out_mask", "run_check"]


class CalibrationError(RvcoaxError, ValueError):
    """The rig lacks a parameter that the check's calibration fits."""


@dataclass(frozen=True, eq=False, kw_only=True)
class CheckRun:
    """Everything the check computed.

    Attributes
    ----------
    rows : tuple of PublishedRow
        The published table compared with.
    blind, calibrated : Sweep
        The rig as built, and the rig with the calibrated parameters.
    calibration : Calibration
        The fitted parameters and the rows used to fit them.
    comparison_blind, comparison_calibrated : Comparison
        Row-by-row errors against the table.
    held_out : ndarray of bool
        The rows not used to fit (the calibrated verdict is judged on these only).
    blind_verdict, calibrated_verdict : Verdict
        Blind on every row; calibrated on the held-out rows.
    outcome : CheckVerdict
        The verdict with its status, text and exit code.
    """

    rows: tuple[PublishedRow, ...]
    blind: Sweep
    calibration: Calibration
    calibrated: Sweep
    comparison_blind: Comparison
    comparison_calibrated: Comparison
    held_out: np.ndarray
    blind_verdict: Verdict
    calibrated_verdict: Verdict
    outcome: CheckVerdict


NO_TABLE_HELP = ("paper 000's table belongs to the built-in reference rig only; compare this rig with its own "
                 "measured Y (command line: check --measured FILE; Python: run_check(rig, rows=measured_rows(...))), "
                 "FILE a CSV with columns T1_input_Nm, "
                 "T2_output_Nm, Y_input_mm, Y_output_mm (a table), or T1_input_Nm, T2_output_Nm, shaft, x_mm, uy_mm "
                 "(measured paths), at least three load cases with two different T2")
"""What the check tells a user whose rig has no table to compare with: give its own measured Y."""


class MissingTableError(RvcoaxError, ValueError):
    """A check of a rig other than the reference rig without a table to compare with."""


def fit_output_torques(rows: tuple[PublishedRow, ...]) -> tuple[float, float]:
    """The output torques whose rows the calibration fits: the smallest and the largest T2 of the table
    (paper 000's table: T2 = 10 and 200 N·m); every other row is a prediction.

    Parameters
    ----------
    rows : tuple of PublishedRow
        The table the check compares with.

    Returns
    -------
    (float, float)
        The smallest and the largest T2 (N·m).

    Raises
    ------
    CalibrationError
        Fewer than three rows, or fewer than two different T2.
    """
    torques = sorted({r.case.output_torque_Nm for r in rows})
    if len(torques) < 2 or len(rows) < 3:
        raise CalibrationError(f"the table has {len(rows)} row(s) with {len(torques)} different T2: the check fits "
                               "two rows (the smallest and the largest T2) and judges the others, so it needs at "
                               "least three rows with two different T2")
    return torques[0], torques[-1]


def held_out_mask(n_rows: int, fit_rows) -> np.ndarray:
    """True for the rows not used to fit."""
    mask = np.ones(n_rows, dtype=bool)
    mask[list(fit_rows)] = False
    return mask


def check_loads_ahead(rig: Rig):
    """``loads_ahead`` for :func:`rvcoax.results.sweep.prepare_model` of a model that :func:`run_check` will check.

    The rig's unit loads and those of the calibration's trial rigs are then solved in the set-up's own solve call
    where it makes one (the hybrid model: two solve calls, passes over the whole factor, fewer).

    Parameters
    ----------
    rig : Rig
        The rig to be checked, as :func:`rvcoax.load_rig` returns it.

    Returns
    -------
    callable
        ``loads_ahead(system)`` → the load vectors on an assembled system of ``rig``
        (:func:`rvcoax.results.studies.calibration.loads_with_trials`).
    """
    return functools.partial(loads_with_trials, rig)


def run_check(rig: Rig, rows: tuple[PublishedRow, ...] | None = None, settings: SweepSettings | None = None,  # noqa: PLR0913
              prepared: PreparedModel | None = None, *,
              progress: Callable[[str, int, int], None] | None = None,
              tolerance: Tolerance | None = None) -> CheckRun:
    """Compare ``rig`` with a published Y/β table, blind and calibrated.

    Parameters
    ----------
    rig : Rig
        The rig, as :func:`rvcoax.load_rig` returns it.
    rows : tuple of PublishedRow, optional
        The table to compare with (:func:`rvcoax.results.studies.check.measured_rows` turns a
        measured-data file into rows); omitted: paper 000's, for the built-in reference rig only.
    settings : SweepSettings, optional
        Model fidelity, solver and mesh size (the beam model's defaults when omitted).
    prepared : PreparedModel, optional
        An assembled, factorised model of ``rig`` to reuse (set up with :func:`check_loads_ahead`'s loads, it has
        them solved already).
    progress : callable, optional
        ``progress(stage, done, total)`` with stage ``"blind sweep"``, ``"calibrating"`` or
        ``"calibrated sweep"``.
    tolerance : Tolerance, optional
        What a value must be within: paper 000's 2 % by default; for measured data their measurement
        uncertainty (:func:`rvcoax.results.studies.check.measurement_tolerance`).

    Returns
    -------
    CheckRun

    Raises
    ------
    CalibrationError
        The rig lacks a parameter the calibration fits, or the table has too few rows to fit and judge.
    MissingTableError
        ``rows`` omitted for a rig other than the built-in reference rig.
    """
    if rows is None:
        if not is_reference_rig(rig):
            raise MissingTableError(f"rig '{rig.rig.name}': {NO_TABLE_HELP}")
        rows = paper_table()
    settings = SweepSettings() if settings is None else settings
    cases = tuple(r.case for r in rows)
    prepared = prepare_model(rig, settings, loads_ahead=check_loads_ahead(rig)) if prepared is None else prepared

    def sweep(on: Rig, stage: str) -> Sweep:
        report = None if progress is None else (lambda i, n: progress(stage, i, n))
        return run_sweep(on, cases, settings, progress=report, prepared=prepared)

    solve_with_trials(rig, prepared)  # the blind rig's and the calibration's unit loads in one solve call
    blind = sweep(rig, "blind sweep")
    if progress is not None:
        progress("calibrating", 0, 1)
    try:
        calibration = calibrate(rig, rows, fit_output_torques_Nm=fit_output_torques(rows), settings=settings,
                                prepared=prepared)
    except KeyError as error:
        raise CalibrationError(f"cannot calibrate: {error.args[0]} (the check fits "
                               + ", ".join(p.address for p in DEFAULT_PARAMETERS) + ")") from None
    if progress is not None:
        progress("calibrating", 1, 1)
    calibrated = sweep(calibration.rig, "calibrated sweep")
    tolerance = Tolerance() if tolerance is None else tolerance
    comparison_blind, comparison_calibrated = compare(rows, blind, tolerance), compare(rows, calibrated, tolerance)
    held_out = held_out_mask(len(rows), calibration.fit_rows)
    calibrated_verdict = verdict(comparison_calibrated, held_out)
    blind_verdict = verdict(comparison_blind, np.ones(len(rows), dtype=bool))
    return CheckRun(rows=rows, blind=blind, calibration=calibration, calibrated=calibrated,
                    comparison_blind=comparison_blind, comparison_calibrated=comparison_calibrated, held_out=held_out,
                    blind_verdict=blind_verdict, calibrated_verdict=calibrated_verdict,
                    outcome=check_verdict(calibrated_verdict, calibration.parameters))
