"""Beam vs hybrid vs solid on the 20 paper cases, what the differences come from, and hybrid timing.

Run: ``.venv/bin/python benchmarks/bench_fidelity.py [--no-record] [--repeats 3]``. Writes
benchmarks/fidelity_20_cases.csv and appends a summary to benchmarks/RESULTS.md.

1. **Side by side.** Y_input and Y_output of the 20 paper cases for the beam, hybrid and solid
   models (rig-file mesh settings), blind (the rig as built) and calibrated (each model calibrated
   with its own settings and prepared model), with hybrid/beam − 1 and solid/beam − 1 per case;
   the unit responses (T1, T2, engaged per 1 µm of position error, self-weight) of each model.
2. **Effects.** Numerical experiments that isolate one modelling difference at a time, each
   reported as a number (see EFFECTS below): load distribution over the gear band, tie type at
   every solid attachment, ring averaging of the probe, Poisson's ratio, shaft shoulders, the
   beam's shear flexibility, housings as solids.
3. **Timing.** The hybrid model end to end from a cold mesh cache (temporary RVCOAX_CACHE_DIR):
   load the rig, mesh, assemble, factorise, solve, post-process; the 20-case sweep and a single
   case, alternated ``--repeats`` times after one uncounted warm-up (first imports), plus the same
   through the ``rvcoax sweep`` command line (a new process: adds Python start-up, imports and
   writing the result files).
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import dataclasses
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_convergence import cold_cache, timed_calls, timed_meshing  # noqa: E402
from machine import record  # noqa: E402

import rvcoax.geometry.model.hybrid as hybrid  # noqa: E402
from rvcoax.fem import solid as fem_solid  # noqa: E402
from rvcoax.geometry.model.loads import UNIT_LOADS  # noqa: E402
from rvcoax.geometry.parameters import with_parameters  # noqa: E402
from rvcoax.geometry.rigfile import load_rig  # noqa: E402
from rvcoax.geometry.schema import Rig  # noqa: E402
from rvcoax.loadcases.cases import paper_cases, paper_table  # noqa: E402
from rvcoax.results.studies.calibration import calibrate  # noqa: E402
from rvcoax.results.sweep import SweepSettings, prepare_model, run_sweep  # noqa: E402

HERE = Path(__file__).resolve().parent
CSV_PATH = HERE / "fidelity_20_cases.csv"
MODELS = ("beam", "hybrid", "solid")
POSITION_ERRORS = ("torque_lateral_loads.sun_gear_load_sharing.position_error_um",
                   "torque_lateral_loads.crankshaft_load_sharing.position_error_um")
SWEEP_LIMIT_S = 60.0
UNITS = (("T1", "input"), ("T1", "output"), ("T2", "output"), ("engaged_T1", "input"), ("engaged_T2", "output"),
         ("gravity", "input"), ("gravity", "output"))


# ----------------------------------------------------------------------------------------- helpers


def unit_responses(rig: Rig, settings: SweepSettings, prepared, engaged_rig: Rig | None = None
                   ) -> dict[tuple[str, str], float]:
    """Largest |u_y| (mm) of each unit load on each path; engaged loads per 1 µm position error
    (``engaged_rig``: ``rig`` with 1 µm position errors, by default made here)."""
    cases = paper_cases()[:1]
    unit = run_sweep(rig, cases, settings, prepared=prepared).unit_paths
    if engaged_rig is None:
        engaged_rig = with_parameters(rig, dict.fromkeys(POSITION_ERRORS, 1.0))
    engaged = run_sweep(engaged_rig, cases, settings, prepared=prepared).unit_paths
    out = {}
    for name, path in UNITS:
        source = engaged if name.startswith("engaged") else unit
        out[(name, path)] = source[name][path].y_max_mm
    return out


def y_table(sweep) -> np.ndarray:
    """(cases, 2) array of Y_input, Y_output (mm)."""
    return np.array([[c.paths[s].y_max_mm for s in MEASURED_SHAFTS] for c in sweep.cases])


def with_material(rig: Rig, material: str, **values) -> Rig:
    data = rig.model_dump(by_alias=True)
    data["materials"][material].update(values)
    return Rig.model_validate(data)


def with_bearing_width(rig: Rig, shafts: tuple[str, ...], width_mm: float) -> Rig:
    data = rig.model_dump(by_alias=True)
    for bearing in data["bearings"]:
        if bearing["shaft"] in shafts:
            bearing["width_mm"] = width_mm
    return Rig.model_validate(data)


def with_uniform_shafts(rig: Rig) -> Rig:
    """The measured shafts with every segment at the shaft's largest section (no shoulders)."""
    data = rig.model_dump(by_alias=True)
    for part in data["parts"]:
        if part["name"] in (rig.paths.input.part, rig.paths.output.part):
            outer = max(s["outer_diameter_mm"] for s in part["segments"])
            inner = max(s["inner_diameter_mm"] for s in part["segments"])
            for s in part["segments"]:
                s["outer_diameter_mm"], s["inner_diameter_mm"] = outer, inner
    return Rig.model_validate(data)


def with_band_load_on_beam(rig: Rig, name: str, pieces: int = 18) -> Rig:
    """The beam analogue of a band traction: load ``name`` split into ``pieces`` equal point loads
    spread uniformly over its band (imbalance and position error divided, both enter linearly)."""
    data = rig.model_dump(by_alias=True)
    loads = []
    for load in data["torque_lateral_loads"]:
        band = load["on"].get("band_mm")
        if load["name"] != name or band is None:
            loads.append(load)
            continue
        for k in range(pieces):
            piece = {**load, "name": f"{name}_{k}", "on": {**load["on"], "band_mm": None}}
            piece["on"]["x_mm"] = band[0] + (k + 0.5) * (band[1] - band[0]) / pieces
            piece["imbalance"] = load["imbalance"] / pieces
            piece["position_error_um"] = load["position_error_um"] / pieces
            loads.append(piece)
    data["torque_lateral_loads"] = loads
    return Rig.model_validate(data)


@contextlib.contextmanager
def all_ties(kind: str):
    """Every attachment to a solid tied ``kind`` ("rigid" or "distributing") while assembling."""
    original = hybrid.attachments

    def patched(rig, names):
        return [dataclasses.replace(a, tie=kind) for a in original(rig, names)]

    hybrid.attachments = patched
    try:
        yield
    finally:
        hybrid.attachments = original


def ring_points(sweep, which: str, unit: str) -> dict[str, float]:
    """u_y (mm) of unit load ``unit`` at the path's station of max: ring mean (the probe), single
    points at 0°, 90°, 180°, 270° on the probe radius, and on the axis (solid shafts only)."""
    system = sweep.system
    path = getattr(system.rig.paths, which)
    part = next(s for s in system.solids if s.name == path.part)
    column = sweep.unit_displacements[:, UNIT_LOADS.index(unit)]
    local = column[part.offset: part.offset + part.n_dofs]
    result = sweep.unit_paths[unit][which]
    x = path.x_start_mm + result.station_of_max_mm
    lo, hi = part.geometry.segments[0][0], part.geometry.segments[-1][1]
    x = min(max(x, lo + 1e-3), hi - 1e-3)
    outer, inner = part.geometry.section_at(x)
    r = 0.25 * (outer + inner)  # mid-wall radius, as the probe
    named = {"top (+y)": (r, 0.0), "side (+z)": (0.0, r), "bottom (-y)": (-r, 0.0), "side (-z)": (0.0, -r)}
    if inner == 0.0:
        named["axis"] = (0.0, 0.0)
    points = np.array([[x * 1e-3, y * 1e-3, z * 1e-3] for y, z in named.values()])
    probe = fem_solid.probe_matrix(part.basis, points)
    uy = (probe[1::3] @ local) * 1e3
    out = {name: float(v) for name, v in zip(named, uy)}
    out["ring mean (probe)"] = result.y_max_signed_mm
    out["x_mm"] = x
    out["radius_mm"] = r
    return out


def pct(a: float, b: float) -> float:
    """100 (a / b − 1)."""
    return 100.0 * (a / b - 1.0) if b else float("nan")


# ------------------------------------------------------------------------------------------ timing


def hybrid_end_to_end(cases) -> dict[str, float]:
    """Load the rig, mesh (cold cache), assemble, factorise, solve and post-process ``cases``."""
    seconds = {"mesh": 0.0, "probes": 0.0}
    with cold_cache(), timed_meshing(seconds), timed_calls(seconds, "probes", hybrid, "ring_probe"):
        start = time.perf_counter()
        rig = load_rig()
        settings = SweepSettings(model="hybrid")
        prepared = prepare_model(rig, settings)
        seconds["prepare"] = time.perf_counter() - start
        run_sweep(rig, cases, settings, prepared=prepared)
        seconds["total"] = time.perf_counter() - start
    seconds["factorise"] = float(prepared.report["setup_seconds"])
    seconds["sweep"] = seconds["total"] - seconds["prepare"]
    return seconds


def cli_end_to_end(extra: list[str]) -> float:
    """Wall time of ``rvcoax sweep --model hybrid`` from a cold mesh cache (a fresh process)."""
    exe = Path(sys.executable).with_name("rvcoax")
    command = [str(exe)] if exe.exists() else [sys.executable, "-m", "rvcoax.results.cli.app"]
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = {**os.environ, "RVCOAX_CACHE_DIR": cache}
        start = time.perf_counter()
        subprocess.run([*command, "sweep", "--model", "hybrid", "--out", out, *extra], check=True, env=env,
                       cwd=HERE.parent, stdout=subprocess.DEVNULL)
        return time.perf_counter() - start


def timing(repeats: int) -> tuple[list[tuple[str, str]], dict]:
    cases = paper_cases()
    single = cases[:1]
    hybrid_end_to_end(single)  # warm-up, not counted: first imports of gmsh, MKL PARDISO, skfem kernels
    load_before = os.getloadavg()[0]
    sweeps, singles = [], []
    for _ in range(repeats):
        singles.append(hybrid_end_to_end(single))
        sweeps.append(hybrid_end_to_end(cases))
    cli_sweep = cli_end_to_end([])
    cli_single = cli_end_to_end(["--t1", f"{single[0].input_torque_Nm:g}", "--t2", f"{single[0].output_torque_Nm:g}"])
    load_after = os.getloadavg()[0]
    t20 = [s["total"] for s in sweeps]
    t1 = [s["total"] for s in singles]
    best20, best1 = min(sweeps, key=lambda s: s["total"]), min(singles, key=lambda s: s["total"])
    ratio_median = statistics.median(t20) / statistics.median(t1)
    ratio_best = best20["total"] / best1["total"]
    per_case = (statistics.median(t20) - statistics.median(t1)) / (len(cases) - 1)

    def split(s):
        assemble = s["prepare"] - s["mesh"] - s["factorise"] - s["probes"]
        return (f"load rig + mesh {s['mesh']:.2f} s + assemble, ties, loads, support check {assemble:.2f} s + "
                f"locating the 2 × 41 × 8 ring-probe points {s['probes']:.2f} s + factorise "
                f"{s['factorise']:.2f} s + unit solves and cases {s['sweep']:.2f} s")

    rows = [
        ("hybrid 20-case sweep end to end, cold mesh cache (best / median of "
         f"{repeats})", f"{min(t20):.2f} / {statistics.median(t20):.2f} s  [{split(best20)}]"),
        (f"hybrid single case (T1 = {single[0].input_torque_Nm:g}, T2 = {single[0].output_torque_Nm:g}) end to end, "
         f"cold (best / median of {repeats})", f"{min(t1):.2f} / {statistics.median(t1):.2f} s  [{split(best1)}]"),
        ("ratio 20-case sweep / single case", f"{ratio_median:.3f} (medians), {ratio_best:.3f} (best); "
                                              f"{1e3 * per_case:.0f} ms per extra case"),
        ("`rvcoax sweep --model hybrid` (new process, cold cache, writes files): 20 cases / 1 case",
         f"{cli_sweep:.2f} s / {cli_single:.2f} s (ratio {cli_sweep / cli_single:.3f})"),
        ("20-case hybrid sweep < 60 s on this machine?",
         f"{'yes' if max(max(t20), cli_sweep) < SWEEP_LIMIT_S else 'NO'} (slowest of all runs "
         f"{max(max(t20), cli_sweep):.1f} s)"),
        ("load average (1 min) before / after timing", f"{load_before:.2f} / {load_after:.2f}"),
    ]
    return rows, {"t20": t20, "t1": t1, "cli": (cli_sweep, cli_single)}


# -------------------------------------------------------------------------------------------- main


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="timing repeats (default %(default)s)")
    parser.add_argument("--no-record", action="store_true", help="do not append to RESULTS.md")
    args = parser.parse_args()
    t_script = time.perf_counter()
    rig = load_rig()
    cases = paper_cases()
    published = paper_table()
    rows: list[tuple[str, str]] = []

    # ---- timing first, on a quiet process (nothing cached in memory yet)
    timing_rows, _ = timing(args.repeats)
    for name, value in timing_rows:
        print(f"{name}: {value}", flush=True)

    # ---- the three models, blind and calibrated
    blind, calibrated, units, fitted, info, sweeps = {}, {}, {}, {}, {}, {}
    for model in MODELS:
        settings = SweepSettings(model=model)
        start = time.perf_counter()
        prepared = prepare_model(rig, settings)
        t_prepare = time.perf_counter() - start
        sweep = run_sweep(rig, cases, settings, prepared=prepared)
        blind[model] = y_table(sweep)
        sweeps[model] = sweep
        units[model] = unit_responses(rig, settings, prepared)
        start = time.perf_counter()
        calibration = calibrate(rig, published, settings=settings, prepared=prepared)
        t_calibrate = time.perf_counter() - start
        fitted[model] = calibration.values()
        calibrated[model] = y_table(run_sweep(calibration.rig, cases, settings, prepared=prepared))
        units[model].update({(f"calibrated {k}", p): v for (k, p), v in
                             unit_responses_calibrated(calibration.rig, settings, prepared).items()})
        info[model] = (prepared.system.n_dofs, prepared.solver_name, t_prepare, t_calibrate)
        print(f"{model}: {prepared.system.n_dofs} DOF, {prepared.solver_name}, set-up {t_prepare:.1f} s, "
              f"calibration {t_calibrate:.2f} s", flush=True)
        if model != "hybrid":
            del prepared

    write_csv(cases, published, blind, calibrated)
    rows += [(f"{m} model", f"{info[m][0]} DOF, {info[m][1]}, assemble + factorise {info[m][2]:.1f} s, "
                            f"calibration {info[m][3]:.2f} s") for m in MODELS]
    rows += comparison_rows(blind, calibrated, units, fitted)

    # ---- effects, one at a time
    effect_rows = effects(rig, sweeps, units)
    rows += effect_rows
    rows += timing_rows
    t_total = time.perf_counter() - t_script
    rows.append(("script runtime", f"{t_total:.0f} s"))

    print()
    for name, value in rows:
        print(f"{name}: {value}")
    print(f"\nwrote {CSV_PATH}")
    if not args.no_record:
        record("bench_fidelity.py: beam vs hybrid vs solid, 20 paper cases, reference rig", rows)


def unit_responses_calibrated(rig: Rig, settings: SweepSettings, prepared) -> dict[tuple[str, str], float]:
    """Unit responses of a calibrated rig (its own imbalance and position errors)."""
    unit = run_sweep(rig, paper_cases()[:1], settings, prepared=prepared).unit_paths
    return {(name, path): unit[name][path].y_max_mm for name, path in UNITS if not name.startswith("gravity")}


def write_csv(cases, published, blind, calibrated) -> None:
    header = ["T1_input_Nm", "T2_output_Nm", "published_Y_input_mm", "published_Y_output_mm"]
    for kind in ("blind", "calibrated"):
        for model in MODELS:
            header += [f"{kind}_{model}_Y_input_mm", f"{kind}_{model}_Y_output_mm"]
        for model in MODELS[1:]:
            header += [f"{kind}_{model}_vs_beam_input_pct", f"{kind}_{model}_vs_beam_output_pct"]
    lines = []
    for i, (case, row) in enumerate(zip(cases, published)):
        line = [case.input_torque_Nm, case.output_torque_Nm, row.y_input_mm, row.y_output_mm]
        for table in (blind, calibrated):
            for model in MODELS:
                line += [f"{table[model][i, 0]:.9g}", f"{table[model][i, 1]:.9g}"]
            for model in MODELS[1:]:
                line += [f"{pct(table[model][i, k], table['beam'][i, k]):.6g}" for k in (0, 1)]
        lines.append(line)
    temporary = CSV_PATH.with_suffix(".csv.tmp")
    with temporary.open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(header)
        writer.writerows(lines)
    os.replace(temporary, CSV_PATH)


def comparison_rows(blind, calibrated, units, fitted) -> list[tuple[str, str]]:
    rows = []
    for kind, table in (("blind", blind), ("calibrated", calibrated)):
        for model in MODELS[1:]:
            for k, shaft in enumerate(MEASURED_SHAFTS):
                d = np.array([pct(a, b) for a, b in zip(table[model][:, k], table["beam"][:, k])])
                rows.append((f"{kind} Y_{shaft}, {model} vs beam (20 cases)",
                             f"max |Δ| {np.abs(d).max():.3g} % (case T2 = {paper_cases()[int(np.abs(d).argmax())].output_torque_Nm:g}), "
                             f"median {np.median(d):+.3g} %, range {d.min():+.3g} … {d.max():+.3g} %"))
    for name, path in UNITS + tuple((f"calibrated {n}", p) for n, p in UNITS if not n.startswith("gravity")):
        values = [units[m][(name, path)] for m in MODELS]
        unit = "mm per µm" if "engaged" in name and not name.startswith("calibrated") else (
            "mm" if name.startswith(("gravity", "calibrated engaged")) else "mm per N·m")
        label = name.replace("engaged_T", "engaged T") + (" (per 1 µm position error)" if name.startswith("engaged") else "")
        rows.append((f"unit response {label} → {path} Y_max ({unit}), beam / hybrid / solid",
                     " / ".join(f"{v:.6g}" for v in values)
                     + (f"  (hybrid {pct(values[1], values[0]):+.3f} %, solid {pct(values[2], values[0]):+.3f} %)"
                        if values[0] > 1e-15 else "")))
    for key in fitted["beam"]:
        rows.append((f"calibrated {'.'.join(key.split('.')[1:])}, beam / hybrid / solid",
                     " / ".join(f"{fitted[m][key]:.6g}" for m in MODELS)
                     + f"  (hybrid {pct(fitted['hybrid'][key], fitted['beam'][key]):+.3f} %, "
                       f"solid {pct(fitted['solid'][key], fitted['beam'][key]):+.3f} %)"))
    return rows


def effects(rig: Rig, sweeps, units) -> list[tuple[str, str]]:
    """Numerical experiments isolating one modelling difference at a time."""
    rows = []
    beam, hyb = SweepSettings(model="beam"), SweepSettings(model="hybrid")

    def pair(variant: Rig, ties: str | None = None) -> tuple[dict, dict]:
        b = unit_responses(variant, beam, prepare_model(variant, beam))
        with all_ties(ties) if ties else contextlib.nullcontext():
            prepared = prepare_model(variant, hyb)
        h = unit_responses(variant, hyb, prepared)
        return b, h

    base_b, base_h = units["beam"], units["hybrid"]
    t1, t2 = ("T1", "input"), ("T2", "output")

    def ratio_text(b, h):
        return f"T1→input {pct(h[t1], b[t1]):+.3f} %, T2→output {pct(h[t2], b[t2]):+.3f} %"

    rows.append(("EFFECT baseline hybrid vs beam", ratio_text(base_b, base_h)))

    # 1. where the gear load acts: beam point load at x = 330 mm vs the band traction 322…340 mm
    spread = with_band_load_on_beam(rig, "sun_gear_load_sharing")
    spread_engaged = with_band_load_on_beam(with_parameters(rig, dict.fromkeys(POSITION_ERRORS, 1.0)),
                                            "sun_gear_load_sharing")
    b_spread = unit_responses(spread, beam, prepare_model(spread, beam), spread_engaged)
    e1 = ("engaged_T1", "input")
    rows.append(("EFFECT load distribution: beam with the sun-gear load spread over its band 322…340 mm "
                 "(18 point loads) vs at x = 330 mm",
                 f"beam T1→input {pct(b_spread[t1], base_b[t1]):+.3f} %, engaged T1→input "
                 f"{pct(b_spread[e1], base_b[e1]):+.3f} %; hybrid vs this beam: T1→input "
                 f"{pct(base_h[t1], b_spread[t1]):+.3f} % (vs the point-load beam {pct(base_h[t1], base_b[t1]):+.3f} %)"))

    # 2. tie type at every attachment to the solid shafts
    with all_ties("rigid"):
        prepared = prepare_model(rig, hyb)
    h_rigid = unit_responses(rig, hyb, prepared)
    rows.append(("EFFECT ties: every attachment to the solids rigid (RBE2) instead of distributing (RBE3; "
                 "C2 hub and the output flange are rigid in the rig file)",
                 f"hybrid all-rigid vs beam: {ratio_text(base_b, h_rigid)}; vs distributing hybrid "
                 f"T1→input {pct(h_rigid[t1], base_h[t1]):+.3f} %, T2→output {pct(h_rigid[t2], base_h[t2]):+.3f} %"))
    del prepared

    # 3. ring averaging: the probe's ring mean vs single points, at each path's station of max
    for which, unit in (("input", "T1"), ("output", "T2")):
        pts = ring_points(sweeps["hybrid"], which, unit)
        mean = pts["ring mean (probe)"]
        top_bottom = 0.5 * (pts["top (+y)"] + pts["bottom (-y)"])
        sides = 0.5 * (pts["side (+z)"] + pts["side (-z)"])
        twist = -(pts["side (+z)"] - pts["side (-z)"]) / (2.0 * pts["radius_mm"])  # u_y = −θ_x z
        text = (f"ring mean {mean:.6g}; top {pct(pts['top (+y)'], mean):+.3f} %, bottom "
                f"{pct(pts['bottom (-y)'], mean):+.3f} %, mean of top and bottom {pct(top_bottom, mean):+.3f} %, "
                f"mean of the two sides {pct(sides, mean):+.3f} %; a single side point is off by "
                f"{abs(pts['side (+z)']):.3g} mm because the section turns by θx = {twist:.4g} rad")
        if "axis" in pts:
            text += f"; axis {pct(pts['axis'], mean):+.4f} %"
        rows.append((f"EFFECT ring averaging: {unit}→{which} u_y at x = {pts['x_mm']:.1f} mm on r = "
                     f"{pts['radius_mm']:.2f} mm (unit load {unit}, mm per N·m)", text))

    # 4. Poisson's ratio of the shafts' steel (Q460, also the beams' G)
    nu0 = with_material(rig, "Q460", poisson_ratio=0.0)
    b0, h0 = pair(nu0)
    rows.append(("EFFECT Poisson: Q460 ν = 0 instead of 0.28 in both models",
                 f"hybrid vs beam at ν = 0: {ratio_text(b0, h0)} (at ν = 0.28: {ratio_text(base_b, base_h)}); "
                 f"beam T1→input {pct(b0[t1], base_b[t1]):+.3f} %, hybrid {pct(h0[t1], base_h[t1]):+.3f} %"))

    # 5. shoulders: the measured shafts without steps
    uniform = with_uniform_shafts(rig)
    bu, hu = pair(uniform)
    rows.append(("EFFECT shoulders: measured shafts at their largest section throughout (no steps)",
                 f"hybrid vs beam without steps: {ratio_text(bu, hu)} (with steps: {ratio_text(base_b, base_h)})"))

    # 6. the beam's shear flexibility (Timoshenko): G raised 26× (ν = −0.95, beam only)
    stiff_shear = with_material(rig, "Q460", poisson_ratio=-0.95)
    b_shear = unit_responses(stiff_shear, beam, prepare_model(stiff_shear, beam))
    rows.append(("EFFECT shear: beam with Q460 shear modulus ×25.6 (ν = −0.95; bending unchanged)",
                 f"beam T1→input {pct(b_shear[t1], base_b[t1]):+.3f} %, T2→output {pct(b_shear[t2], base_b[t2]):+.3f} % "
                 "(= minus the shear share of the beam's response)"))

    # 7. how much of each response is shaft bending at all: shafts (Q460) 1000× stiffer, beam model
    rigid_shafts = with_material(rig, "Q460", youngs_modulus_MPa=2.06e8)
    b_rigid = unit_responses(rigid_shafts, beam, prepare_model(rigid_shafts, beam))
    rows.append(("EFFECT shaft elasticity share: beam with Q460 shafts 1000× stiffer (springs unchanged)",
                 f"T1→input {pct(b_rigid[t1], base_b[t1]):+.2f} %, T2→output {pct(b_rigid[t2], base_b[t2]):+.2f} % "
                 "(the rest of the response is bearing, coupling, joint and mount springs)"))

    # 8. bearing band width: the distributing tie over a 2 mm band instead of the bearing's width
    narrow = with_bearing_width(rig, (rig.paths.input.part, rig.paths.output.part), 2.0)
    h_narrow = unit_responses(narrow, hyb, prepare_model(narrow, hyb))
    rows.append(("EFFECT bearing band: shaft bearings tied over 2 mm instead of 14 mm (6204) / 16 mm (6206)",
                 f"hybrid vs beam: {ratio_text(base_b, h_narrow)}; vs the hybrid with full bands T1→input "
                 f"{pct(h_narrow[t1], base_h[t1]):+.3f} %, T2→output {pct(h_narrow[t2], base_h[t2]):+.3f} %"))

    # 9. housings as solids: solid vs hybrid (same shafts, housings and bodies meshed)
    s = units["solid"]
    rows.append(("EFFECT housings as solids: solid vs hybrid",
                 f"T1→input {pct(s[t1], base_h[t1]):+.3f} %, T2→output {pct(s[t2], base_h[t2]):+.3f} %, "
                 f"self-weight sag input {pct(s[('gravity', 'input')], base_h[('gravity', 'input')]):+.3f} %, "
                 f"output {pct(s[('gravity', 'output')], base_h[('gravity', 'output')]):+.3f} % "
                 f"(hybrid vs beam sag: input {pct(base_h[('gravity', 'input')], base_b[('gravity', 'input')]):+.3f} %, "
                 f"output {pct(base_h[('gravity', 'output')], base_b[('gravity', 'output')]):+.3f} %)"))
    return rows


if __name__ == "__main__":
    main()
