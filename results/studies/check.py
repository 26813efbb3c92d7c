"""Row-by-row comparison of the model with a published or measured Y / β table (paper 000's by default)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.loadcases.cases import PublishedRow
from rvcoax.results.paths import beta_from_y_deg
from rvcoax.results.studies.discrepancy.measured import MeasuredData, check_stations
from rvcoax.results.sweep import Sweep

__all__ = ["CheckVerdict", "Comparison", "EXIT_IMPLAUSIBLE_FIT", "EXIT_OUTSIDE", "EXIT_WITHIN", "MeasuredTableError",
           "CHECK_QUANTITIES", "Tolerance", "Verdict", "check_verdict", "compare", "measured_rows", "measurement_tolerance",
           "published_values",
           "sweep_values", "verdict", "y_at_stations"]

CHECK_QUANTITIES = ("Y_input_mm", "Y_output_mm", "beta_input_deg", "beta_output_deg")
"""The four values of each row of the published table that the check compares."""


@dataclass(frozen=True)
class Tolerance:
    """Acceptance: |error| ≤ max(relative · |published|, absolute floor).

    The floor (1e-7 mm in Y, the matching arcsin(1e-7 / L) in β) only matters next to the input
    sign change, where the published Y is a few nm and 2 % of it is below any meaningful length.
    """

    relative: float = 0.02
    absolute_y_mm: float = 1e-7
    absolute_y_mm_by_shaft: tuple[tuple[str, float], ...] = ()  # overrides absolute_y_mm for a shaft
    description: str = "2 % of each value (paper 000's rounding), at least 1e-7 mm"

    def limit(self, quantity: str, published: float, length_mm: float) -> float:
        shaft = "input" if "input" in quantity else "output"
        absolute = dict(self.absolute_y_mm_by_shaft).get(shaft, self.absolute_y_mm)
        floor = absolute if quantity.startswith("Y") else float(beta_from_y_deg(absolute, length_mm))
        return max(self.relative * abs(published), floor)


def measurement_tolerance(data: MeasuredData, uncertainty_um: float | None = None,
                          uncertainty_percent: float | None = None) -> Tolerance:
    """The tolerance a measured table is judged with: its measurement uncertainty.

    From the options (``uncertainty_um``, ``uncertainty_percent``) where given, else from the file's
    ``# uncertainty_um`` / ``# uncertainty_percent`` lines; a value is within when |model − measured| ≤
    max(relative · |measured|, absolute). Where neither gives one, 2 % of each value and, as the absolute
    part, one unit of the last digit the file prints (a table's resolution: it cannot be known better),
    and the description says that no uncertainty was given.

    Parameters
    ----------
    data : MeasuredData
        The measured data (:func:`rvcoax.read_measured`).
    uncertainty_um, uncertainty_percent : float, optional
        From the command line; each takes precedence over the file's.

    Returns
    -------
    Tolerance
        With its ``description`` (shown beside the verdict).
    """
    absolute = uncertainty_um if uncertainty_um is not None else data.uncertainty_um
    relative = uncertainty_percent if uncertainty_percent is not None else data.uncertainty_percent
    where = {k: ("the command line" if given is not None else "the file")
             for k, given in (("um", uncertainty_um), ("percent", uncertainty_percent))}
    if absolute is None and relative is None:
        quantum = {s: q for s, q in (data.quantum_mm or {}).items() if math.isfinite(q)}
        resolution = ", ".join(f"{s} {1e3 * q:g} µm" for s, q in quantum.items())
        return Tolerance(0.02, 1e-7, tuple(quantum.items()),
                         "no measurement uncertainty given (--uncertainty-um / --uncertainty-percent, or "
                         "'# uncertainty_um = …' in the file): assumed 2 % of each value"
                         + (f", at least the file's printed resolution ({resolution})" if resolution else ""))
    parts = []
    if absolute is not None:
        parts.append(f"±{absolute:g} µm (from {where['um']})")
    if relative is not None:
        parts.append(f"±{relative:g} % of each value (from {where['percent']})")
    return Tolerance((relative or 0.0) / 100.0, (absolute or 0.0) * 1e-3, (),
                     "measurement uncertainty " + " or ".join(parts) + (", whichever is larger" if len(parts) > 1
                                                                         else ""))


def y_at_stations(station_mm, uy_mm, stations_mm) -> float:
    """The largest |u_y| of a path at ``stations_mm`` (linear between the path's stations), or over
    the whole path when ``stations_mm`` is None."""
    if stations_mm is None:
        return float(np.max(np.abs(uy_mm)))
    return float(np.max(np.abs(np.interp(np.asarray(stations_mm, float), station_mm, uy_mm))))


def sweep_values(sweep: Sweep, rows: tuple[PublishedRow, ...] | None = None) -> dict[str, np.ndarray]:
    """Y_max and β of every case of a sweep, keyed like :data:`CHECK_QUANTITIES`.

    With ``rows`` (one per case) whose stations are given, Y is the largest |u_y| at those stations.
    """
    out: dict[str, list[float]] = {q: [] for q in CHECK_QUANTITIES}
    for i, case in enumerate(sweep.cases):
        for shaft in MEASURED_SHAFTS:
            path = case.paths[shaft]
            stations = None if rows is None else rows[i].stations_mm(shaft)
            if stations is None:
                out[f"Y_{shaft}_mm"].append(path.y_max_mm)
                out[f"beta_{shaft}_deg"].append(path.beta_deg)
            else:
                y = y_at_stations(path.station_mm, path.uy_mm, stations)
                out[f"Y_{shaft}_mm"].append(y)
                out[f"beta_{shaft}_deg"].append(float(beta_from_y_deg(y, path.length_mm)))
    return {q: np.array(v) for q, v in out.items()}


class MeasuredTableError(RvcoaxError, ValueError):
    """Measured data that cannot be compared row by row (the message names the file and the reason)."""


def measured_rows(data: MeasuredData, path_lengths_mm: dict[str, float]) -> tuple[PublishedRow, ...]:
    """A measured-data file (:mod:`rvcoax.results.studies.discrepancy.measured`) as rows of Y/β per case.

    *table*: Y_max per shaft and case; β = arcsin(Y/L) with the rig's path lengths L (paper 000's
    definition). *paths*: per case and shaft, the largest |u_y| over the measured stations (the
    model is then read at the same stations); every case needs stations on both shafts.

    Parameters
    ----------
    data : MeasuredData
        From :func:`rvcoax.read_measured`.
    path_lengths_mm : dict of str to float
        The rig's measured path length per shaft, for β.

    Returns
    -------
    tuple of PublishedRow
        One per case, to pass to :func:`rvcoax.run_check` as ``rows``.
    """
    check_stations(data, path_lengths_mm)
    rows = []
    for k, case in enumerate(data.cases):
        values, stations = {}, {}
        for shaft in MEASURED_SHAFTS:
            here = (data.case_index == k) & (data.shaft == shaft)
            if not here.any():
                raise MeasuredTableError(f"measured data {data.source}: case T1 = {case.input_torque_Nm:g}, "
                                         f"T2 = {case.output_torque_Nm:g} N·m has no value for the {shaft} shaft "
                                         "(the check compares both shafts of every case)")
            values[shaft] = float(np.max(np.abs(data.value_mm[here])))
            stations[shaft] = None if data.schema == "table" else tuple(float(x) for x in data.x_mm[here])
        beta = {s: float(beta_from_y_deg(values[s], path_lengths_mm[s])) for s in MEASURED_SHAFTS}
        rows.append(PublishedRow(case=case, y_input_mm=values["input"], y_output_mm=values["output"],
                                 beta_input_deg=beta["input"], beta_output_deg=beta["output"],
                                 stations_input_mm=stations["input"], stations_output_mm=stations["output"]))
    return tuple(rows)


def published_values(rows: tuple[PublishedRow, ...]) -> dict[str, np.ndarray]:
    return {
        "Y_input_mm": np.array([r.y_input_mm for r in rows]),
        "Y_output_mm": np.array([r.y_output_mm for r in rows]),
        "beta_input_deg": np.array([r.beta_input_deg for r in rows]),
        "beta_output_deg": np.array([r.beta_output_deg for r in rows]),
    }


@dataclass(frozen=True)
class Comparison:
    """Published vs model values with errors; ``within`` per quantity and row."""

    published: dict[str, np.ndarray]
    model: dict[str, np.ndarray]
    absolute_error: dict[str, np.ndarray]
    relative_error: dict[str, np.ndarray]
    within: dict[str, np.ndarray]


def compare(rows: tuple[PublishedRow, ...], sweep: Sweep, tolerance: Tolerance = Tolerance()) -> Comparison:
    """Compare a sweep over the published rows' load cases with the published values."""
    if len(sweep.cases) != len(rows):
        raise ValueError("the sweep must hold exactly the published load cases")
    published = published_values(rows)
    model = sweep_values(sweep, rows)
    lengths = {"input": sweep.rig.paths.input.length_mm, "output": sweep.rig.paths.output.length_mm}
    absolute, relative, within = {}, {}, {}
    for q in CHECK_QUANTITIES:
        length = lengths["input" if "input" in q else "output"]
        absolute[q] = model[q] - published[q]
        relative[q] = absolute[q] / np.abs(published[q])
        limits = np.array([tolerance.limit(q, p, length) for p in published[q]])
        within[q] = np.abs(absolute[q]) <= limits
    return Comparison(published, model, absolute, relative, within)


@dataclass(frozen=True)
class Verdict:
    passed: bool
    worst_row: int
    worst_quantity: str
    worst_relative_error: float
    failures: int


def verdict(comparison: Comparison, held_out: np.ndarray) -> Verdict:
    """Pass when every quantity of every held-out row is within tolerance; name the worst row."""
    failures = sum(int(np.sum(~comparison.within[q][held_out])) for q in CHECK_QUANTITIES)
    worst = (-1.0, -1, "")
    for q in CHECK_QUANTITIES:
        errors = np.where(held_out, np.abs(comparison.relative_error[q]), -1.0)
        i = int(np.argmax(errors))
        if errors[i] > worst[0]:
            worst = (float(errors[i]), i, q)
    return Verdict(failures == 0, worst[1], worst[2], worst[0], failures)


# exit statuses of ``rvcoax check`` (2 is reserved for user errors, as in every command)
EXIT_WITHIN = 0  # every value within tolerance, every fitted parameter plausible
EXIT_OUTSIDE = 1  # a value outside tolerance
EXIT_IMPLAUSIBLE_FIT = 3  # within tolerance only with a fitted parameter outside its plausible range


@dataclass(frozen=True)
class CheckVerdict:
    """What a check concludes: the held-out rows against the tolerance, and the plausibility of the fit.

    Attributes
    ----------
    status : str
        ``within_tolerance`` (every held-out row within tolerance, every fitted parameter plausible),
        ``within_tolerance_implausible_fit`` (within tolerance, but only with a fitted value outside its
        physically plausible range: the model fits the table without explaining it), or
        ``outside_tolerance``.
    text : str
        The verdict as printed: ``"VERDICT: within tolerance"``, ``"VERDICT: fits only with implausible
        parameter(s) …"`` or ``"VERDICT: outside tolerance (n values)"``.
    exit_code : int
        :data:`EXIT_WITHIN`, :data:`EXIT_IMPLAUSIBLE_FIT` or :data:`EXIT_OUTSIDE`.
    implausible : tuple of str
        ``address = value unit (plausible lo .. hi)`` for every implausible fitted parameter.
    """

    status: str
    text: str
    exit_code: int
    implausible: tuple[str, ...]


def check_verdict(held_out: Verdict, fitted) -> CheckVerdict:
    """The check's verdict from the held-out comparison and the fitted parameters.

    Parameters
    ----------
    held_out : Verdict
        :func:`verdict` of the calibrated model on the rows not used to fit.
    fitted : iterable of rvcoax.results.studies.calibration.FittedParameter
        The calibration's fitted parameters (``plausible``, ``fitted_value``, ``parameter``).
    """
    def unit(p) -> str:
        return "" if p.parameter.unit in ("", "-") else f" {p.parameter.unit}"

    implausible = tuple(
        f"{p.parameter.address} ({p.parameter.shaft} shaft) = {p.fitted_value:.4g}{unit(p)} "
        f"(plausible {p.parameter.plausible[0]:g} .. {p.parameter.plausible[1]:g})"
        for p in fitted if not p.plausible)
    if not held_out.passed:
        return CheckVerdict("outside_tolerance", f"VERDICT: outside tolerance ({held_out.failures} held-out "
                            "value(s))", EXIT_OUTSIDE, implausible)
    if implausible:
        return CheckVerdict("within_tolerance_implausible_fit", "VERDICT: within tolerance, but fits only with "
                            "implausible parameter(s): " + "; ".join(implausible), EXIT_IMPLAUSIBLE_FIT, implausible)
    return CheckVerdict("within_tolerance", "VERDICT: within tolerance", EXIT_WITHIN, implausible)
