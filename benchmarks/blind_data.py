"""Hidden-effect data sets made by a model the discrepancy workflow does not identify with.

The workflow identifies with the beam model. These data come from the **hybrid** model of the
same rig (the two measured shafts as quadratic tetrahedra tied into the beam line,
``SweepSettings(model="hybrid")``): on the unmodified rig it differs from the beam model by 1.8 %
(input shaft) and 0.3 % (output shaft) of the signal, so a model-form difference is always present. Bearing clearances, which the
hybrid model does not take, are the one exception: their change of the paths is solved directly
with the beam model at a five times finer discretisation (1 mm elements instead of 5 mm) and added
to the hybrid base paths.

What is generated (:func:`design`):

- every kind of the vocabulary (``rvcoax.geometry.effects``) at one or two locations (but
  ``shear_deformation``, which is no candidate on the identification rig: see :func:`identification_rig`), at a
  plausible magnitude (20–35 % of the signal on the shaft it changes most, within its physical
  bounds; effects that cannot reach that are kept at their bound as *faint* effects);
- no effect; pairs of effects;
- loads outside the vocabulary: a lateral force proportional to T2 at three stations of the output
  shaft, a moment proportional to T2 (a couple of such forces 30 mm apart), a constant lateral force;
- optionally (``write_sets(..., out_of_bounds=True)``, used by ``blind_solid.py``) every linear effect at twice its
  physical bound: a truth the workflow must never call ``explained``;
- both schemas (paths file and table), both datums (Y from the unloaded geometry and from the rig
  aligned at rest), 1 % and 5 % noise, several seeds, numbers in fixed, e, E and mixed notation.

Effects that are linear in their parameter are solved once and superposed (scaled, summed);
:func:`superposition_check` compares a superposed pair with a direct solve. Nonlinear effects
(bearing stiffness, mount compliance, shear, clearance) and pairs with one of them are solved
directly. Every solve is cached as ``.npz`` under ``.blindcache/`` (git-ignored), keyed by a hash of
the rig, the cases and the model, so a rerun only writes files.

Usage: ``python benchmarks/blind_data.py [--out DIR]`` (default ``.blindcache/sets``) writes the CSV
files and ``manifest.json`` (the truth of every file); the benchmark reads them.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.effects import candidate_effects
from rvcoax.geometry.rigfile import load_rig
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase, paper_cases
from rvcoax.results.sweep import SweepSettings, run_sweep

if TYPE_CHECKING:
    from rvcoax.results.studies.discrepancy.responses import PathLayout

# The workflow's own modules (observation operator, path layout, effect sizing) are imported where they are
# used, so that the benchmark can run another tree's workflow on these data even if it reorganised them.

ROOT = Path(__file__).resolve().parents[1]
CACHE = ROOT / ".blindcache"
LENGTHS = {"input": 120.0, "output": 160.0}
STATIONS = 11
DATUMS = ("unloaded", "aligned_at_rest")
SCHEMAS = ("paths", "table")
NOISES = (0.01, 0.05)
NOTATIONS = ("fixed", "e", "E", "mixed")
HYBRID = SweepSettings(model="hybrid")
FINE_BEAM_ELEMENT_MM = 1.0
REST = LoadCase(0.0, 0.0)

# one or two locations of every kind of the vocabulary
VOCABULARY = ("self_weight", "force_pairs", "bearing_stiffness@input_B1", "bearing_stiffness@output_B2",
              "bearing_clearance@input_B2", "mount_compliance@reducer", "coupling_offset@C2", "coupling_angle@C3",
              "mesh_force@reducer_input", "mesh_position_error@sun_gear_load_sharing", "torque_reaction@reducer",
              "torque_reaction@output_bearing_block", "thermal_growth@output_bearing_block")
PAIRS = (("coupling_offset@C2", "bearing_stiffness@output_B2"),
         ("mesh_force@reducer_input", "torque_reaction@output_bearing_block"),
         ("thermal_growth@output_bearing_block", "coupling_angle@C3"),
         ("self_weight", "mesh_position_error@sun_gear_load_sharing"),
         ("bearing_stiffness@input_B1", "torque_reaction@output_bearing_block"),
         ("mesh_position_error@sun_gear_load_sharing", "torque_reaction@reducer"))
# loads outside the vocabulary: (name, kind, output-shaft x in the rig frame (mm), needs the unloaded datum)
OUT_OF_VOCABULARY = (("lateral_T2@output_x35", "proportional", 440.0, False),
                     ("lateral_T2@output_x80", "proportional", 485.0, False),
                     ("lateral_T2@output_x135", "proportional", 540.0, False),
                     ("moment_T2@output_x80", "couple", 485.0, False),
                     ("constant_force@output_x95", "constant", 500.0, True))
FAINT = 0.10  # an effect that cannot change the data by 10 % of the signal within its bounds is "faint"
TARGET = {0: 0.30, 1: 0.20, 2: 0.35}  # fraction of the signal by seed


def truth_rig(datum: str = "unloaded") -> Rig:
    """The rig the data are made from: the reference rig with self-weight off (so ``self_weight`` is a
    candidate) and Euler–Bernoulli beams, Y measured from ``datum``. In the hybrid model the measured shafts are
    solids (with their shear deformation); the other shafts are Euler–Bernoulli beams."""
    data = load_rig().model_dump(by_alias=True)
    data["paths"]["measured_from"] = datum
    data["gravity"]["enabled"] = False
    data["beam"]["shear_deformation"] = False
    return Rig.model_validate(data)


def identification_rig(datum: str = "unloaded") -> Rig:
    """The rig the workflow identifies with: the same, but Timoshenko beams (the reference rig's own setting).

    The hybrid model's solid measured shafts deform in shear; against Euler–Bernoulli beams that is a
    4–5 % difference on the short input shaft, which *is* the vocabulary's ``shear_deformation``. With
    Timoshenko beams the model-form difference left is 1.8 % (input) and 0.3 % (output) of the signal on the
    unmodified rig: the solid's 3-D stiffness and ties against the beams, and Euler–Bernoulli against Timoshenko
    in the shafts that are not measured."""
    data = truth_rig(datum).model_dump(by_alias=True)
    data["beam"]["shear_deformation"] = True
    return Rig.model_validate(data)


def solve_cases() -> tuple[LoadCase, ...]:
    """The rest state first (for the aligned datum), then paper 000's 20 cases."""
    return (REST, *paper_cases())


# ---- solves, cached ----------------------------------------------------------------------------------------

def _key(rig: Rig, cases, settings: SweepSettings) -> str:
    text = json.dumps([rig.model_dump(by_alias=True), [(c.input_torque_Nm, c.output_torque_Nm) for c in cases],
                       settings.model, settings.mesh_size_mm], sort_keys=True, default=str)
    return hashlib.sha1(text.encode()).hexdigest()[:20]


def absolute_paths(rig: Rig, settings: SweepSettings, cases=None, log=print) -> tuple[np.ndarray, PathLayout]:
    """u_y from the unloaded geometry of every case of ``cases`` (default :func:`solve_cases`) and both shafts,
    as (cases, stations) flattened like ``responses.full_paths``; cached under ``.blindcache``."""
    from rvcoax.results.studies.discrepancy.responses import PathLayout  # noqa: F811 (at run time)

    cases = tuple(cases or solve_cases())
    path = CACHE / "solves" / f"{settings.model}-{_key(rig, cases, settings)}.npz"
    if path.exists():
        stored = np.load(path)
        layout = PathLayout(len(cases), {s: stored[f"stations_{s}"] for s in MEASURED_SHAFTS},
                            {s: float(stored[f"length_{s}"]) for s in MEASURED_SHAFTS})
        return stored["paths"], layout
    start = time.perf_counter()
    sweep = run_sweep(rig, cases, settings)
    first = sweep.cases[0].absolute_paths
    layout = PathLayout(len(cases), {s: np.asarray(first[s].station_mm, float) for s in MEASURED_SHAFTS},
                        {s: float(first[s].length_mm) for s in MEASURED_SHAFTS})
    paths = np.concatenate([np.concatenate([c.absolute_paths[s].uy_mm for s in MEASURED_SHAFTS])
                            for c in sweep.cases])
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path.with_suffix(".tmp.npz"), paths=paths, **{f"stations_{s}": layout.stations_mm[s] for s in
                                                           MEASURED_SHAFTS},
             **{f"length_{s}": layout.length_mm[s] for s in MEASURED_SHAFTS})
    path.with_suffix(".tmp.npz").replace(path)
    log(f"  solved {settings.model} ({len(cases)} cases) in {time.perf_counter() - start:.1f} s")
    return paths, layout


def fine_beam(rig: Rig) -> Rig:
    data = rig.model_dump(by_alias=True)
    data["mesh"]["max_element_length_mm"] = FINE_BEAM_ELEMENT_MM
    return Rig.model_validate(data)


def _load_rig(rig: Rig, load: tuple) -> Rig:
    """``rig`` with an out-of-vocabulary load of unit size (N per N·m of T2, or N)."""
    name, kind, x, _ = load
    data = rig.model_dump(by_alias=True)
    on = {"part": "output_shaft", "x_mm": x}
    if kind == "constant":
        data["force_table"] = {"apply": True, "scale": 1.0, "pairs": [],
                               "singles": [{"label": "hidden", "force_N": 1.0, "at": on}]}
        return Rig.model_validate(data)
    entries = [(on, 1.0)] if kind == "proportional" else [({"part": "output_shaft", "x_mm": x - 15.0}, 1.0),
                                                          ({"part": "output_shaft", "x_mm": x + 15.0}, -1.0)]
    for i, (where, sign) in enumerate(entries):
        data["torque_lateral_loads"].append({"name": f"hidden_{i}", "torque": "T2", "kind": "proportional", "on": where,
                                             "direction_deg": 0.0, "force_per_torque_N_per_Nm": sign})
    return Rig.model_validate(data)


@dataclass
class Responses:
    """Hybrid base paths and the change of the paths of every hidden effect or load (absolute, with the rest case)."""

    base: np.ndarray
    layout: PathLayout
    deltas: dict = field(default_factory=dict)  # name → (value, delta paths, linear)
    direct_pairs: dict = field(default_factory=dict)  # (a, b) → (values, delta paths) of a direct solve
    pairs: tuple = PAIRS  # the pairs of the design


def _observe(paths: np.ndarray, layout: PathLayout, datum: str, schema: str,
             cases: tuple[LoadCase, ...] | None = None, stations: int = STATIONS):
    """Observations of ``schema`` (11 stations per shaft for paths) of the paper's cases (or ``cases``, a subset),
    from absolute paths whose first case is the rest state."""
    from rvcoax.results.studies.discrepancy.responses import Observation, PathLayout  # noqa: F811
    from rvcoax.results.studies.discrepancy.synthetic import observation_layout

    per_case = paths.size // layout.n_cases
    table = paths.reshape(layout.n_cases, per_case)
    measured = table[1:] - (table[0] if datum == "aligned_at_rest" else 0.0)
    all_cases = paper_cases()
    if cases is not None:
        measured = measured[[all_cases.index(c) for c in cases]]
    cases = tuple(cases or all_cases)
    template = observation_layout(cases, stations, LENGTHS, schema)
    sub = PathLayout(len(cases), layout.stations_mm, layout.length_mm)
    return template, Observation(template, sub)(measured.ravel())


def _relative_change(delta_obs, base_obs, shaft) -> float:
    return max(float(np.sqrt(np.mean(delta_obs[shaft == s] ** 2)) / np.sqrt(np.mean(base_obs[shaft == s] ** 2)))
               for s in MEASURED_SHAFTS)


def build_responses(log=print, settings: SweepSettings = HYBRID, vocabulary=VOCABULARY, loads=OUT_OF_VOCABULARY,
                    pairs=PAIRS, direct_pairs: bool = True) -> Responses:
    """Solve (or read from the cache) every response the design needs, with the model of ``settings`` (default the
    hybrid model); ``vocabulary``, ``loads`` and ``pairs`` choose a subset of the design (``direct_pairs`` false: every
    pair of linear effects is superposed, none solved directly as a check)."""
    from rvcoax.results.studies.discrepancy.synthetic import effect_size_for, observation_layout

    rig = truth_rig("unloaded")
    effects = {e.name: e for e in candidate_effects(rig)}
    base, layout = absolute_paths(rig, settings, log=log)
    out = Responses(base, layout)
    template = observation_layout(paper_cases(), STATIONS, LENGTHS, "paths")
    for name in vocabulary:
        effect = effects[name]
        log(f"{name}:")
        if effect.linear:
            value = effect.parameters[0].typical
        else:
            value = effect_size_for(effect, rig, paper_cases(), template, TARGET[0])
        changed = effect.apply(rig, [value])
        if name.startswith("bearing_clearance"):  # neither the hybrid nor the solid model takes a clearance
            paths, _ = absolute_paths(fine_beam(changed), SweepSettings(), log=log)
            delta = paths - absolute_paths(fine_beam(rig), SweepSettings(), log=log)[0]
        else:
            paths, _ = absolute_paths(changed, settings, log=log)
            delta = paths - base
        out.deltas[name] = (value, delta, effect.linear)
    for load in loads:
        log(f"{load[0]}:")
        paths, _ = absolute_paths(_load_rig(rig, load), settings, log=log)
        out.deltas[load[0]] = (1.0, paths - base, True)
    out.pairs = tuple(pairs)
    for a, b in pairs:
        if not (effects[a].linear and effects[b].linear) or (direct_pairs and (a, b) == PAIRS[1]):  # the check
            log(f"{a} + {b} (direct):")
            values = {n: bounded_delta(out, n, "unloaded", TARGET[0], effects)[1] for n in (a, b)}
            rig_ab = effects[b].apply(effects[a].apply(rig, [values[a]]), [values[b]])
            paths, _ = absolute_paths(rig_ab, settings, log=log)
            out.direct_pairs[(a, b)] = (values, paths - base)
    return out


def superposition_check(responses: Responses) -> dict[str, float]:
    """RMS(direct − superposed) / RMS(direct change) of every pair solved directly (both at their sizes)."""
    out = {}
    for (a, b), (values, direct) in responses.direct_pairs.items():
        summed = sum(responses.deltas[n][1] * (values[n] / responses.deltas[n][0] if responses.deltas[n][2] else 1.0)
                     for n in (a, b))
        out[f"{a} + {b}"] = float(np.sqrt(np.mean((direct - summed) ** 2)) / np.sqrt(np.mean(direct ** 2)))
    return out


# ---- data sets ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class DataSet:
    """One hidden-effect data set: its truth and how it is written."""

    id: str
    group: str  # vocabulary | faint | none | pair | out_of_vocabulary
    truth: tuple[str, ...]  # vocabulary effect names (empty for none / out-of-vocabulary)
    load: str  # the out-of-vocabulary load's name, else ""
    datum: str
    schema: str
    noise: float
    seed: int
    notation: str
    fraction: float  # size of the hidden change, of the signal (RMS, on the shaft it changes most)


def _scaled_delta(responses: Responses, name: str, datum: str, fraction: float):
    """The change of a linear effect or load scaled to ``fraction`` of the signal on ``datum`` (paths, 11 stations),
    and its value; a nonlinear effect at its solved value."""
    value, delta, linear = responses.deltas[name]
    if not linear:
        return delta, value
    _, base_obs = _observe(responses.base, responses.layout, datum, "paths")
    _, delta_obs = _observe(responses.base + delta, responses.layout, datum, "paths")
    change = _relative_change(delta_obs - base_obs, base_obs, _observe_template_shaft())
    if change == 0.0:
        return delta * 0.0, 0.0
    return delta * fraction / change, value * fraction / change


def _observe_template_shaft():
    from rvcoax.results.studies.discrepancy.synthetic import observation_layout

    return observation_layout(paper_cases(), STATIONS, LENGTHS, "paths").shaft


def bounded_delta(responses: Responses, name: str, datum: str, fraction: float, effects: dict):
    """Like :func:`_scaled_delta`, but a vocabulary effect's value is kept within its physical bounds."""
    delta, value = _scaled_delta(responses, name, datum, fraction)
    if name in effects and responses.deltas[name][2]:
        p = effects[name].parameters[0]
        clipped = float(np.clip(value, p.lower, p.upper))
        if value != 0.0 and clipped != value:
            delta, value = delta * clipped / value, clipped
    return delta, value


def visible_fraction(responses: Responses, name: str, datum: str, effects: dict) -> float:
    """The largest change (of the signal) the effect can make on ``datum`` within its physical bounds."""
    value, delta, linear = responses.deltas[name]
    _, base_obs = _observe(responses.base, responses.layout, datum, "paths")
    if linear:
        p = effects[name].parameters[0]
        delta = delta * max(abs(p.lower), abs(p.upper)) / abs(value)
    _, obs = _observe(responses.base + delta, responses.layout, datum, "paths")
    return _relative_change(obs - base_obs, base_obs, _observe_template_shaft())


OUT_OF_BOUNDS = 2.0  # an out-of-bounds truth: a linear effect at this multiple of its bound (the larger in size)


def design(responses: Responses, out_of_bounds: bool = False) -> list[DataSet]:
    """The data sets (about 250), each with its truth; notations rotate over the sets. ``out_of_bounds``: also every
    linear effect at :data:`OUT_OF_BOUNDS` times its physical bound (Y from the unloaded geometry, seed 0)."""
    effects = {e.name: e for e in candidate_effects(truth_rig())}
    sets: list[tuple] = []
    for datum in DATUMS:
        for name in [n for n in VOCABULARY if n in responses.deltas]:
            reach = visible_fraction(responses, name, datum, effects)
            if reach < 1e-6:  # e.g. a load-independent effect on the aligned datum: invisible by construction
                continue
            group = "vocabulary" if reach >= FAINT else "faint"
            seeds = (0, 1) if datum == "unloaded" else (0,)
            sets += [(group, (name,), "", datum, seed) for seed in seeds]
        for pair in responses.pairs:
            if all(visible_fraction(responses, n, datum, effects) >= FAINT for n in pair):
                sets.append(("pair", pair, "", datum, 0))
        for load in [ld for ld in OUT_OF_VOCABULARY if ld[0] in responses.deltas]:
            if datum == "unloaded" or not load[3]:
                sets.append(("out_of_vocabulary", (), load[0], datum, 0))
        sets += [("none", (), "", datum, seed) for seed in (0, 1, 2)]
        if out_of_bounds and datum == "unloaded":
            sets += [("out_of_bounds", (name,), "", datum, 0) for name in VOCABULARY
                     if name in responses.deltas and responses.deltas[name][2]]
    out = []
    for group, truth, load, datum, seed in sets:
        for schema in SCHEMAS:
            for noise in NOISES:
                k = len(out)
                out.append(DataSet(f"{k:03d}", group, truth, load, datum, schema, noise, seed,
                                   NOTATIONS[k % len(NOTATIONS)], 0.0 if group == "none" else TARGET[seed % 3]))
    return out


def hidden_paths(responses: Responses, dataset: DataSet, effects: dict) -> tuple[np.ndarray, dict]:
    """Absolute paths of the rig with the data set's hidden effects or load, and the values used."""
    paths = responses.base.copy()
    values = {}
    if dataset.load:
        delta, value = _scaled_delta(responses, dataset.load, dataset.datum, dataset.fraction)
        return paths + delta, {dataset.load: value}
    if len(dataset.truth) == 2 and tuple(dataset.truth) in responses.direct_pairs:
        values, delta = responses.direct_pairs[tuple(dataset.truth)]
        return paths + delta, dict(values)
    if dataset.group == "out_of_bounds":
        name = dataset.truth[0]
        value, delta, _ = responses.deltas[name]
        p = effects[name].parameters[0]
        beyond = OUT_OF_BOUNDS * (p.upper if abs(p.upper) >= abs(p.lower) else p.lower)
        return paths + delta * beyond / value, {name: beyond}
    for name in dataset.truth:
        fraction = dataset.fraction if len(dataset.truth) == 1 else TARGET[0]
        delta, values[name] = bounded_delta(responses, name, dataset.datum, fraction, effects)
        paths = paths + delta
    return paths, values


def _formatter(notation: str, rng: np.random.Generator):
    fixed, expo, upper = "{:.9f}".format, "{:.5e}".format, "{:.5E}".format
    if notation == "fixed":
        return fixed
    if notation == "e":
        return expo
    if notation == "E":
        return upper
    return lambda v: (fixed, expo, upper, "{:.6g}".format)[int(rng.integers(4))](v)


def _torque_text(value: float, notation: str) -> str:
    return {"fixed": f"{value:g}", "e": f"{value:.4e}", "E": f"{value:.4E}"}.get(notation, f"{value:g}")


def noisy_observations(paths: np.ndarray, layout: PathLayout, datum: str, schema: str, noise: float, seed: int,
                       cases=None, stations: int = STATIONS):
    """The template and noisy observations (σ = noise × RMS of each shaft's values; a table holds magnitudes)."""
    template, values = _observe(paths, layout, datum, schema, cases, stations)
    rng = np.random.default_rng(10_000 + seed)
    sigma = np.zeros_like(values)
    for s in MEASURED_SHAFTS:
        mask = template.shaft == s
        sigma[mask] = noise * np.sqrt(np.mean(values[mask] ** 2))
    noisy = values + rng.normal(size=values.size) * sigma
    return template, (np.abs(noisy) if schema == "table" else noisy)


def csv_text(template, values: np.ndarray, notation: str, seed: int) -> str:
    """The data as a CSV file of its schema, numbers in ``notation``."""
    rng = np.random.default_rng(seed)
    number = _formatter(notation, rng)
    if template.schema == "paths":
        lines = ["T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm"]
        for c, s, x, v in zip(template.case_index, template.shaft, template.x_mm, values):
            case = template.cases[c]
            lines.append(f"{_torque_text(case.input_torque_Nm, notation)},{_torque_text(case.output_torque_Nm, notation)}"
                         f",{s},{x:g},{number(v)}")
    else:
        lines = ["T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm"]
        for c, case in enumerate(template.cases):
            y = {s: values[(template.case_index == c) & (template.shaft == s)][0] for s in MEASURED_SHAFTS}
            lines.append(f"{_torque_text(case.input_torque_Nm, notation)},{_torque_text(case.output_torque_Nm, notation)}"
                         f",{number(y['input'])},{number(y['output'])}")
    return "\n".join(lines) + "\n"


MODEL_FORM = 0.02  # the workflow's model-form allowance, of the signal


def detectability(paths: np.ndarray, responses: Responses, dataset: DataSet) -> float:
    """RMS over the observations of the noise-free hidden change in units of σ, where σ² = (noise × RMS of the
    shaft's values)² + (2 % of the value)²: below 1 the data cannot carry the effect (``no_gap`` is then right too).
    """
    _, hidden = _observe(paths, responses.layout, dataset.datum, dataset.schema)
    template, plain = _observe(responses.base, responses.layout, dataset.datum, dataset.schema)
    sigma = np.zeros_like(hidden)
    for s in MEASURED_SHAFTS:
        mask = template.shaft == s
        sigma[mask] = np.hypot(dataset.noise * np.sqrt(np.mean(hidden[mask] ** 2)), MODEL_FORM * np.abs(plain[mask]))
    return float(np.sqrt(np.mean(((hidden - plain) / np.maximum(sigma, 1e-300)) ** 2)))


def write_sets(responses: Responses, out: Path, log=print, model: str = "", out_of_bounds: bool = False) -> list[dict]:
    """Write every data set of :func:`design` as ``<id>.csv`` under ``out`` and ``manifest.json``."""
    effects = {e.name: e for e in candidate_effects(truth_rig())}
    out.mkdir(parents=True, exist_ok=True)
    manifest = []
    for dataset in design(responses, out_of_bounds):
        paths, values = hidden_paths(responses, dataset, effects)
        template, noisy = noisy_observations(paths, responses.layout, dataset.datum, dataset.schema, dataset.noise,
                                             dataset.seed)
        (out / f"{dataset.id}.csv").write_text(csv_text(template, noisy, dataset.notation, int(dataset.id)))
        detect = detectability(paths, responses, dataset)
        entry = dict(dataset.__dict__, truth=list(dataset.truth), file=f"{dataset.id}.csv",
                     values={k: float(v) for k, v in values.items()}, detectability=round(detect, 4),
                     detectable=dataset.group == "none" or detect >= 1.0)
        manifest.append(entry)
    (out / "manifest.json").write_text(json.dumps({"model": model or "hybrid", "superposition_check":
                                                   superposition_check(responses), "sets": manifest}, indent=1))
    log(f"wrote {len(manifest)} data sets to {out}")
    return manifest


# the committed fixtures (tests/results/studies/data/blind): a few small files, 7 of the paper's cases, 6 stations per shaft
FIXTURE_CASES = (0, 3, 6, 9, 12, 15, 19)
FIXTURE_STATIONS = 6
FIXTURES = (  # name, truth, load, datum, schema, noise, notation
    ("none_exact", (), "", "unloaded", "paths", 0.0, "e"),
    ("none", (), "", "unloaded", "paths", 0.01, "e"),
    ("none_table", (), "", "aligned_at_rest", "table", 0.01, "fixed"),
    ("torque_reaction", ("torque_reaction@output_bearing_block",), "", "aligned_at_rest", "table", 0.01, "E"),
    ("coupling_angle", ("coupling_angle@C3",), "", "unloaded", "paths", 0.01, "fixed"),
    ("bearing_stiffness", ("bearing_stiffness@output_B2",), "", "aligned_at_rest", "paths", 0.05, "E"),
    ("pair", ("mesh_force@reducer_input", "torque_reaction@output_bearing_block"), "", "unloaded", "table", 0.05,
     "mixed"),
    ("lateral_load", (), "lateral_T2@output_x80", "aligned_at_rest", "paths", 0.01, "e"),
)


def write_fixtures(responses: Responses, out: Path, log=print, fixtures=FIXTURES, model: str = "",
                   generator: str = "benchmarks/blind_data.py") -> None:
    """Write the small committed fixture set and its ``manifest.json`` (truth and provenance of each file)."""
    effects = {e.name: e for e in candidate_effects(truth_rig())}
    cases = tuple(paper_cases()[i] for i in FIXTURE_CASES)
    out.mkdir(parents=True, exist_ok=True)
    manifest = {"model": model or "hybrid (reference rig, self-weight off, Euler-Bernoulli beams; clearances: beam at "
                f"{FINE_BEAM_ELEMENT_MM:g} mm elements)", "generator": generator, "sets": []}
    for seed, (name, truth, load, datum, schema, noise, notation) in enumerate(fixtures):
        group = ("out_of_vocabulary" if load else "none" if not truth else "pair" if len(truth) == 2 else "vocabulary")
        dataset = DataSet(name, group, truth, load, datum, schema, noise, seed, notation, TARGET[0])
        paths, values = hidden_paths(responses, dataset, effects)
        template, noisy = noisy_observations(paths, responses.layout, datum, schema, noise, seed, cases,
                                             FIXTURE_STATIONS)
        (out / f"{name}.csv").write_text(csv_text(template, noisy, notation, seed))
        manifest["sets"].append(dict(dataset.__dict__, truth=list(truth), file=f"{name}.csv",
                                     values={k: round(float(v), 6) for k, v in values.items()}))
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    log(f"wrote {len(fixtures)} fixtures to {out}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(CACHE / "sets"))
    parser.add_argument("--fixtures", default="", help="also write the committed fixture set to this folder")
    args = parser.parse_args()
    responses = build_responses()
    if args.fixtures:
        write_fixtures(responses, Path(args.fixtures))
    for pair, error in superposition_check(responses).items():
        print(f"superposition vs direct solve, {pair}: {100 * error:.2g} % of the change")
    write_sets(responses, Path(args.out))


if __name__ == "__main__":
    main()
