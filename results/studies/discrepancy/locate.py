"""Locate a gap: noise level, scaled residuals, a χ² test, and the structure of the residual.

σ of an observation combines the measurement noise and a model-form allowance:
``σ² = σ_noise² + (f_model · s)²`` with ``s`` the RMS of the measured values of the same shaft in
the same case (a model that differs in form by a fraction ``f_model`` of the signal is not a gap).

σ_noise comes from the file's ``sigma_mm`` column when present; otherwise it is estimated from the
data alone, independent of any model:
- *paths*: the scatter about a cubic in x fitted to each (case, shaft) path with at least six
  stations (a beam deflection between supports is a cubic), pooled per shaft;
- *table*: the scatter of each value about the line through its two neighbours along the torque
  sweep (their RMS, a value far off the line left out), never below the rounding of the printed digits.

A σ read from a table's few misses is itself uncertain: it carries ν degrees of freedom (:attr:`NoiseEstimate.dof`),
and the gap test reads χ²/n against Snedecor's F(n, ν) instead of χ²_n/n (:func:`gap_test`, :func:`detection_norm`).
σ from the file, from the printed digits or from the many stations of paths files counts as known (ν = ∞: the χ² test).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.studies.discrepancy.measured import MeasuredData

__all__ = ["GapTest", "NoiseEstimate", "StructureFinding", "critical_chi2", "curvature_beyond_allowance",
           "detection_norm", "estimate_noise", "gap_p_value", "gap_test", "group_rms", "residual_structure"]


@dataclass(frozen=True)
class NoiseEstimate:
    """σ per observation (mm) and how it was obtained, per shaft.

    ``dof`` holds, per shaft, the degrees of freedom ν of σ_noise² (∞ where σ_noise counts as known) and ``share`` the
    part of every observation's σ² that σ_noise² makes (the model-form allowance is set, not estimated)."""

    sigma_mm: np.ndarray
    noise_mm: dict[str, float]
    method: dict[str, str]
    dof: dict[str, float] = field(default_factory=dict)
    share: np.ndarray | None = None

    def degrees_of_freedom(self, rows: np.ndarray | None = None, shaft: np.ndarray | None = None) -> float:
        """ν of the σ² that scales χ² over ``rows`` (every observation when None), shafts combined by matching the
        variance of the mean relative error of σ² (Satterthwaite): 1/ν = Σ_shaft (Σ_i share_i / n)² / ν_shaft.
        ``shaft`` gives the shaft of every observation (the data's)."""
        if self.share is None or shaft is None or not any(np.isfinite(v) for v in self.dof.values()):
            return np.inf
        share, shaft = (self.share, shaft) if rows is None else (self.share[rows], shaft[rows])
        if share.size == 0:
            return np.inf
        inverse = sum((share[shaft == s].sum() / share.size) ** 2 / nu for s, nu in self.dof.items()
                      if np.isfinite(nu) and nu > 0)
        return 1.0 / inverse if inverse > 0 else np.inf


def group_rms(data: MeasuredData) -> np.ndarray:
    """RMS of the measured values of the same (case, shaft) as each observation."""
    rms = np.zeros(data.n)
    for case in np.unique(data.case_index):
        for shaft in MEASURED_SHAFTS:
            mask = (data.case_index == case) & (data.shaft == shaft)
            if mask.any():
                rms[mask] = np.sqrt(np.mean(data.value_mm[mask] ** 2))
    return rms


def _paths_noise(data: MeasuredData, shaft: str) -> tuple[float, str]:
    squares, dof = 0.0, 0
    for case in np.unique(data.case_index):
        mask = (data.case_index == case) & (data.shaft == shaft)
        if mask.sum() >= 6:
            x, y = data.x_mm[mask], data.value_mm[mask]
            scale = max(np.ptp(x), 1e-12)
            coefficients = np.polyfit((x - x.mean()) / scale, y, 3)
            squares += float(np.sum((y - np.polyval(coefficients, (x - x.mean()) / scale)) ** 2))
            dof += int(mask.sum()) - 4
    if dof > 0:
        return float(np.sqrt(squares / dof)), f"scatter about cubic fits of {shaft} paths ({dof} degrees of freedom)"
    values = data.value_mm[data.shaft == shaft]
    return 0.01 * float(np.sqrt(np.mean(values ** 2))) if values.size else 0.0, \
        "assumed 1 % of the RMS signal (fewer than six stations per path)"


OUTLIER_ALPHA = 0.01  # the chance that a table's sweep without a kink loses a value to the outlier test


def _neighbour_weights(t: np.ndarray):
    """(i, w) of every value with a neighbour on each side along the sweep: the line through them predicts
    w·y[i − 1] + (1 − w)·y[i + 1] at t[i]."""
    for i in range(1, t.size - 1):
        span = t[i + 1] - t[i - 1]
        if span > 0:
            yield i, (t[i + 1] - t[i]) / span


def _neighbour_residuals(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each value's miss of the line through its two neighbours along the sweep, scaled to the noise's σ (for equal
    noise the miss has variance σ²·(1 + w² + (1 − w)²)), and the index of that value."""
    misses, middles = [], []
    for i, w in _neighbour_weights(t):
        predicted = w * y[i - 1] + (1 - w) * y[i + 1]
        misses.append(abs(y[i] - predicted) / np.sqrt(1 + w ** 2 + (1 - w) ** 2))
        middles.append(i)
    return np.array(misses), np.array(middles, dtype=int)


def _misses_dof(t: np.ndarray) -> float:
    """Degrees of freedom of the mean square of the scaled misses along a sweep at ``t`` (normal noise of equal σ).
    Neighbouring misses share values (a correlation of about −2/3 for an even sweep, 1/6 two apart), so their mean
    square is not χ²_m/m: its two moments match χ²_ν/ν with ν = (tr C)²/tr(C²), C their correlation matrix (ν ≈ 2.9
    for the 5 misses of a 7-case sweep, 9.5 for 18 misses of 20 cases)."""
    rows = []
    for i, w in _neighbour_weights(t):
        row = np.zeros(t.size)
        row[i - 1:i + 2] = -w, 1.0, -(1 - w)
        rows.append(row / np.linalg.norm(row))
    if not rows:
        return np.inf
    c = np.array(rows) @ np.array(rows).T
    return float(np.trace(c) ** 2 / np.sum(c ** 2))


def _sweep_scatter(t: np.ndarray, y: np.ndarray) -> tuple[float, int, int, float]:
    """σ of values along a sweep: the RMS of their misses of the line through their neighbours, after leaving out, one
    at a time, a value whose miss the others' RMS makes improbable (beyond Student's t with m − 1 degrees of freedom at
    :data:`OUTLIER_ALPHA`, shared over the m misses): a misread value or a sharp kink of |Y_max| (the station of the
    maximum switching) would otherwise set σ. The RMS keeps the precision of every miss: their median (37 % efficient
    for normal noise) misjudges σ by more than a factor 0.6 or 1.6 in one file of ten from the 18 misses of a 20-case
    sweep, the RMS by 0.65 or 1.35. Returns (σ, misses used, values left out, degrees of freedom of σ²)."""
    keep = np.ones(t.size, bool)
    while True:
        misses, middles = _neighbour_residuals(t[keep], y[keep])
        m = misses.size
        if m < 4:
            break
        worst = int(np.argmax(misses))
        others = float(np.sqrt((misses @ misses - misses[worst] ** 2) / (m - 1)))
        if not (others > 0 and misses[worst] > stats.t.isf(OUTLIER_ALPHA / (2 * m), m - 1) * others):
            break
        keep[np.flatnonzero(keep)[middles[worst]]] = False
    sigma = float(np.sqrt(np.mean(misses ** 2))) if misses.size else 0.0
    return sigma, int(misses.size), int(t.size - keep.sum()), _misses_dof(t[keep])


def _table_noise(data: MeasuredData, shaft: str) -> tuple[float, str, float]:
    mask = data.shaft == shaft
    torque = np.array([c.input_torque_Nm if shaft == "input" else c.output_torque_Nm for c in data.cases])
    t, y = torque[data.case_index[mask]], data.value_mm[mask]
    order = np.argsort(t)
    t, y = t[order], y[order]
    quantum = (data.quantum_mm or {}).get(shaft, 0.0)
    floor = quantum / np.sqrt(12.0)
    estimate, used, left_out, dof = _sweep_scatter(t, y)
    if used >= 3 and estimate > floor:
        return estimate, (f"scatter about neighbours along the sweep ({used} points, RMS, {dof:.3g} degrees of freedom"
                          + (f"; {left_out} value(s) far off the line left out)" if left_out else ")")), dof
    return floor, "rounding of the printed digits" if floor > 0 else "none detectable", np.inf


def estimate_noise(data: MeasuredData, model_form_fraction: float) -> NoiseEstimate:
    """σ of every observation (see the module docstring)."""
    noise, method, dof = {}, {}, {}
    for shaft in MEASURED_SHAFTS:
        if not (data.shaft == shaft).any():
            continue
        if data.sigma_mm is not None:
            noise[shaft] = float(np.sqrt(np.mean(data.sigma_mm[data.shaft == shaft] ** 2)))
            method[shaft] = "sigma_mm column of the file"
        elif data.schema == "paths":
            noise[shaft], method[shaft] = _paths_noise(data, shaft)
        else:
            noise[shaft], method[shaft], dof[shaft] = _table_noise(data, shaft)
    base = data.sigma_mm if data.sigma_mm is not None else np.array([noise[s] for s in data.shaft])
    sigma = np.sqrt(base ** 2 + (model_form_fraction * group_rms(data)) ** 2)
    positive = sigma[sigma > 0]
    sigma = np.where(sigma > 0, sigma, positive.min() if positive.size else 1e-9)
    share = np.where(np.array([np.isfinite(dof.get(s, np.inf)) for s in data.shaft]), base ** 2 / sigma ** 2, 0.0)
    return NoiseEstimate(sigma, noise, method, {s: dof.get(s, np.inf) for s in noise}, share)


@dataclass(frozen=True)
class GapTest:
    """χ² test of the scaled residuals: is there a gap beyond the noise? With σ estimated on ``dof`` degrees of freedom
    (finite), χ²/n is read against F(n, dof)."""

    chi2: float
    n: int
    p_value: float
    alpha: float
    dof: float = np.inf

    @property
    def gap(self) -> bool:
        return self.p_value < self.alpha

    def describe(self) -> str:
        against = f", against F({self.n}, {self.dof:.3g}): σ estimated" if np.isfinite(self.dof) else ""
        return (f"χ² = {self.chi2:.4g} on {self.n} observations (χ²/n = {self.chi2 / max(self.n, 1):.3g}{against}), "
                f"p = {self.p_value:.3g}: " + ("a gap beyond the noise" if self.gap else "consistent with the noise"))


def critical_chi2(n: int, alpha: float, dof: float = np.inf) -> float:
    """The χ² at which the gap test on ``n`` observations fires: χ²₁₋α(n), or n·F₁₋α(n, ν) with σ estimated on
    ν = ``dof`` degrees of freedom."""
    n = max(n, 1)
    return float(stats.chi2.isf(alpha, n) if not np.isfinite(dof) else n * stats.f.isf(alpha, n, dof))


def gap_p_value(chi2: float, n: int, dof: float = np.inf) -> float:
    """The gap test's p-value of ``chi2`` on ``n`` observations (σ known: χ²_n; σ on ν = ``dof``: F(n, ν) of χ²/n)."""
    n = max(n, 1)
    return float(stats.chi2.sf(chi2, n) if not np.isfinite(dof) else stats.f.sf(chi2 / n, n, dof))


def detection_norm(n: int, alpha: float, dof: float = np.inf) -> float:
    """The signature norm (in σ) an effect needs for the gap test on ``n`` observations to find it: the χ² it adds,
    ‖s‖², must lift the expected χ² (n) to the test's critical value (:func:`critical_chi2`, with σ as estimated).
    The same σ (noise, the rounding of printed digits, the model-form allowance) scales the signature and the test,
    and the same ν reads it, so "detectable" means the workflow's own test would see the gap."""
    return float(np.sqrt(max(critical_chi2(n, alpha, dof) - max(n, 1), 0.0)))


def gap_test(scaled_residual: np.ndarray, alpha: float, dof: float = np.inf) -> GapTest:
    """χ² of the scaled residuals against the noise alone; ``dof`` the degrees of freedom of the estimated σ² (∞:
    known σ, the χ² test; finite: F(n, ν), see :meth:`NoiseEstimate.degrees_of_freedom`)."""
    chi2 = float(np.sum(scaled_residual ** 2))
    n = int(scaled_residual.size)
    return GapTest(chi2, n, gap_p_value(chi2, n, dof), alpha, dof)


@dataclass(frozen=True)
class StructureFinding:
    """One test of the residual's structure, for one shaft."""

    shaft: str
    test: str
    statistic: float
    significant: bool
    detail: str


def _t_test(design: np.ndarray, r: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Weighted least squares r ≈ design·c: coefficients and their t statistics (σ known, = 1/√w)."""
    a = design * np.sqrt(weights)[:, None]
    b = r * np.sqrt(weights)
    coefficients, *_ = np.linalg.lstsq(a, b, rcond=None)
    covariance = np.linalg.pinv(a.T @ a)
    return coefficients, coefficients / np.sqrt(np.maximum(np.diag(covariance), 1e-300))


def residual_structure(data: MeasuredData, residual_mm: np.ndarray, sigma_mm: np.ndarray,
                       threshold: float = 3.0, model_form_fraction: float = 0.0) -> list[StructureFinding]:
    """Tests of the residual along the sweep and along the shaft (|t| > ``threshold`` is significant).

    - *constant offset* and *torque-proportional*: r = a + b·T over the cases (T = the shaft's torque);
    - *curvature along the shaft* (paths): judged against the model-form allowance (see
      :func:`curvature_beyond_allowance`); with ``model_form_fraction`` 0, the significance of c alone;
    - *sign change*: a + b·T changes sign inside the measured torque range;
    - *dead band*: the line through the upper half of the sweep misses the lower half.
    """
    findings: list[StructureFinding] = []
    weights = 1.0 / sigma_mm ** 2
    for shaft in MEASURED_SHAFTS:
        mask = data.shaft == shaft
        if mask.sum() < 3:
            continue
        torque = np.array([c.input_torque_Nm if shaft == "input" else c.output_torque_Nm for c in data.cases])
        t = torque[data.case_index[mask]]
        r, w = residual_mm[mask], weights[mask]
        unit = "N·m"
        if np.ptp(t) > 0:
            (a, b), (ta, tb) = _t_test(np.column_stack([np.ones_like(t), t]), r, w)
            findings.append(StructureFinding(shaft, "constant offset", float(ta), abs(ta) > threshold,
                                             f"{a * 1e3:+.4g} µm (t = {ta:+.1f})"))
            findings.append(StructureFinding(shaft, "torque-proportional", float(tb), abs(tb) > threshold,
                                             f"{b * 1e3:+.4g} µm per {unit} (t = {tb:+.1f})"))
            crossing = -a / b if b != 0 else np.inf
            inside = bool(t.min() < crossing < t.max()) and abs(ta) > threshold and abs(tb) > threshold
            findings.append(StructureFinding(shaft, "sign change", float(crossing), inside,
                                             f"a + b·T = 0 at T = {crossing:.4g} {unit}"))
            upper = t >= np.median(t)
            lower = ~upper
            if upper.sum() >= 2 and lower.sum() >= 1 and np.ptp(t[upper]) > 0:
                line, *_ = np.linalg.lstsq(np.column_stack([np.ones(upper.sum()), t[upper]]) * np.sqrt(w[upper])[:, None],
                                           r[upper] * np.sqrt(w[upper]), rcond=None)
                miss = (r[lower] - (line[0] + line[1] * t[lower])) * np.sqrt(w[lower])
                chi2 = float(np.sum(miss ** 2))
                p = float(stats.chi2.sf(chi2, int(lower.sum())))
                findings.append(StructureFinding(shaft, "dead band", chi2, p < 1e-3,
                                                 f"lower half vs the line of the upper half: χ² = {chi2:.3g} "
                                                 f"on {int(lower.sum())} points (p = {p:.2g})"))
        if data.schema == "paths" and np.ptp(data.x_mm[mask]) > 0:
            finding = curvature_beyond_allowance(data, residual_mm, sigma_mm, shaft,
                                                 model_form_fraction=model_form_fraction, threshold=threshold)
            if finding is not None:
                findings.append(finding)
    return findings


def curvature_beyond_allowance(data: MeasuredData, residual_mm: np.ndarray, sigma_mm: np.ndarray, shaft: str, *,  # noqa: PLR0913
                               model_form_fraction: float, threshold: float) -> StructureFinding | None:
    """Curvature of the residual along one shaft, as a fraction of the signal, against the model-form allowance.

    A model of another form (another discretisation, shear, a solid part) differs from the data by a smooth
    shape along the shaft that grows with the load: a fixed fraction of the signal. The likelihood allows
    ``model_form_fraction`` of the signal (σ² = σ_noise² + (f·s)²), so the structure test does too: the
    residual relative to its path's RMS signal s, ρ = r/s (σ_ρ = σ/s), is fitted by a + b·x + c·x² over every
    case, and the curvature's amplitude A = |c|·RMS(q) (q: x² without its part along 1 and x, both weighted)
    is compared with f. The statistic is (A − f)/SE(A): the curvature exceeds the allowance by that many
    standard errors; it is significant above ``threshold``. With f = 0 it is |t| of c. Curvature smaller
    than the allowance is what the fit already tolerates as model form, however many points see it.
    """
    mask = data.shaft == shaft
    scale = group_rms(data)
    keep = mask & (scale > 0) & (sigma_mm > 0)
    if keep.sum() < 4 or np.ptp(data.x_mm[keep]) <= 0:
        return None
    x = data.x_mm[keep] / np.ptp(data.x_mm[keep])
    s = scale[keep]
    rho, weights = residual_mm[keep] / s, (s / sigma_mm[keep]) ** 2
    design = np.column_stack([np.ones_like(x), x, x ** 2])
    coefficients, t = _t_test(design, rho, weights)
    root = np.sqrt(weights)
    line, *_ = np.linalg.lstsq(design[:, :2] * root[:, None], x ** 2 * root, rcond=None)
    q = x ** 2 - design[:, :2] @ line
    shape = float(np.sqrt(np.average(q ** 2, weights=weights)))
    amplitude = abs(float(coefficients[2])) * shape
    error = amplitude / abs(float(t[2])) if t[2] != 0 else np.inf
    statistic = float((amplitude - model_form_fraction) / error) if 0 < error < np.inf else 0.0
    detail = f"{100 * amplitude:.2g} % of the signal, t = {t[2]:+.1f}"
    if model_form_fraction > 0:
        detail += (f"; {'beyond' if amplitude > model_form_fraction else 'within'} the "
                   f"{100 * model_form_fraction:.3g} % model-form allowance ({statistic:+.1f} standard errors)")
    return StructureFinding(shaft, "curvature along the shaft", statistic, statistic > threshold, detail)
