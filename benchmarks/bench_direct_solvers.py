"""MKL PARDISO against MUMPS and CHOLMOD on the same matrices: analysis, factorisation, solves, memory.

Run: ``.venv/bin/python benchmarks/bench_direct_solvers.py [--h 4.0] [--other-python PATH] [--no-record]``.

Matrices (written once to a temporary folder, then each (matrix, solver) runs in a fresh process so that its
peak resident memory is its own):

- **hybrid**: the reference rig's hybrid model as rvcoax factorises it, the saddle-point matrix of the
  distributing ties (symmetric indefinite; its right-hand sides are the rig's unit loads);
- **cantilever**: the clamped solid cantilever of bench_solid_scaling.py at ``--h`` mm (SPD; tip load).

Solvers: PARDISO through :mod:`rvcoax.fem.pardiso` (this interpreter; indefinite mode with matching, scaling and
MKL's refinement for the hybrid matrix, SPD in 3 × 3 blocks for the cantilever), MUMPS (``python-mumps``,
symmetric mode, METIS ordering) and CHOLMOD (``scikit-sparse``, supernodal Cholesky, SPD matrices only), the last
two in ``--other-python``, an interpreter that has them (neither installs into rvcoax's environment: the only
python-mumps wheel on PyPI for this platform, 0.0.2, is built against numpy 1.x, and scikit-sparse is a source
package that needs SuiteSparse's headers, ``libsuitesparse-dev``). Each row: analysis, factorisation, one solve
and all right-hand sides, CPU time of the process (``time.process_time``: PARDISO runs on 2 threads, the
MUMPS and CHOLMOD builds on 1) beside wall time, the factor's nonzeros, the process's peak memory, the
relative residual, and the largest difference from PARDISO's solution.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

CHILD = r'''
import json, resource, sys, time
import numpy as np, scipy.sparse as sp
solver, matrix_file, rhs_file, symmetric_upper = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] == "upper"
a = sp.load_npz(matrix_file).tocsr()
rhs = np.load(rhs_file).reshape(a.shape[0], -1)
full = (a + sp.triu(a, 1).T).tocsr() if symmetric_upper else a
upper = sp.triu(a, format="coo")
clock = lambda: (time.process_time(), time.perf_counter())
out = {}
c0 = clock()
if solver == "mumps":
    import mumps
    ctx = mumps.Context()
    ctx.set_matrix(upper, symmetric=True)
    ctx.analyze(ordering="metis")
    c1 = clock()
    ctx.factor(reuse_analysis=True)
    c2 = clock()
    solve = ctx.solve
    import re
    found = re.search(r"nonzeros in factored matrix: *([0-9]+)", str(ctx.factor_stats))
    out["factor_nonzeros"] = int(found.group(1)) if found else None
elif solver == "cholmod":
    from sksparse.cholmod import analyze
    factor = analyze(full.tocsc(), mode="supernodal", ordering_method="metis")
    c1 = clock()
    factor.cholesky_inplace(full.tocsc())
    c2 = clock()
    solve = factor
    out["factor_nonzeros"] = int(factor.L().nnz)
c3a = clock()
x1 = solve(rhs[:, :1])
c3 = clock()
x = solve(rhs)
c4 = clock()
scale = np.linalg.norm(rhs, axis=0)
residual = np.linalg.norm(full @ x - rhs, axis=0) / np.where(scale > 0, scale, 1.0)
np.save(matrix_file + f".{solver}.npy", x)
out.update(analysis_cpu=c1[0] - c0[0], analysis_wall=c1[1] - c0[1], factor_cpu=c2[0] - c1[0], factor_wall=c2[1] - c1[1],
           solve1_cpu=c3[0] - c3a[0], solves_cpu=c4[0] - c3[0], solves_wall=c4[1] - c3[1], n_rhs=rhs.shape[1],
           residual=float(residual.max()), peak_MB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
print(json.dumps(out))
'''


def pardiso_child(matrix_file: str, rhs_file: str, indefinite: bool) -> dict:
    import resource

    import numpy as np
    import scipy.sparse as sp

    from rvcoax.fem import pardiso

    pardiso.set_analysis_reuse(False)
    a = sp.load_npz(matrix_file).tocsr()
    rhs = np.load(rhs_file).reshape(a.shape[0], -1)
    if indefinite:
        storage = pardiso.UpperStorage(a.shape[0], 1, a.indptr.astype(np.int32), a.indices.astype(np.int32), a.data)
        full = (a + sp.triu(a, 1).T).tocsr()
    else:
        storage, full = pardiso.upper_storage(a), a
    walls = {}
    original = pardiso._phase

    def timed(handle, iparm, mtype, phase, storage, rhs):  # CPU and wall of each PARDISO phase
        start = time.process_time(), time.perf_counter()
        try:
            return original(handle, iparm, mtype, phase, storage, rhs)
        finally:
            walls.setdefault(phase, (time.process_time() - start[0], time.perf_counter() - start[1]))

    pardiso._phase = timed
    factor = pardiso.Factorization(storage, indefinite=indefinite)
    c2 = time.process_time(), time.perf_counter()
    factor.solve(rhs[:, :1])
    c3 = time.process_time(), time.perf_counter()
    x = factor.solve(rhs)
    c4 = time.process_time(), time.perf_counter()
    scale = np.linalg.norm(rhs, axis=0)
    residual = np.linalg.norm(full @ x - rhs, axis=0) / np.where(scale > 0, scale, 1.0)
    np.save(matrix_file + ".pardiso.npy", x)
    return {"analysis_cpu": walls[11][0], "analysis_wall": walls[11][1], "factor_cpu": walls[22][0],
            "factor_wall": walls[22][1], "solve1_cpu": c3[0] - c2[0], "solves_cpu": c4[0] - c3[0],
            "solves_wall": c4[1] - c3[1], "n_rhs": rhs.shape[1], "residual": float(residual.max()),
            "factor_nonzeros": factor.factor_nonzeros, "perturbed_pivots": factor.perturbed_pivots,
            "peak_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def write_matrices(folder: Path, h: float) -> dict:
    import numpy as np
    import scipy.sparse as sp
    from bench_symbolic_reuse import cantilever

    from rvcoax.fem import system as fem_system
    from rvcoax.geometry.model.assemble import assemble_rig
    from rvcoax.geometry.model.loads import UNIT_LOADS
    from rvcoax.geometry.rigfile import load_rig

    rig_system = assemble_rig(load_rig(), "hybrid")
    operator = fem_system.constrained_stiffness(rig_system.stiffness, rig_system.elimination,
                                                fem_system.long_rows(rig_system.elimination))
    upper = operator.saddle_point_upper()
    loads = rig_system.elimination.T @ np.column_stack([rig_system.unit_loads[k] for k in UNIT_LOADS])
    loads = loads[:, np.linalg.norm(loads, axis=0) > 0]
    rhs = np.zeros((upper.n, loads.shape[1]))
    rhs[: operator.shape[0]] = loads
    sp.save_npz(folder / "hybrid.npz", sp.csr_matrix((upper.data, upper.indices, upper.indptr), shape=(upper.n,) * 2))
    np.save(folder / "hybrid_rhs.npy", rhs)
    k, force = cantilever(h, 0.3, str(folder))
    sp.save_npz(folder / "cantilever.npz", k)
    np.save(folder / "cantilever_rhs.npy", force)
    return {"hybrid": (upper.n, int(upper.indices.size), True),
            "cantilever": (k.shape[0], int(k.nnz), False)}


def run_child(command: list[str]) -> dict | str:
    done = subprocess.run(command, capture_output=True, text=True, timeout=900)
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode or not lines:
        return (done.stderr.strip().splitlines() or ["no output"])[-1]
    return json.loads(lines[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h", type=float, default=4.0, help="cantilever mesh size, mm (4.0: about 61 k DOF)")
    parser.add_argument("--other-python", default=None, help="interpreter with python-mumps and/or scikit-sparse")
    parser.add_argument("--no-record", action="store_true")
    parser.add_argument("--pardiso-child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.pardiso_child:
        print(json.dumps(pardiso_child(args.pardiso_child[0], args.pardiso_child[1], args.pardiso_child[2] == "upper")))
        return
    import numpy as np
    from machine import publish

    load_before = os.getloadavg()[0]
    rows = [("timer", "CPU = time.process_time() of the solver's own process; wall beside it (shared machine)")]
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        sizes = write_matrices(folder, args.h)
        for name, (n, nnz, indefinite) in sizes.items():
            matrix, rhs = str(folder / f"{name}.npz"), str(folder / f"{name}_rhs.npy")
            kind = "upper" if indefinite else "full"
            solvers = [("pardiso", [sys.executable, __file__, "--pardiso-child", matrix, rhs, kind])]
            if args.other_python:
                solvers.append(("mumps", [args.other_python, "-c", CHILD, "mumps", matrix, rhs, kind]))
                if not indefinite:
                    solvers.append(("cholmod", [args.other_python, "-c", CHILD, "cholmod", matrix, rhs, kind]))
            reference = None
            for solver, command in solvers:
                found = run_child(command)
                label = (f"{name} ({n:,} unknowns, {nnz:,} stored nonzeros, "
                         f"{'symmetric indefinite' if indefinite else 'SPD'}): {solver}")
                if isinstance(found, str):
                    rows.append((label, f"failed: {found}"))
                    print(rows[-1])
                    continue
                x = np.load(matrix + f".{solver}.npy")
                reference = x if reference is None else reference
                difference = float(np.abs(x - reference).max() / np.abs(reference).max())
                extra = f", {found['perturbed_pivots']} perturbed pivots" if "perturbed_pivots" in found else ""
                rows.append((label, f"analysis {found['analysis_cpu']:.2f} s CPU ({found['analysis_wall']:.2f} s wall), "
                                    f"factorisation {found['factor_cpu']:.2f} s CPU ({found['factor_wall']:.2f} s), "
                                    f"1 solve {found['solve1_cpu']:.3f} s CPU, {found['n_rhs']} solves "
                                    f"{found['solves_cpu']:.3f} s CPU ({found['solves_wall']:.3f} s); factor "
                                    f"{(found.get('factor_nonzeros') or 0) / 1e6:.1f} M nonzeros{extra}; peak "
                                    f"{found['peak_MB']:.0f} MB; residual {found['residual']:.1e}; "
                                    f"vs PARDISO {difference:.1e}"))
                print(rows[-1])
    publish("bench_direct_solvers.py: PARDISO, MUMPS and CHOLMOD on the same matrices", rows, load_before,
            keep=not args.no_record)


if __name__ == "__main__":
    main()
