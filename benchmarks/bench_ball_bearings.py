"""Ball bearings from geometry on the reference rig: cost of the nonlinear sweep, robustness, and Y/β blind.

Times the 20-case paper sweep with the typed-in (linear) bearings and with the ball-bearing variant
(6204 input, 6206 output, solved by Newton on the condensed bearing motions, one factorisation);
scans clearance and preload for convergence; and compares both readings, blind, with paper 000's
table (mean |relative error| per quantity, as ``rvcoax check`` computes it). Prints the figures and
appends them to benchmarks/RESULTS.md with the machine, date and load average.

Run: ``.venv/bin/python benchmarks/bench_ball_bearings.py``
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
from machine import record  # noqa: E402

from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text  # noqa: E402
from rvcoax.loadcases.cases import paper_table  # noqa: E402
from rvcoax.results.studies.check import CHECK_QUANTITIES as QUANTITIES  # noqa: E402
from rvcoax.results.studies.check import compare  # noqa: E402
from rvcoax.results.sweep import run_sweep  # noqa: E402

REPEATS = 5
SHAFT_BEARINGS = ("input_B1", "input_B2", "output_B1", "output_B2")


def _timed(function, repeats: int = REPEATS):
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), statistics.median(times), result


def variant_text(clearance_um: float | None = None, preload_N: float = 0.0) -> str:
    """The ball-bearing variant with every shaft bearing at ``clearance_um`` (None: CN) and ``preload_N``."""
    text = reference_rig_text("ball_bearings")
    extra = ("" if clearance_um is None else f"\nclearance_um = {clearance_um}") + (
        f"\npreload_N = {preload_N}" if preload_N else "")
    return text.replace('clearance_class = "CN"', f'clearance_class = "CN"{extra}')


def readings() -> dict[str, str]:
    return {
        "typed-in linear bearings (reference rig)": reference_rig_text(),
        "ball bearings, CN clearance (12.5 µm)": variant_text(),
        "ball bearings, zero operating clearance": variant_text(0.0),
        "ball bearings, zero clearance, 50 N preload": variant_text(0.0, 50.0),
    }


def main() -> None:
    rows_paper = paper_table()
    cases = tuple(r.case for r in rows_paper)
    load_before = os.getloadavg()[0]
    figures: list[tuple[str, str]] = []
    sweeps = {}
    for label, text in readings().items():
        rig = parse_rig_text(text, label)
        best, median, sweep = _timed(lambda rig=rig: run_sweep(rig, cases))
        sweeps[label] = sweep
        newton = sweep.solver_report.get("newton_iterations_max")
        figures.append((f"sweep, 20 paper cases + rest: {label}",
                        f"{median:.3f} s median, {best:.3f} s best of {REPEATS}"
                        + (f"; Newton iterations ≤ {newton} per case" if newton is not None else "")))
    # robustness: every clearance class edge and preload converges
    start = time.perf_counter()
    solved = 0
    for clearance in (0.0, 2.0, 5.0, 12.5, 20.0, 28.0, 36.0):
        for preload in (0.0, 10.0, 100.0):
            run_sweep(parse_rig_text(variant_text(clearance, preload), "scan"), cases)
            solved += 1
    figures.append(("scan: clearance 0 … 36 µm × preload 0/10/100 N, 20 cases each",
                    f"{solved} sweeps, all converged, {time.perf_counter() - start:.1f} s"))
    # operating stiffness at rest and at the largest case
    points = sweeps["ball bearings, CN clearance (12.5 µm)"].solver_report["ball_bearing_operating_points"]
    for name in SHAFT_BEARINGS:
        rest, top = points[name][0], points[name][1]
        figures.append((f"CN operating point {name}: at rest / T1 = 1.43, T2 = 200 N·m",
                        f"{rest['radial_force_N']:.2f} N, k_y {rest['radial_stiffness_y_N_per_um']:.1f} N/µm, "
                        f"{rest['loaded_balls']} balls / {top['radial_force_N']:.2f} N, "
                        f"k_y {top['radial_stiffness_y_N_per_um']:.1f} N/µm, {top['loaded_balls']} balls"))
    # Y and β blind against paper 000
    print("\nY and β blind against paper 000 (mean |relative error| over the 20 rows):")
    for label, sweep in sweeps.items():
        comparison = compare(rows_paper, sweep)
        errors = {q: 100 * float(np.mean(np.abs(comparison.relative_error[q]))) for q in QUANTITIES}
        top = {q: float(comparison.model[q][0]) for q in QUANTITIES}
        figures.append((f"blind vs paper 000, {label}: mean abs. relative error Y_in / Y_out / β_in / β_out",
                        " / ".join(f"{errors[q]:.0f} %" for q in QUANTITIES)))
        figures.append((f"{label}: row T1 = 1.43, T2 = 200 N·m: Y_in, Y_out (µm); β_in, β_out (µrad)",
                        f"{top['Y_input_mm'] * 1e3:.3f}, {top['Y_output_mm'] * 1e3:.3f}; "
                        f"{np.radians(top['beta_input_deg']) * 1e6:.3f}, {np.radians(top['beta_output_deg']) * 1e6:.3f}"))
    published = compare(rows_paper, sweeps["typed-in linear bearings (reference rig)"]).published
    figures.append(("paper 000, row T1 = 1.43, T2 = 200 N·m: Y_in, Y_out (µm); β_in, β_out (µrad)",
                    f"{published['Y_input_mm'][0] * 1e3:.3f}, {published['Y_output_mm'][0] * 1e3:.3f}; "
                    f"{np.radians(published['beta_input_deg'][0]) * 1e6:.3f}, "
                    f"{np.radians(published['beta_output_deg'][0]) * 1e6:.3f}"))
    figures.append(("load average (1 min) before / after", f"{load_before:.2f} / {os.getloadavg()[0]:.2f}"))
    for name, value in figures:
        print(f"{name}: {value}")
    record("bench_ball_bearings.py: nonlinear ball-bearing sweep on the reference rig, Y/β blind", figures)


if __name__ == "__main__":
    main()
