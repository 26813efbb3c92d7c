"""MKL PARDISO against MUMPS and CHOLMOD on the same matrices: analysis, factorisation, solves, memory.

Run: ``.venv/bin/python benchmarks/bench_direct_solvers.py [--h 4.0] [--other-python PATH] [--no-record]``.

``--variants``: instead, PARDISO's settings on the cantilever alone (:data:`VARIANTS`: orderings, scalar against
3 × 3-block storage, the parallel factorisation algorithms, a single-precision factor refined in double
precision against the matrix), each in a fresh process, and the set-up as :func:`rvcoax.fem.solvers.prepare`
runs it split into its parts (checks and upper storage, analysis, factorisation, singularity test, condition
estimate).

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


VARIANTS = {  # name: (iparm entries set on top of rvcoax's, storage, single precision)
    "rvcoax's settings (METIS nested dissection, OpenMP; 3 × 3 blocks)": ({}, "blocks", False),
    "METIS, serial (iparm[1] = 2)": ({1: 2}, "blocks", False),
    "minimum degree (iparm[1] = 0)": ({1: 0}, "blocks", False),
    "scalar CSR storage": ({}, "scalar", False),
    "two-level parallel factorisation (iparm[23] = 1)": ({23: 1}, "blocks", False),
    "parallel forward/backward solve (iparm[24] = 1)": ({24: 1}, "blocks", False),
    "single-precision factor (iparm[27] = 1), refined in double": ({27: 1}, "blocks", True),
}
REFINEMENT_STEPS = 8


def variant_child(matrix_file: str, rhs_file: str, name: str) -> dict:
    """One PARDISO setting on the SPD matrix: each phase's CPU and wall time, factor size, residual."""
    import dataclasses

    import numpy as np
    import scipy.sparse as sp

    from rvcoax.fem import pardiso

    sets, kind, single = VARIANTS[name]
    a = sp.load_npz(matrix_file).tocsr()
    b = np.load(rhs_file).reshape(a.shape[0], -1)[:, :1]
    storage = pardiso.upper_storage(a) if kind == "blocks" else pardiso.upper_csr(a)
    dtype = np.float32 if single else float
    storage = dataclasses.replace(storage, data=storage.data.astype(dtype))
    handle, iparm = np.zeros(64, dtype=np.int64), np.zeros(64, dtype=np.int32)
    iparm[[0, 1, 9, 17, 18, 34]] = [1, 3, 8, -1, -1, 1]  # as rvcoax.fem.pardiso.Factorization (with the flop count)
    iparm[36] = storage.block_size if storage.block_size > 1 else 0
    for key, value in sets.items():
        iparm[key] = value
    out, errors = {}, []

    def phase(number, rhs):
        start = time.process_time(), time.perf_counter()
        x, error = pardiso._phase(handle, iparm, 2, number, storage, rhs=np.asfortranarray(rhs, dtype=dtype))
        errors.append(error)
        return x.astype(float), (time.process_time() - start[0], time.perf_counter() - start[1])

    _, out["analysis"] = phase(11, np.zeros((a.shape[0], 1)))
    _, out["factorisation"] = phase(22, np.zeros((a.shape[0], 1)))
    x, out["solve"] = phase(33, b)
    residuals = [float(np.linalg.norm(b - a @ x) / np.linalg.norm(b))]
    if single:  # x += A_single⁻¹ (b − A x), the residual in double precision
        for _ in range(REFINEMENT_STEPS):
            x += phase(33, b - a @ x)[0]
            residuals.append(float(np.linalg.norm(b - a @ x) / np.linalg.norm(b)))
    np.save(matrix_file + f".variant{list(VARIANTS).index(name)}.npy", x)
    found = {**out, "errors": errors, "gflop": int(iparm[18]) / 1e3, "factor_nonzeros": int(iparm[17]),
             "memory_MB": (int(iparm[15]) + int(iparm[16])) / 1024, "residuals": residuals}
    phase(-1, np.zeros((a.shape[0], 1)))
    return found


def setup_parts_child(matrix_file: str) -> dict:
    """:func:`rvcoax.fem.solvers.prepare`'s PARDISO set-up, with and without the condition estimate, by parts."""
    import scipy.sparse as sp

    from rvcoax.fem import diagnostics, pardiso, solvers

    pardiso.set_analysis_reuse(False)
    a = sp.load_npz(matrix_file).tocsr()
    parts: dict[str, list[float]] = {}
    clocks = {}

    def timed(module, name, label):
        original = getattr(module, name)

        def wrapper(*args, **kwargs):
            start = time.process_time(), time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                spent = parts.setdefault(label, [0.0, 0.0])
                spent[0] += time.process_time() - start[0]
                spent[1] += time.perf_counter() - start[1]
        clocks[label] = wrapper
        setattr(module, name, wrapper)

    original_phase = pardiso._phase

    def phase(handle, iparm, mtype, number, storage, *, rhs):
        label = {11: "analysis", 22: "factorisation", 33: "solves"}.get(number, "release")
        start = time.process_time(), time.perf_counter()
        try:
            return original_phase(handle, iparm, mtype, number, storage, rhs=rhs)
        finally:
            spent = parts.setdefault(label, [0.0, 0.0])
            spent[0] += time.process_time() - start[0]
            spent[1] += time.perf_counter() - start[1]

    pardiso._phase = phase
    timed(pardiso, "upper_storage", "upper storage")
    timed(solvers, "singularity_and_condition", "singularity test + condition estimate")
    timed(solvers, "scaled_inverse_norm_bound", "singularity test")
    timed(diagnostics, "_scaled_one_norm", "scaled one-norm")
    out = {}
    for eager in (True, False):
        parts.clear()
        start = time.process_time(), time.perf_counter()
        solver = solvers.prepare(a, "pardiso", estimate_condition=eager)
        total = (time.process_time() - start[0], time.perf_counter() - start[1])
        solver.release()
        out["with" if eager else "without"] = {"total": total, **{k: tuple(v) for k, v in parts.items()}}
    return out


def variant_rows(folder: Path, h: float) -> list[tuple[str, str]]:
    import numpy as np
    from bench_symbolic_reuse import cantilever

    k, force = cantilever(h, 0.3, str(folder))
    import scipy.sparse as sp

    matrix, rhs = str(folder / "cantilever.npz"), str(folder / "cantilever_rhs.npy")
    sp.save_npz(matrix, k)
    np.save(rhs, force)
    tag = f"cantilever ({k.shape[0]:,} DOF, SPD)"
    rows, reference = [], None
    for index, name in enumerate(VARIANTS):
        found = run_child([sys.executable, __file__, "--variant-child", matrix, rhs, name])
        if isinstance(found, str):
            rows.append((f"{tag}: {name}", f"failed: {found}"))
            continue
        x = np.load(matrix + f".variant{index}.npy")
        reference = x if reference is None else reference
        difference = float(np.abs(x - reference).max() / np.abs(reference).max())
        residuals = found["residuals"]
        refined = (f"; residual after {len(residuals) - 1} double-precision refinement steps "
                   f"{' → '.join(f'{r:.0e}' for r in residuals)}" if len(residuals) > 1 else "")
        rows.append((f"{tag}: {name}", "analysis {:.3f} s CPU ({:.3f} s wall), factorisation {:.3f} s CPU ({:.3f} s), "
                     "solve {:.3f} s CPU ({:.3f} s)".format(*found["analysis"], *found["factorisation"], *found["solve"])
                     + f"; factor {found['factor_nonzeros'] / 1e6:.1f} M nonzeros (blocks or scalars as stored), "
                       f"{found['gflop']:.1f} GFLOP as MKL reports it, MKL memory {found['memory_MB']:.0f} MB; "
                       f"errors {found['errors']}; residual {residuals[-1]:.1e}{refined}; vs the first row "
                       f"{difference:.1e}"))
        print(rows[-1], flush=True)
    found = run_child([sys.executable, __file__, "--setup-parts-child", matrix])
    for which in ("with", "without"):
        if isinstance(found, str):
            rows.append((f"{tag}: prepare(), set-up by parts", f"failed: {found}"))
            break
        parts = found[which]
        text = ", ".join(f"{k} {v[0]:.3f} s CPU ({v[1]:.3f} s)" for k, v in parts.items() if k != "total")
        rows.append((f"{tag}: prepare(\"pardiso\", estimate_condition={which == 'with'}), set-up by parts",
                     "total {:.3f} s CPU ({:.3f} s wall); parts, nested (the tests hold solves and the one-norm): "
                     .format(*parts["total"]) + text))
        print(rows[-1], flush=True)
    return rows


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
    parser.add_argument("--variants", action="store_true",
                        help="PARDISO's settings and the set-up's parts on the cantilever instead (no MUMPS/CHOLMOD)")
    parser.add_argument("--pardiso-child", nargs=3, help=argparse.SUPPRESS)
    parser.add_argument("--variant-child", nargs=3, help=argparse.SUPPRESS)
    parser.add_argument("--setup-parts-child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.variant_child:
        print(json.dumps(variant_child(*args.variant_child)))
        return
    if args.setup_parts_child:
        print(json.dumps(setup_parts_child(args.setup_parts_child)))
        return
    if args.variants:
        from machine import publish

        load_before = os.getloadavg()[0]
        with tempfile.TemporaryDirectory() as temporary:
            rows = variant_rows(Path(temporary), args.h)
        publish("bench_direct_solvers.py --variants: PARDISO's settings and set-up parts, solid cantilever",
                [("timer", "CPU = time.process_time() of the child process (MKL on 2 threads); wall beside it"),
                 *rows], load_before, keep=not args.no_record)
        return
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
