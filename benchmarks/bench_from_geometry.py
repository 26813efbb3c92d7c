"""Issue 16: the cost of a housing condensation, and the reference rig read from geometry against paper 000.

1. The reference rig's input bearing block (HT200, 90 × 145 × 72 mm, bore Ø47, foot plate; two bearing
   seats tied to bore bands, feet clamped) condensed at mesh sizes 16 … 6 mm, cache off: solid DOFs,
   meshing + assembly + condensation time, and the block's vertical stiffness at the first seat
   (K_c[1, 1], N/µm: mesh convergence).
2. Blind Y/β of the beam model on paper 000's 20 load cases for the typed-in reference rig and for the
   readings from geometry (gear data; condensed blocks; both; with temperatures): median and largest
   relative error of Y_input, Y_output, β_input, β_output against the published table. Nothing is fitted.

Run: ``.venv/bin/python benchmarks/bench_from_geometry.py``. Prints the figures and appends them to
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


def main() -> None:
    rows: list = []
    load = os.getloadavg()
    condensation_costs(rows)
    blind_errors(rows)
    rows.append(("load average at start (1, 5, 15 min)", ", ".join(f"{v:.2f}" for v in load)))
    record("bench_from_geometry.py: housing condensation and the reference rig from geometry", rows)


if __name__ == "__main__":
    main()
