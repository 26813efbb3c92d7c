"""The out-of-vocabulary sentinel, and cross-validation over load cases.

The sentinel is a generic localized lateral load that no effect of the vocabulary names: a
vertical force (or a moment about Z) at one node of any part, with a constant part, a part
proportional to T1 and a part proportional to T2. Its location is scanned over every part's
nodes (:meth:`engine.Engine.sentinel_sites`), every subset of the three parts is tried, and the
best is kept by ``BIC = χ² + (k + 1) ln n`` (the location counts as one parameter). All of it is one
block solve on the base factorisation and linear least squares.

When a vocabulary explanation needs more parameters than the sentinel for no better fit, or the
sentinel fits much better, the data show a load the vocabulary does not have; the sentinel then
says where it acts and how it scales with torque.

Cross-validation: the load cases are split into folds (every ``folds``-th case by torque); each
fold is predicted from a fit on the others, and the held-out χ² is compared with the base
model's on the same cases.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.loads import UNIT_LOADS, gear_contact_torques
from rvcoax.results.studies.discrepancy.engine import case_matrix

__all__ = ["CrossValidation", "SentinelFit", "case_folds", "fit_sentinel", "linear_observation", "scan_spacing_mm",
           "site_in"]

SLOTS = {"constant": "force_table", "T1": "T1", "T2": "T2"}  # a constant load acts like the rest loads
FAMILIES = {"force": (1, "N"), "moment": (5, "N·m")}
# plausible sizes (constant, per N·m of torque): a sentinel beyond them is a fit of noise or of a linearisation
LIMITS = {"force": (1e4, 1e3), "moment": (1e3, 1e2)}


@dataclass(frozen=True)
class SentinelFit:
    """The best generic localized load."""

    family: str  # force | moment
    part: str
    role: str  # shaft | body
    x_mm: float
    parts_fitted: tuple[str, ...]  # subset of constant, T1, T2
    coefficients: tuple[float, ...]  # N (constant) and N per N·m (T1, T2); N·m and N·m per N·m for a moment
    chi2: float
    n: int
    change: np.ndarray  # its change of every observation (mm)

    @property
    def k(self) -> int:
        return len(self.coefficients) + 1

    @property
    def bic(self) -> float:
        return self.chi2 + self.k * np.log(max(self.n, 2))

    def describe(self) -> str:
        unit = FAMILIES[self.family][1]
        what = "lateral load" if self.family == "force" else "lateral moment"
        terms = []
        for part, value in zip(self.parts_fitted, self.coefficients):
            terms.append(f"{value:+.3g} {unit}" if part == "constant" else f"{value:+.3g} {unit} per N·m of {part}")
        where = f"the {self.part}" if self.role == "shaft" else f"the housing {self.part}"
        return f"a vertical {what} of about {', '.join(terms)} near x = {self.x_mm:.0f} mm on {where}"


def linear_observation(observe, base_paths) -> sp.csr_matrix:
    """The observation operator as a matrix: exact for paths, linearised at ``base_paths`` for a table
    (|Y_max| changes by sign(Y) at the station of the maximum)."""
    if hasattr(observe, "matrix"):
        return observe.matrix
    rows, cols, vals = [], [], []
    for i, block in enumerate(observe.blocks):
        values = base_paths[block]
        j = int(np.argmax(np.abs(values)))
        rows.append(i)
        cols.append(block.start + j)
        vals.append(1.0 if values[j] >= 0 else -1.0)
    return sp.csr_matrix((vals, (rows, cols)), shape=(len(observe.blocks), base_paths.size))


ROW_CHUNK = 4096
"""Observations whose site responses are formed at once in the scan (memory: this × sites × 8 bytes), so that a
large measured file costs what its rows cost, not rows × sites × parts of copies."""


def _observed_blocks(engine, sites, component, cases, *, from_rest: bool, operator):  # noqa: PLR0913
    """(shapes_of(rows) → (len(rows), n_sites) observed change per unit load at each site, {part: weight of each
    observation's case}): each observation reads one case's block, so the operator within a block times
    that case's weight gives every part's column (no (cases × path) × sites matrix is ever formed)."""
    g = engine.sentinel_paths(sites, component)  # (n_sites, n_path)
    weights = case_matrix(cases, from_rest, gear_contact_torques(engine.rig))
    n_path = g.shape[1]
    coo = operator.tocoo()
    local = sp.csr_matrix((coo.data, (coo.row, coo.col % n_path)), shape=(operator.shape[0], n_path))
    case_of_row = np.zeros(operator.shape[0], dtype=int)
    case_of_row[coo.row] = coo.col // n_path
    factors = {}
    for part, slot in SLOTS.items():
        column = weights[:, UNIT_LOADS.index(slot)]
        if np.any(column):  # (not e.g. a constant load when Y is read from the rig at rest)
            factors[part] = column[case_of_row]

    def shapes_of(rows: np.ndarray) -> np.ndarray:
        return np.asarray(local[rows] @ g.T)

    return shapes_of, factors


def _columns(engine, sites, component, cases, *, from_rest: bool, operator) -> dict[str, np.ndarray]:  # noqa: PLR0913
    """Per sentinel part: observed change (n_obs, n_sites) per unit load at each site (for a few sites)."""
    shapes_of, factors = _observed_blocks(engine, sites, component, cases, from_rest=from_rest, operator=operator)
    shapes = shapes_of(np.arange(operator.shape[0]))
    return {part: factor[:, None] * shapes for part, factor in factors.items()}


def _normal_equations(shapes_of, factors: dict, rows: np.ndarray, sigma: np.ndarray, target: np.ndarray):
    """Per site, the least-squares normal equations of every part together: gram (sites, k, k) and
    right-hand side (sites, k) over the observations ``rows``, accumulated :data:`ROW_CHUNK` rows at a time."""
    parts = list(factors)
    picked = np.flatnonzero(rows)
    gram = rhs = None
    for start in range(0, picked.size, ROW_CHUNK):
        chunk = picked[start:start + ROW_CHUNK]
        shapes = shapes_of(chunk)  # (chunk, sites)
        scaled = np.stack([factors[p][chunk] / sigma[chunk] for p in parts], axis=1)  # (chunk, k)
        squared = shapes * shapes
        block_gram = np.einsum("ns,ni,nj->sij", squared, scaled, scaled)
        block_rhs = shapes.T @ (scaled * (target[start:start + ROW_CHUNK])[:, None])
        gram = block_gram if gram is None else gram + block_gram
        rhs = block_rhs if rhs is None else rhs + block_rhs
    return parts, gram, rhs


def scan_spacing_mm(sites, part: str) -> float:
    """The distance between neighbouring sentinel sites on ``part`` (the scan's resolution along x)."""
    x = np.sort([s[1] for s in sites if s[0] == part])
    return float(np.median(np.diff(x))) if x.size > 1 else 0.0


def site_in(site, regions) -> bool:
    """Whether a sentinel site (part, x_mm, …) lies in one of ``regions`` ((part, lo_mm, hi_mm), …)."""
    return any(site[0] == part and lo <= site[1] <= hi for part, lo, hi in regions)


def fit_sentinel(observed, exclude: tuple[tuple[str, float, float], ...] = ()) -> SentinelFit | None:
    """The best sentinel on the observations used to fit (``observed.rows``; see the module docstring), scanned over
    every site except those in ``exclude`` ((part, lo_mm, hi_mm), …)."""
    engine, data, base_paths, observe = observed.engine, observed.data, observed.base_paths, observed.observe
    sigma, rows = observed.sigma, observed.rows
    operator = linear_observation(observe, base_paths)
    residual = ((data.value_mm - observe(base_paths)) / sigma)
    target = residual[rows]
    n = int(np.count_nonzero(rows))
    sites = [s for s in engine.sentinel_sites() if not site_in(s, exclude)]
    if not sites:
        return None
    best = None
    total = float(target @ target)
    for family, (component, _) in FAMILIES.items():
        blocks = _observed_blocks(engine, sites, component, data.cases, from_rest=observed.from_rest,
                                  operator=operator)
        parts, full_gram, full_rhs = _normal_equations(*blocks, rows, sigma, target)
        if full_gram is None:
            continue
        for size in range(1, len(parts) + 1):
            for subset in itertools.combinations(parts, size):
                index = [parts.index(p) for p in subset]
                gram = full_gram[:, index][:, :, index]  # every site at once
                rhs = full_rhs[:, index]
                usable = np.linalg.det(gram) > 1e-12 * np.prod(np.diagonal(gram, axis1=1, axis2=2), axis=1)
                if not usable.any():
                    continue
                coefficients = np.zeros_like(rhs)
                coefficients[usable] = np.linalg.solve(gram[usable], rhs[usable][..., None])[..., 0]
                chi2 = total - np.einsum("si,si->s", rhs, coefficients)
                limits = np.array([LIMITS[family][0 if p == "constant" else 1] for p in subset])
                usable &= np.all(np.abs(coefficients) <= limits, axis=1)
                if not usable.any():
                    continue
                bic = np.where(usable, chi2 + (size + 1) * np.log(max(n, 2)), np.inf)
                j = int(np.argmin(bic))
                if best is None or bic[j] < best[0]:
                    best = (float(bic[j]), family, j, subset, coefficients[j], float(max(chi2[j], 0.0)))
    if best is None:
        return None
    _, family, j, subset, coefficients, chi2 = best
    part, x_mm, _ = sites[j]
    columns = _columns(engine, [sites[j]], FAMILIES[family][0], data.cases, from_rest=observed.from_rest,
                       operator=operator)  # the best site only
    change = sum(c * columns[p][:, 0] for p, c in zip(subset, coefficients))
    role = next(p.role for p in engine.rig.parts if p.name == part)
    return SentinelFit(family=family, part=part, role=role, x_mm=float(x_mm), parts_fitted=tuple(subset), coefficients=tuple(float(c) for c in coefficients), chi2=chi2, n=n,
                       change=np.asarray(change))


@dataclass(frozen=True)
class SentinelScan:
    """The sentinel's scan for many targets at once: per entry (family × site) and target, the best subset's
    ``chi2`` and ``bic`` (``inf`` where no subset is usable), its parameter count ``k`` (fitted parts + the
    location), and each entry's ``family`` and ``site``."""

    chi2: np.ndarray  # (targets, entries)
    bic: np.ndarray
    k: np.ndarray
    family: tuple[str, ...]
    site: tuple[tuple, ...]


def sentinel_scan(observed, targets: np.ndarray) -> SentinelScan | None:
    """:func:`fit_sentinel`'s scan for every row of ``targets`` (scaled residuals of every observation, (m, n)) at
    once, with the σ and rows of ``observed``: the normal equations' matrices depend on σ and the sites only, so
    many data sets on the same observations cost one scan and a few products (the confidence estimate's draws)."""
    engine, data, base_paths, observe = observed.engine, observed.data, observed.base_paths, observed.observe
    sigma, rows = observed.sigma, observed.rows
    operator = linear_observation(observe, base_paths)
    picked = np.flatnonzero(rows)
    n = picked.size
    scaled_targets = np.asarray(targets)[:, picked]
    total = np.einsum("mi,mi->m", scaled_targets, scaled_targets)
    sites = engine.sentinel_sites()
    chi2_all, bic_all, k_all, families, entries = [], [], [], [], []
    for family, (component, _) in FAMILIES.items():
        shapes_of, factors = _observed_blocks(engine, sites, component, data.cases, from_rest=observed.from_rest,
                                              operator=operator)
        parts = list(factors)
        if not parts:
            continue
        shapes = shapes_of(picked)  # (n, sites)
        scaled = np.stack([factors[p][picked] / sigma[picked] for p in parts], axis=1)  # (n, k)
        gram_full = np.einsum("ns,ni,nj->sij", shapes * shapes, scaled, scaled)
        rhs_full = np.einsum("ns,ni,nm->sim", shapes, scaled, scaled_targets.T)  # (sites, k, m)
        best_bic = np.full((len(sites), total.size), np.inf)
        best_chi2 = np.full_like(best_bic, np.inf)
        best_k = np.zeros(best_bic.shape, dtype=int)
        for size in range(1, len(parts) + 1):
            for subset in itertools.combinations(parts, size):
                index = [parts.index(p) for p in subset]
                gram = gram_full[:, index][:, :, index]
                rhs = rhs_full[:, index, :]
                usable = np.linalg.det(gram) > 1e-12 * np.prod(np.diagonal(gram, axis1=1, axis2=2), axis=1)
                if not usable.any():
                    continue
                coefficients = np.zeros_like(rhs)
                coefficients[usable] = np.linalg.solve(gram[usable], rhs[usable])
                chi2 = total[None, :] - np.einsum("sim,sim->sm", rhs, coefficients)
                limits = np.array([LIMITS[family][0 if p == "constant" else 1] for p in subset])
                ok = usable[:, None] & np.all(np.abs(coefficients) <= limits[None, :, None], axis=1)
                bic = np.where(ok, chi2 + (size + 1) * np.log(max(n, 2)), np.inf)
                better = bic < best_bic
                best_bic = np.where(better, bic, best_bic)
                best_chi2 = np.where(better, np.maximum(chi2, 0.0), best_chi2)
                best_k = np.where(better, size + 1, best_k)
        chi2_all.append(best_chi2.T), bic_all.append(best_bic.T), k_all.append(best_k.T)
        families += [family] * len(sites)
        entries += list(sites)
    if not entries:
        return None
    return SentinelScan(np.hstack(chi2_all), np.hstack(bic_all), np.hstack(k_all), tuple(families), tuple(entries))


def sentinel_columns(fit: SentinelFit, observed) -> np.ndarray:
    """The observed change per unit of each fitted part of ``fit`` (n_obs, k − 1), for refits on other rows."""
    engine = observed.engine
    operator = linear_observation(observed.observe, observed.base_paths)
    site = [(fit.part, fit.x_mm, s[2]) for s in engine.sentinel_sites() if s[0] == fit.part and s[1] == fit.x_mm]
    columns = _columns(engine, site, FAMILIES[fit.family][0], observed.data.cases, from_rest=observed.from_rest,
                       operator=operator)
    return np.column_stack([columns[p][:, 0] for p in fit.parts_fitted])


def case_folds(data, folds: int = 3) -> list[np.ndarray]:
    """Held-out masks: the cases ordered by torque, every ``folds``-th in one fold (none below 2 × folds cases)."""
    n_cases = len(data.cases)
    if n_cases < 2 * folds:
        return []
    order = sorted(range(n_cases), key=lambda i: (abs(data.cases[i].output_torque_Nm), abs(data.cases[i].input_torque_Nm)))
    fold_of = {case: rank % folds for rank, case in enumerate(order)}
    return [np.array([fold_of[int(c)] == f for c in data.case_index]) for f in range(folds)]


@dataclass(frozen=True)
class CrossValidation:
    """Held-out χ² over all folds: the base model's and the explanation's (each fold fitted without it)."""

    chi2_before: float
    chi2_after: float
    n: int
    folds: int

    @property
    def improves(self) -> bool:
        return self.chi2_after < self.chi2_before

    @property
    def reduction(self) -> float:
        return 1.0 - self.chi2_after / self.chi2_before if self.chi2_before > 0 else 0.0

    def as_dict(self) -> dict:
        return {"folds": self.folds, "held_out_observations": self.n, "chi2_before": float(f"{self.chi2_before:.6g}"),
                "chi2_after": float(f"{self.chi2_after:.6g}"), "chi2_per_observation_after":
                    float(f"{self.chi2_after / max(self.n, 1):.4g}"), "improves": self.improves,
                "reduction_of_chi2": float(f"{self.reduction:.4g}")}


def cross_validate(scaled_residual: np.ndarray, predict_fold, folds: list[np.ndarray]) -> CrossValidation | None:
    """``predict_fold(train_mask)`` returns the scaled change of every observation fitted on ``train_mask``."""
    if not folds:
        return None
    before = after = 0.0
    n = 0
    for held in folds:
        change = predict_fold(~held)
        before += float(np.sum(scaled_residual[held] ** 2))
        after += float(np.sum((scaled_residual[held] - change[held]) ** 2))
        n += int(held.sum())
    return CrossValidation(before, after, n, len(folds))


def shafts_of(data) -> list[str]:
    return [s for s in MEASURED_SHAFTS if (data.shaft == s).any()]
