"""Monte Carlo of the rig's coaxiality: one sample = the rig with toleranced parameters changed, solved.

:func:`plan_study` fixes what is solved (rig, load cases, model, toleranced addresses) and how
much of the model a sample may reuse, found by assembling the beam model with every parameter
changed and comparing it with the system each strategy would build from the nominal one:

``loads``  every parameter only changes loads (load-sharing imbalance, position errors, coupling
           offsets and angles, mount heights, bearing clearances): one
           assembled and factorised model serves every sample; only the unit loads are rebuilt.
``frame``  springs change (bearing, mount, coupling, joint stiffness): per sample the springs
           (stiffness and prestrain) are re-assembled after the stored beam triplets and the system
           is re-factorised; beams, meshes, solid blocks, ties and path probes are reused. The frame
           and the solid blocks share no stiffness entry, so the sample's matrix is exactly the one
           a fresh assembly gives.
``full``   a parameter changes geometry, mass or a solid part (a shaft diameter): every sample is
           assembled, and for solid parts meshed, anew.

:func:`evaluate_sample` is a pure function of (study, values): it gives the same numbers in any
process, in any order. The nominal model it reuses is memoised per process (built on first use),
which only saves time. :func:`exceedance` is P(β > limit) with a Wilson score interval.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import threading
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy import stats

from rvcoax.fem.pieces import Contribution, assemble, beam_contribution, bushing_contribution
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.beam import build_rig_model
from rvcoax.geometry.model.hybrid import attachments
from rvcoax.geometry.model.loads import GRAVITY_DIRECTION
from rvcoax.geometry.model.system import RigSystem, assemble_beam
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.studies.tolerances import Tolerances, apply_values, parameter_value, study_rig
from rvcoax.results.sweep import (
    ModelError,
    PreparedModel,
    SweepSettings,
    assemble_model,
    prepare_model,
    prepare_system,
    run_sweep,
)

__all__ = ["Exceedance", "QUANTILES", "STRATEGIES", "STRATEGY_TEXT", "Study", "classify_parameter", "describe",
           "evaluate_sample", "exceedance", "parameters_needing", "plan_study", "stack_records"]

STRATEGIES = ("loads", "frame", "full")
# what each evaluation strategy re-builds per sample, as the commands print it
STRATEGY_TEXT = {
    "loads": "every toleranced parameter only changes loads: one assembled and factorised model serves every "
             "sample, only the unit loads are rebuilt",
    "frame": "spring stiffnesses change: per sample the springs (stiffness and prestrain) are re-assembled and the "
             "system re-factorised; beams, meshes, solid blocks, ties and path probes are reused",
    "full": "a parameter changes geometry, mass or a solid part: every sample is assembled (and meshed) anew",
}
QUANTILES = (0.01, 0.05, 0.5, 0.95, 0.99)


@dataclass(frozen=True, eq=False)
class Study:
    """What one sample solves.

    Attributes
    ----------
    rig : Rig
        The nominal rig (with the tolerance file's ``measured_from``).
    cases : tuple of LoadCase
    settings : SweepSettings
    addresses : tuple of str
        Toleranced parameters, in the order of a sample's values.
    strategy : str
        ``loads``, ``frame`` or ``full`` (see the module docstring).
    key : str
        SHA-256 of everything above: names the study in sample files and in the per-process memo.
    """

    rig: Rig
    cases: tuple[LoadCase, ...]
    settings: SweepSettings
    addresses: tuple[str, ...]
    strategy: str
    key: str


def _solid_parts(rig: Rig, model: str) -> tuple[str, ...]:
    if model == "hybrid":
        return rig.hybrid_solid_parts()
    if model == "solid":
        return tuple(p.name for p in rig.parts)
    return ()


def _same(a: sp.spmatrix, b: sp.spmatrix) -> bool:
    return a.shape == b.shape and (a != b).nnz == 0


@dataclass(frozen=True, eq=False)
class _FixedStiffness:
    """What a spring-stiffness sample does not change: the beams and the solid blocks, as model pieces."""

    beams: Contribution
    solid_block: Contribution | None  # K minus the frame block, as triplets; None for the beam model
    solid_parts: tuple[str, ...]


def _fixed_stiffness(system: RigSystem, solid_parts: tuple[str, ...]) -> _FixedStiffness:
    structure = system.frame.structure
    beams = beam_contribution(structure, GRAVITY_DIRECTION)
    block = None
    if system.solids:
        frame = assemble(structure.n_dofs, [beams, bushing_contribution(structure)]).stiffness
        solid = (system.stiffness - _pad(frame, system.n_dofs)).tocoo()
        block = Contribution((solid.row, solid.col, solid.data))
    return _FixedStiffness(beams, block, solid_parts)


def _frame_system(system: RigSystem, fixed: _FixedStiffness, rig: Rig) -> RigSystem:
    """``system`` with the springs (stiffness and prestrain) of ``rig``; the beams and solids are reused.

    The pieces are assembled in the order of a fresh assembly (beams, springs, then the solid blocks,
    which share no entry with the frame), so the matrix is the one a fresh assembly of ``rig`` gives
    whenever the beams and the frame's nodes are the same (checked by :func:`plan_study`). The
    constraints do not depend on spring stiffness: the nominal elimination is kept.
    """
    frame = build_rig_model(rig, solid_parts=fixed.solid_parts)
    structure = frame.structure
    if not np.array_equal(structure.coordinates, system.frame.structure.coordinates):
        raise ModelError("a sample moved frame nodes; the study needs strategy 'full'")
    pieces = [fixed.beams, bushing_contribution(structure)]
    if fixed.solid_block is not None:
        pieces.append(fixed.solid_block)
    stiffness = assemble(system.n_dofs, pieces).stiffness
    loads = dataclasses.replace(system.load_builder, frame=frame)  # K Δ0 with this sample's springs
    return dataclasses.replace(system, rig=rig, frame=frame, stiffness=stiffness, unit_loads=loads(rig),
                               load_builder=loads)


def _same_loads(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(np.allclose(a[k], b[k], rtol=1e-12, atol=0.0) for k in a)


def classify_parameter(rig: Rig, address: str, value: float, model: str = "beam", nominal: RigSystem | None = None) -> str:
    """How much of the model changes when ``address`` takes ``value``: ``loads``, ``frame`` or ``full``.

    ``nominal`` is ``rig``'s beam system (assembled here when not given).
    """
    return _reuse(nominal or assemble_beam(rig), apply_values(rig, {address: value}), model)


def _reuse(nominal: RigSystem, changed: Rig, model: str) -> str:
    """The cheapest strategy whose system for ``changed``, built from the nominal beam system, equals a fresh one."""
    rig = nominal.rig
    fresh = assemble_beam(changed)
    if fresh.n_dofs != nominal.n_dofs or not np.array_equal(fresh.frame.structure.coordinates,
                                                             nominal.frame.structure.coordinates):
        return "full"
    solids = _solid_parts(rig, model)
    if not _same(fresh.elimination, nominal.elimination) or (solids and (
            changed.parts != rig.parts or changed.solid != rig.solid
            or attachments(changed, solids) != attachments(rig, solids))):
        return "full"
    if _same(fresh.stiffness, nominal.stiffness) and _same_loads(nominal.load_builder(changed), fresh.unit_loads):
        return "loads"
    updated = _frame_system(nominal, _fixed_stiffness(nominal, ()), changed)
    if _same(updated.stiffness, fresh.stiffness) and _same_loads(updated.unit_loads, fresh.unit_loads):
        return "frame"
    return "full"  # e.g. a mass: self-weight is assembled with the structure


def _fingerprint(*items) -> str:
    return hashlib.sha256(json.dumps(items, sort_keys=True, default=str).encode()).hexdigest()


def _probe_values(rig: Rig, tolerances: Tolerances) -> dict[str, float]:
    """Per parameter a value away from the nominal one (its 10 % or 90 % quantile, the farther)."""
    values = {}
    for p in tolerances.parameters:
        low, high = p.distribution.quantile([0.1, 0.9])
        nominal = parameter_value(rig, p.address)
        values[p.address] = float(high if abs(high - nominal) >= abs(low - nominal) else low)
    return values


def parameters_needing(rig: Rig, tolerances: Tolerances, strategy: str, model: str = "beam") -> list[str]:
    """The toleranced parameters that on their own need ``strategy`` (``rig`` as planned).

    Parameters
    ----------
    rig : Rig
        The rig as planned.
    tolerances : Tolerances
        From :func:`rvcoax.results.studies.load_tolerances`.
    strategy : {"frame", "full"}
        The reuse to look for.
    model : str
        ``beam``, ``hybrid`` or ``solid``.

    Returns
    -------
    list of str
        Their addresses.
    """
    nominal = assemble_beam(rig)
    return [address for address, value in _probe_values(rig, tolerances).items()
            if classify_parameter(rig, address, value, model, nominal) == strategy]


def plan_study(rig: Rig, tolerances: Tolerances, settings: SweepSettings | None = None,
               strategy: str | None = None) -> Study:
    """The study of a tolerance file on ``rig``; ``strategy`` overrides the reuse found (e.g. ``full``).

    The reuse is found with every parameter changed at once (a spring's stiffness and its offset
    interact through the prestrain K Δ0): the cheapest strategy whose system equals a fresh
    assembly of the changed rig. :func:`classify_parameter` tells which parameter needs what.

    Parameters
    ----------
    rig : Rig
        The nominal rig.
    tolerances : Tolerances
        From :func:`rvcoax.results.studies.load_tolerances`.
    settings : SweepSettings, optional
        How each sample is solved (default: the beam model).
    strategy : {"loads", "frame", "full"}, optional
        Force a reuse strategy.

    Returns
    -------
    Study
        The rig, the load cases, the addresses, the strategy and what every sample reuses.
    """
    settings = settings or SweepSettings()
    rig = study_rig(rig, tolerances)
    if strategy is None:
        strategy = _reuse(assemble_beam(rig), apply_values(rig, _probe_values(rig, tolerances)), settings.model)
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {', '.join(STRATEGIES)}, got {strategy!r}")
    key = _fingerprint(rig.model_dump(mode="json", by_alias=True),
                       [(c.input_torque_Nm, c.output_torque_Nm) for c in tolerances.cases],
                       dataclasses.asdict(settings), tolerances.addresses, strategy)
    return Study(rig=rig, cases=tolerances.cases, settings=settings, addresses=tolerances.addresses, strategy=strategy,
                 key=key)


@dataclass(frozen=True, eq=False)
class _Nominal:
    """What a process keeps of the nominal model: strategy ``loads`` its factorisation, ``frame`` the assembled
    system and its fixed pieces only (every sample factorises its own matrix, so a factor of the nominal one would
    be set up for nothing: at the all-solid rig on a 12 mm mesh that was a whole PARDISO analysis, factorisation
    and condition estimate per worker)."""

    system: RigSystem
    prepared: PreparedModel | None
    fixed: _FixedStiffness


_MEMO: dict[str, _Nominal] = {}
_MEMO_LOCK = threading.Lock()


def _pad(matrix: sp.spmatrix, n: int) -> sp.csr_matrix:
    coo = matrix.tocoo()
    return sp.csr_matrix((coo.data, (coo.row, coo.col)), shape=(n, n))


def _nominal(study: Study) -> _Nominal:
    """The nominal model of ``study``, assembled (and for strategy ``loads`` factorised) once per process."""
    with _MEMO_LOCK:
        if study.key not in _MEMO:
            if study.strategy == "loads":
                prepared = prepare_model(study.rig, study.settings)
                system = prepared.system
            else:
                prepared, system = None, assemble_model(study.rig, study.settings)
            if len(_MEMO) >= 2:
                _MEMO.pop(next(iter(_MEMO)))
            _MEMO[study.key] = _Nominal(system, prepared, _fixed_stiffness(system, _solid_parts(study.rig,
                                                                                                 study.settings.model)))
        return _MEMO[study.key]


def evaluate_sample(study: Study, values) -> dict:
    """Solve the study's load cases on the rig with ``values`` (one per address).

    Parameters
    ----------
    study : Study
        From :func:`plan_study`.
    values : sequence of float
        One value per toleranced address, in ``study.addresses`` order.

    Returns
    -------
    dict
        ``Y_max_mm``, ``Y_signed_mm``, ``beta_deg``: per case a pair (input, output);
        ``equilibrium_error``: the largest relative equilibrium error of the sample's cases.
    """
    rig = apply_values(study.rig, dict(zip(study.addresses, (float(v) for v in values))))
    if study.strategy == "full":
        sweep = run_sweep(rig, study.cases, study.settings, engineering=False)  # Y and β only
    else:
        nominal = _nominal(study)
        if study.strategy == "loads":
            prepared = nominal.prepared
        else:
            system = _frame_system(nominal.system, nominal.fixed, rig)
            prepared = prepare_system(system, study.settings)
        sweep = run_sweep(rig, study.cases, study.settings, prepared=prepared, engineering=False)
    return {
        "Y_max_mm": [[c.paths[s].y_max_mm for s in MEASURED_SHAFTS] for c in sweep.cases],
        "Y_signed_mm": [[c.paths[s].y_max_signed_mm for s in MEASURED_SHAFTS] for c in sweep.cases],
        "beta_deg": [[c.paths[s].beta_deg for s in MEASURED_SHAFTS] for c in sweep.cases],
        "equilibrium_error": max(c.equilibrium_error for c in sweep.cases),
    }


def stack_records(records: list[dict], key: str) -> np.ndarray:
    """``key`` of every sample record as an array (samples, cases, shafts).

    Parameters
    ----------
    records : list of dict
        From :func:`evaluate_sample`.
    key : str
        ``Y_max_mm``, ``Y_signed_mm`` or ``beta_deg``.

    Returns
    -------
    ndarray, shape (samples, cases, 2)
        The values, input shaft first.
    """
    return np.array([r[key] for r in records], dtype=float)


@dataclass(frozen=True)
class Exceedance:
    """P(β > limit) estimated from ``count`` of ``n`` samples, with a Wilson score interval."""

    count: int
    n: int
    confidence_level: float
    probability: float
    lower: float
    upper: float


def exceedance(beta_deg, limit_deg: float, confidence_level: float = 0.95) -> Exceedance:
    """P(β > ``limit_deg``) with the Wilson score interval at ``confidence_level``.

    The interval treats the samples as independent. A Latin hypercube design never has a larger
    variance than independent sampling by more than a factor n/(n − 1) (Owen 1997), so the interval
    is valid for it as well (and usually conservative).
    """
    beta = np.asarray(beta_deg, dtype=float)
    n = int(beta.size)
    if n == 0:
        raise ValueError("no samples")
    count = int(np.count_nonzero(beta > limit_deg))
    p = count / n
    z = float(stats.norm.ppf(0.5 + confidence_level / 2))
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return Exceedance(count=count, n=n, confidence_level=confidence_level, probability=p,
                      lower=max(0.0, float(centre - half)), upper=min(1.0, float(centre + half)))


def describe(values) -> dict:
    """Mean, standard deviation, min, max and the quantiles of :data:`QUANTILES` of a sample."""
    values = np.asarray(values, dtype=float)
    out = {"mean": float(values.mean()), "std": float(values.std(ddof=1)) if values.size > 1 else 0.0,
           "min": float(values.min()), "max": float(values.max())}
    out.update({f"q{100 * q:g}": float(np.quantile(values, q)) for q in QUANTILES})
    return out
