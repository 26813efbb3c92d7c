"""Angular-contact and roller bearings from geometry on the reference rig: cost of a 20-case nonlinear sweep.

Times the 20 paper cases (beam model) on the ``rolling_bearings`` variant — a 7204 B DB pair (light preload),
an NU 204 (C2) and two 30206 tapered roller bearings with 10 µm end play, solved by Newton on the condensed
bearing motions with one factorisation — next to the typed-in linear reference rig and the deep-groove
ball-bearing variant; the cost of one law evaluation per bearing type; and a scan of the rings' settings
(preload classes, end play, slices) for convergence. Target (issue 25): the 20-case sweep under 2 s on
2 cores. Prints the figures and appends them to benchmarks/RESULTS.md with the machine, date and load.

Run: ``.venv/bin/python benchmarks/bench_rolling_bearings.py``
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
from machine import publish  # noqa: E402

from rvcoax.fem.rolling_bearing import bearing_force  # noqa: E402
from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text  # noqa: E402
from rvcoax.geometry.rolling_model import rolling_bearing_model  # noqa: E402
from rvcoax.loadcases.cases import paper_table  # noqa: E402
from rvcoax.results.sweep import run_sweep  # noqa: E402

REPEATS = 5


def _timed(function, repeats: int = REPEATS):
    walls, cpus, result = [], [], None
    for _ in range(repeats):
        wall, cpu = time.perf_counter(), time.process_time()
        result = function()
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return statistics.median(walls), min(walls), statistics.median(cpus), result


def _variant(replacements: dict[str, str]) -> str:
    text = reference_rig_text("rolling_bearings")
    for old, new in replacements.items():
        assert old in text, old
        text = text.replace(old, new)  # every occurrence (both tapered bearings)
    return text


def main() -> None:
    cases = tuple(r.case for r in paper_table())
    load_before = os.getloadavg()[0]
    figures: list[tuple[str, str]] = []
    for label, text in (("typed-in linear bearings (reference rig)", reference_rig_text()),
                        ("deep-groove ball bearings, CN (ball_bearings variant)", reference_rig_text("ball_bearings")),
                        ("7204 B DB + NU 204 + 2 × 30206 (rolling_bearings variant)",
                         reference_rig_text("rolling_bearings")),
                        ("the same with every bearing engaged: NU 204 zero clearance, 30206 pair preloaded (+5 µm "
                         "each)", _variant({'clearance_class = "C2"': "clearance_um = 0",
                                            "axial_offset_um = -5": "axial_offset_um = 5"}))):
        rig = parse_rig_text(text, label)
        median, best, cpu, sweep = _timed(lambda rig=rig: run_sweep(rig, cases))
        newton = sweep.solver_report.get("newton_iterations_max")
        figures.append((f"sweep, 20 paper cases + rest, beam model: {label}",
                        f"{median:.3f} s wall median (best {best:.3f} s), {cpu:.3f} s CPU median, {REPEATS} runs"
                        + (f"; Newton iterations ≤ {newton} per case" if newton is not None else "")))
    # one law evaluation (force and 6 × 6 tangent) per bearing type
    rig = parse_rig_text(reference_rig_text("rolling_bearings"), "variant")
    motion = np.array([2e-6, 8e-6, -3e-6, 0.0, 1e-4, -1e-4])
    for bearing in rig.bearings:
        if bearing.model == "linear":
            continue
        model = rolling_bearing_model(bearing)
        start, calls = time.process_time(), 2000
        for _ in range(calls):
            bearing_force(model.bearing, motion)
        rows = model.bearing.rows
        elements = sum(getattr(r.law, "roller_count", getattr(r.law, "ball_count", 0)) for r in rows)
        slices = getattr(rows[0].law, "slices", 1)
        figures.append((f"law evaluation, {bearing.name} ({bearing.model}, {bearing.designation}, {len(rows)} row(s), "
                        f"{elements} elements × {slices} slices)",
                        f"{(time.process_time() - start) / calls * 1e6:.0f} µs CPU per call"))
    # robustness: the rings' settings and the slicing converge on the 20 cases
    start, solved = time.process_time(), 0
    scans = [{'preload_class = "light"': f'preload_class = "{c}"'} for c in ("medium", "heavy")]
    scans += [{"axial_offset_um = -5": f"axial_offset_um = {v}"} for v in (-20, 0, 5)]
    scans += [{'clearance_class = "C2"': 'clearance_class = "C4"'},
              {'model = "cylindrical_roller"        # line contact by slicing':
               'model = "cylindrical_roller"\nslices_per_roller = 60\ncrowning = "circular"\ncrown_drop_um = 8'}]
    for replacements in scans:
        run_sweep(parse_rig_text(_variant(replacements), "scan"), cases)
        solved += 1
    figures.append(("scan: preload class medium/heavy, tapered offset −20/0/+5 µm, NU 204 C4, 60 slices circular "
                    "crowning; 20 cases each", f"{solved} sweeps, all converged, {time.process_time() - start:.1f} s CPU"))
    publish("bench_rolling_bearings.py: 20-case sweep with angular-contact and roller bearings from geometry",
            figures, load_before)


if __name__ == "__main__":
    main()
