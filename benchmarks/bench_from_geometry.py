"""Issue 16: the cost of a housing condensation, and the reference rig read from geometry against paper 000.

1. The reference rig's input bearing block (HT200, 90 × 145 × 72 mm, bore Ø47, foot plate; two bearing
   seats tied to bore bands, feet clamped) condensed at mesh sizes 16 … 6 mm, cache off: solid DOFs,
   meshing + assembly + condensation time, and the block's vertical stiffness at the first seat
   (K_c[1, 1], N/µm: mesh convergence).
2. Mesh convergence of the other shapes (issue 16 item 2): the reference rig's input bearing block as a web
   pedestal (``BEARING_PEDESTALS[0]``, bolt feet clamped) and a wall bracket (the test bracket of
   tests/geometry/test_housing_shapes.py on a Winkler bed) at 16 … 5 mm: the vertical and lateral stiffness at the
   first seat, the observed order p from the three finest meshes (K_h ≈ K_∞ + C h^p, non-uniform ratios solved
   for p) and the Richardson-extrapolated K_∞ with each mesh's distance from it.
3. Blind Y/β of the beam model on paper 000's 20 load cases for the typed-in reference rig and for the
   readings from geometry (gear data; condensed blocks; both; with temperatures): median and largest
   relative error of Y_input, Y_output, β_input, β_output against the published table. Nothing is fitted.

Run: ``.venv/bin/python benchmarks/bench_from_geometry.py [--part condensation|shapes|blind]`` (all three by
default). Prints the figures and appends them to
benchmarks/RESULTS.md with the machine, date and load.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
from machine import record  # noqa: E402

from rvcoax.geometry.model.housings import condensed_housing  # noqa: E402
from rvcoax.geometry.rigfile import load_rig  # noqa: E402
from rvcoax.geometry.variants import reference_from_geometry  # noqa: E402
from rvcoax.loadcases.cases import paper_table  # noqa: E402
from rvcoax.results.sweep import run_sweep  # noqa: E402

READINGS = {
    "typed-in (reference)": None,
    "gear data": ("gears",),
    "condensed blocks": ("housings",),
    "gear data + blocks": ("gears", "housings"),
    "all from geometry (+ temperatures)": ("gears", "housings", "thermal"),
    "condensed pedestals": ("pedestals",),
    "gear data + pedestals": ("gears", "pedestals"),
    "all from geometry, blocks as pedestals (+ temperatures)": ("gears", "pedestals", "thermal"),
}


def condensation_costs(rows: list) -> None:
    rig = reference_from_geometry(("housings",))
    block = rig.housings[0]
    for size in (16.0, 12.0, 8.0, 6.0):  # 4 mm: 319 k DOFs, 400 s and 4.8 GB here (too much for a shared machine)
        sized = block.model_copy(update={"mesh_size_mm": size})
        with tempfile.TemporaryDirectory() as cache:
            start = time.perf_counter()
            result = condensed_housing(rig, sized, cache_dir=Path(cache))
            seconds = time.perf_counter() - start
        line = (f"{result.solid_dofs} solid DOFs, {seconds:.2f} s (mesh + assembly + condensation), "
                f"K_yy at the first seat {result.matrix[1, 1] / 1e6:.1f} N/µm, K_yy between the two seats {result.matrix[1, 7] / 1e6:.1f} N/µm")
        print(f"input block, mesh {size:g} mm: {line}")
        rows.append((f"input block condensation, mesh {size:g} mm", line))


def observed_order(sizes, values) -> tuple[float, float]:
    """p and K_∞ of K_h = K_∞ + C h^p through the three (h, K) given (coarse to fine; any size ratios)."""
    (h1, h2, h3), (k1, k2, k3) = sizes, values
    ratio = (k1 - k2) / (k2 - k3)
    low, high = 0.05, 8.0
    for _ in range(200):  # (h1^p − h2^p)/(h2^p − h3^p) grows with p: bisection
        p = 0.5 * (low + high)
        if (h1**p - h2**p) / (h2**p - h3**p) < ratio:
            low = p
        else:
            high = p
    limit = k3 - (k2 - k3) * h3**p / (h2**p - h3**p)
    return p, limit


def shape_convergence(rows: list) -> None:
    from rvcoax.geometry.housings import BracketGeometry, Reference
    from rvcoax.geometry.model.condensed_housing import condense_housing

    def bracket(size: float) -> BracketGeometry:  # as in tests/geometry/test_housing_shapes.py
        return BracketGeometry(name="bracket", x_mm=(0.0, 60.0), width_mm=70.0, top_mm=35.0, seat_bottom_mm=-35.0,
                               bore_diameter_mm=35.0, split_x_mm=(12.0, 48.0), mesh_size_mm=size, wall_z_mm=-110.0,
                               arm_length_mm=60.0, arm_height_mm=40.0, plate_length_mm=100.0, plate_height_mm=110.0,
                               plate_thickness_mm=12.0, foot_pad_mm=25.0)

    seats = [Reference((6.0, 0.0, 0.0), ("bore", 0.0, 12.0)), Reference((54.0, 0.0, 0.0), ("bore", 48.0, 60.0))]

    rig = reference_from_geometry(("pedestals",))
    pedestal = rig.housings[0]
    material = rig.materials[pedestal.material]
    sizes = (16.0, 12.0, 8.0, 6.0, 5.0)
    for label, condense in (
            ("reference input pedestal (clamped bolt feet)",
             lambda size, cache: condensed_housing(rig, pedestal.model_copy(update={"mesh_size_mm": size}), cache)),
            ("wall bracket of the tests (Winkler bed 0.5 / 0.2 N/(µm·mm²))",
             lambda size, cache: condense_housing(bracket(size), material.youngs_modulus_MPa * 1e6,
                                                  material.poisson_ratio, seats, "bed", bed_stiffness_N_per_um_per_mm2=(0.5, 0.2), cache_dir=cache))):
        stiffness = []
        for size in sizes:
            with tempfile.TemporaryDirectory() as cache:
                start = time.perf_counter()
                result = condense(size, Path(cache))
                seconds = time.perf_counter() - start
            stiffness.append(np.diag(result.matrix)[:3] / 1e6)
            line = (f"{result.solid_dofs} solid DOFs, {seconds:.2f} s; K_xx, K_yy, K_zz at the first seat "
                    + ", ".join(f"{k:.1f}" for k in stiffness[-1]) + " N/µm")
            print(f"{label}, mesh {size:g} mm: {line}")
            rows.append((f"{label}, mesh {size:g} mm", line))
        stiffness = np.array(stiffness)
        parts = []
        for axis, name in ((1, "K_yy"), (2, "K_zz")):
            p, limit = observed_order(sizes[-3:], stiffness[-3:, axis])
            distance = ", ".join(f"{size:g} mm {100 * (k / limit - 1):+.1f} %" for size, k in zip(sizes, stiffness[:, axis]))
            parts.append(f"{name}: order p = {p:.2f}, extrapolated {limit:.1f} N/µm; {distance}")
        line = "; ".join(parts)
        print(f"{label}, convergence: {line}")
        rows.append((f"{label}, convergence (Richardson on 8/6/5 mm)", line))


def blind_errors(rows: list) -> None:
    table = paper_table()
    cases = tuple(r.case for r in table)
    published = {"Y_input": np.array([r.y_input_mm for r in table]), "Y_output": np.array([r.y_output_mm for r in table]),
                 "beta_input": np.array([r.beta_input_deg for r in table]),
                 "beta_output": np.array([r.beta_output_deg for r in table])}
    for label, readings in READINGS.items():
        rig = load_rig() if readings is None else reference_from_geometry(readings)
        sweep = run_sweep(rig, cases)
        model = {}
        for which in ("input", "output"):
            paths = [c.paths[which] for c in sweep.cases]
            y = np.array([p.y_max_mm for p in paths])
            model[f"Y_{which}"] = y
            model[f"beta_{which}"] = np.degrees(np.arcsin(y / np.array([p.length_mm for p in paths])))
        parts = []
        for key, values in published.items():
            error = np.abs(model[key] - values) / np.abs(values)
            parts.append(f"{key} {100 * np.median(error):.1f} / {100 * error.max():.1f} %")
        line = ", ".join(parts) + f"; Y_output at 200 N·m {1e3 * model['Y_output'][0]:.3f} µm"
        print(f"{label}: {line}")
        rows.append((f"blind relative error (median / max), {label}", line))


PARTS = {"condensation": condensation_costs, "shapes": shape_convergence, "blind": blind_errors}


def main() -> None:
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=sorted(PARTS), action="append", help="run only this part (repeatable)")
    chosen = parser.parse_args().part or list(PARTS)
    rows: list = []
    load = os.getloadavg()
    for name in chosen:
        PARTS[name](rows)
    rows.append(("load average at start / end (1, 5, 15 min)",
                 " / ".join(", ".join(f"{v:.2f}" for v in values) for values in (load, os.getloadavg()))))
    record(f"bench_from_geometry.py ({', '.join(chosen)}): housing condensation and the reference rig from geometry",
           rows)


if __name__ == "__main__":
    main()
