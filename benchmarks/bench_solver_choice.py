"""The constants of rvcoax.fem.solver_cost: PARDISO and AMG-CG measured on the solid cantilever.

The system is the clamped cantilever of bench_solid_scaling.py at three mesh sizes (h = 4.0, 2.8 and
2.1 mm: about 60 k, 160 k and 340 k DOF). Each (size, method) runs in a fresh Python process, so that
its peak memory (VmHWM) is its own:

- PARDISO (``rvcoax.fem.solvers.prepare(..., "pardiso")``): set-up (ordering, factorisation and the
  singularity check), the factor's memory as MKL reports it, one solve of 1 and of 20 right-hand
  sides (the difference / 19 is the cost of one substitution);
- AMG-CG (``prepare(..., "amg")`` with the rigid-body modes): set-up (the smoothed-aggregation
  hierarchy), CG iterations to the default stopping rule, seconds per iteration, the peak memory
  above the matrix; the iterations the energy-error rule alone would take (residual limit off) and the
  times of one product with A and of one V-cycle, both rvcoax's own (``rvcoax.fem.amg``, the cycle the
  solve uses; earlier versions timed pyamg's cycle here, which rvcoax no longer runs).

The script fits PARDISO's power laws in n (least squares in log–log) and AMG's per-nonzero costs
(mean over the sizes; iterations: the largest seen, rounded up to 5), prints them next to
``rvcoax.fem.solver_cost.COST_MODEL`` and the measured times next to the model's, and appends all
to benchmarks/RESULTS.md (``--no-record``: print only). Peak memory above 3 GB at 340 k DOF: run it
alone on a shared machine.

Run: ``.venv/bin/python benchmarks/bench_solver_choice.py [--sizes 4.0,2.8,2.1]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_solid_scaling import LENGTH_MM, POISSON, SEGMENTS, TIP_FORCE_N, YOUNGS_PA, peak_rss_mb  # noqa: E402
from machine import publish  # noqa: E402

SIZES_MM = (4.0, 2.8, 2.1)


def system(h: float, cache: str, poisson: float = POISSON):
    """Clamped cantilever at mesh size ``h`` mm: (reduced stiffness, tip load, rigid-body modes of the free DOFs)."""
    import numpy as np

    from rvcoax.fem import solid
    from rvcoax.fem.rigid_body import rigid_body_modes
    from rvcoax.geometry.meshing import SolidPartGeometry, mesh_part

    mesh = mesh_part(SolidPartGeometry(f"cantilever_{h}", SEGMENTS, (), h), cache_dir=Path(cache))
    basis = solid.solid_basis(mesh)
    stiffness = solid.stiffness_matrix(basis, YOUNGS_PA, poisson)
    coordinates, dofs = solid.dof_locations(basis)
    keep = np.ones(basis.N, dtype=bool)
    keep[dofs[np.abs(coordinates[:, 0]) < 1e-9].ravel()] = False
    free = np.flatnonzero(keep)
    tip = mesh.facets_satisfying(lambda x: np.isclose(x[0], LENGTH_MM * 1e-3, rtol=0.0, atol=1e-9))
    force = solid.force_traction_vector(mesh, tip, TIP_FORCE_N)[free]
    return stiffness[free][:, free].tocsr(), force, rigid_body_modes(basis.doflocs.T)[free]


def child(h: float, method: str, cache: str) -> dict:
    import numpy as np

    from rvcoax.fem import blas_threads, hugepages, solvers

    hugepages.avoid_compaction_stalls()
    blas_threads.single_threaded_openblas()
    a, force, modes = system(h, cache)
    import gc

    gc.collect()
    try:  # reset the high-water mark to the resident size now (Linux ≥ 4.0), so the peak below is the solver's
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        pass
    before = peak_rss_mb()
    out = {"h": h, "n": int(a.shape[0]), "nnz": int(a.nnz), "load": os.getloadavg()[0]}
    if method == "pardiso":
        start = time.perf_counter()
        solver = solvers.prepare(a, "pardiso")
        out["setup_s"] = time.perf_counter() - start
        out["factor_MB"] = solver.report.factor_memory_MB
        out["extra_MB"] = peak_rss_mb() - before
        many = np.repeat(force[:, None], 20, axis=1)
        times = []
        for block in (force, many):
            start = time.perf_counter()
            solver.solve(block)
            times.append(time.perf_counter() - start)
        out["solve1_s"], out["solve20_s"] = times
        out["substitution_s"] = (times[1] - times[0]) / 19
        solver.release()
    else:
        from rvcoax.fem import amg

        start = time.perf_counter()
        solver = solvers.prepare(a, "amg", near_null_space=modes)
        out["setup_s"] = time.perf_counter() - start
        solver.solve(force)
        out["iterations"] = solver.report.iterations[0]
        out["solve_s"] = solver.report.solve_seconds
        out["iteration_s"] = out["solve_s"] / out["iterations"]
        out["residual"] = solver.report.relative_residuals[0]
        out["estimate"] = solver.report.error_estimates[0]
        out["extra_MB"] = peak_rss_mb() - before  # hierarchy, CG vectors, the solver's residual check
        solver.release()
        # rvcoax's own V-cycle (fem/amg.py, what prepare(..., "amg") uses), timed alone and with the energy rule alone
        hierarchy = amg.smoothed_aggregation(a, modes)
        out["iterations_energy_rule_only"] = solvers.conjugate_gradients(hierarchy.matrix, force, hierarchy.precondition,
                                                                         residual_limit=math.inf)[1]
        start = time.perf_counter()
        for _ in range(5):
            hierarchy.matrix.matvec(force)
        out["matvec_s"] = (time.perf_counter() - start) / 5
        start = time.perf_counter()
        for _ in range(5):
            hierarchy.precondition(force)
        out["vcycle_s"] = (time.perf_counter() - start) / 5
        hierarchy.release()
    return out


def power_fit(xs, ys) -> tuple[float, float]:
    """y = c · (x / 1e5)^e, least squares in log–log: (c, e)."""
    lx = [math.log(x / 1e5) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    e = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
    return math.exp(my - e * mx), e


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default=",".join(str(h) for h in SIZES_MM), help="mesh sizes in mm")
    parser.add_argument("--no-record", action="store_true")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(float(args.child[0]), args.child[1], args.child[2])))
        return
    from rvcoax.fem.solver_cost import COST_MODEL

    load_before = os.getloadavg()[0]
    runs = {"pardiso": [], "amg": []}
    with tempfile.TemporaryDirectory() as cache:
        for h in (float(s) for s in args.sizes.split(",")):
            for method in runs:
                done = subprocess.run([sys.executable, __file__, "--child", str(h), method, cache],
                                      capture_output=True, text=True, check=True)
                runs[method].append(json.loads(done.stdout.strip().splitlines()[-1]))
                print(method, runs[method][-1], flush=True)
    rows = []
    for p, a in zip(runs["pardiso"], runs["amg"]):
        tag = f"h = {p['h']} mm ({p['n']:,} free DOF, {p['nnz']:,} nonzeros)"
        rows.append((f"{tag}: PARDISO", f"set-up {p['setup_s']:.2f} s (model {COST_MODEL.pardiso_seconds(p['n'], 0):.2f}), "
                                        f"factor {p['factor_MB']:.0f} MB, 1 solve {p['solve1_s']:.3f} s, 20 solves "
                                        f"{p['solve20_s']:.3f} s → {p['substitution_s'] * 1e3:.1f} ms per right-hand side"))
        rows.append((f"{tag}: AMG-CG", f"set-up {a['setup_s']:.2f} s, {a['iterations']} iterations × "
                                       f"{a['iteration_s']:.3f} s = {a['solve_s']:.2f} s (model total "
                                       f"{COST_MODEL.amg_seconds(a['nnz'], 1, a['n']):.2f} s, measured {a['setup_s'] + a['solve_s']:.2f} s); "
                                       f"residual {a['residual']:.1e}, error estimate {a['estimate']:.1e}; "
                                       f"{a['iterations_energy_rule_only']} iterations with the energy rule alone; "
                                       f"peak +{a['extra_MB']:.0f} MB above the matrix"))
        rows.append((f"{tag}: one AMG-CG iteration", f"matrix × vector {a['matvec_s'] * 1e3:.1f} ms (float64, MKL), "
                                                     f"rvcoax's V-cycle {a['vcycle_s'] * 1e3:.1f} ms "
                                                     f"({a['iteration_s'] / a['nnz']:.2e} s per nonzero and iteration "
                                                     f"in the solve)"))
    n = [p["n"] for p in runs["pardiso"]]
    if len(set(n)) < 2:
        for name, value in rows:
            print(f"{name}: {value}")
        return
    factor = power_fit(n, [p["setup_s"] for p in runs["pardiso"]])
    substitution = power_fit(n, [max(p["substitution_s"], 1e-6) for p in runs["pardiso"]])
    memory = power_fit(n, [p["factor_MB"] * 2**20 for p in runs["pardiso"]])
    setup = sum(a["setup_s"] / a["nnz"] for a in runs["amg"]) / len(runs["amg"])
    iteration = sum(a["iteration_s"] / a["nnz"] for a in runs["amg"]) / len(runs["amg"])
    iterations = 5 * math.ceil(max(a["iterations"] for a in runs["amg"]) / 5)
    memory_amg = max(a["extra_MB"] * 2**20 / a["nnz"] for a in runs["amg"])
    rows.append(("fitted (rvcoax.fem.solver_cost.COST_MODEL in brackets)",
                 f"factor_s {factor[0]:.2f} ({COST_MODEL.factor_s}), factor_exponent {factor[1]:.2f} "
                 f"({COST_MODEL.factor_exponent}); substitution_s {substitution[0]:.4f} ({COST_MODEL.substitution_s}), "
                 f"substitution_exponent {substitution[1]:.2f} ({COST_MODEL.substitution_exponent}); factor_bytes "
                 f"{memory[0]:.3g} ({COST_MODEL.factor_bytes:.3g}), factor_memory_exponent {memory[1]:.2f} "
                 f"({COST_MODEL.factor_memory_exponent}); amg_setup_s_per_nnz {setup:.2e} ({COST_MODEL.amg_setup_s_per_nnz:.2e}), "
                 f"amg_iteration_s_per_nnz {iteration:.2e} ({COST_MODEL.amg_iteration_s_per_nnz:.2e}), amg_iterations "
                 f"{iterations} ({COST_MODEL.amg_iterations:g}), amg_bytes_per_nnz {memory_amg:.0f} ({COST_MODEL.amg_bytes_per_nnz:g})"))
    publish("bench_solver_choice.py: PARDISO and AMG-CG costs behind rvcoax.fem.solver_cost", rows, load_before,
            keep=not args.no_record)


if __name__ == "__main__":
    main()
