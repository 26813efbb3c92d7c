"""Distributing ties with and without fill-in: the reduced matrix, its factor, time and memory.

For a rig model (default: the reference rig's hybrid model at its 4 mm mesh, and its all-solid model at a
coarse mesh), the same assembled system is solved twice, each in a fresh process:

- ``eliminated``: Tᵀ K T formed (every distributing tie's reference DOFs eliminated: a dense block per
  tied face) and factorised by PARDISO in SPD mode, as before issue 17;
- ``multipliers``: :func:`rvcoax.fem.system.prepare_system`, which keeps the tie reference DOFs as
  unknowns and imposes their relation by Lagrange multipliers (symmetric indefinite PARDISO).

Each reports the unknowns, the stored nonzeros of the matrix factorised and per row, the factor's
nonzeros and MKL's memory for it, the set-up (reduction + factorisation + singularity test) and solve
times (the 7 unit loads at once), and the process's peak resident memory; the two solutions are compared
(largest difference over the largest displacement, per load). Timings depend on the machine's load: the
1-minute load average is recorded before and after.

Run: ``.venv/bin/python benchmarks/bench_ties.py [--models hybrid,solid] [--solid-mesh-mm 16]``; appends to
benchmarks/RESULTS.md (``--no-record``: print only).
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

from machine import publish  # noqa: E402


def child(model: str, mesh_mm: float | None, method: str, out: str) -> None:
    import resource

    import numpy as np

    from rvcoax.fem import solvers
    from rvcoax.fem import system as fem_system
    from rvcoax.geometry.model.assemble import assemble_rig
    from rvcoax.geometry.model.loads import UNIT_LOADS
    from rvcoax.geometry.rigfile import load_rig

    options = {} if mesh_mm is None else {"mesh_size_mm": mesh_mm}
    start = time.perf_counter()
    system = assemble_rig(load_rig(), model, **options)
    assembly = time.perf_counter() - start
    loads = np.column_stack([system.unit_loads[name] for name in UNIT_LOADS])
    start = time.perf_counter()
    if method == "eliminated":
        reduced = fem_system.reduced_stiffness(system.stiffness, system.elimination)
        prepared = solvers.prepare(reduced, "pardiso")
        del reduced
        setup = time.perf_counter() - start
        begin = time.perf_counter()
        u = system.elimination @ prepared.solve(system.elimination.T @ loads)
    else:
        prepared = fem_system.prepare_system(system.stiffness, system.elimination, "pardiso").solver
        setup = time.perf_counter() - start
        begin = time.perf_counter()
        u = system.elimination @ prepared.solve(system.elimination.T @ loads)
    solve = time.perf_counter() - begin
    report = prepared.report
    np.save(out + ".npy", u)
    Path(out + ".json").write_text(json.dumps({
        "dofs": system.n_dofs, "reduced": report.n_dofs, "solver": report.name,
        "nnz": report.matrix_nonzeros, "factor_nnz": report.factor_nonzeros, "factor_MB": report.factor_memory_MB,
        "assembly_s": assembly, "setup_s": setup, "solve_s": solve,
        "peak_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}))


def run(model: str, mesh_mm: float | None, folder: Path) -> list[tuple[str, str]]:
    import numpy as np

    rows, found = [], {}
    label = f"{model}" + ("" if mesh_mm is None else f" ({mesh_mm:g} mm)")
    for method in ("eliminated", "multipliers"):
        out = str(folder / f"{model}-{method}")
        command = [sys.executable, __file__, "--child", model, str(mesh_mm or ""), method, out]
        subprocess.run(command, check=True, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
        found[method] = json.loads(Path(out + ".json").read_text())
        f = found[method]
        rows.append((f"{label}, {method}: matrix factorised",
                     f"{f['reduced']:,} unknowns, {f['nnz'] / 1e6:.2f} M nonzeros, {f['nnz'] / f['reduced']:.1f} per row "
                     f"({f['solver']})"))
        rows.append((f"{label}, {method}: factor",
                     f"{f['factor_nnz'] / 1e6:.1f} M nonzeros, MKL memory {f['factor_MB']:.0f} MB"))
        rows.append((f"{label}, {method}: time and memory",
                     f"assembly {f['assembly_s']:.1f} s, set-up {f['setup_s']:.1f} s, solve (7 loads) {f['solve_s']:.2f} s, "
                     f"peak resident {f['peak_MB']:.0f} MB"))
    a, b = (np.load(str(folder / f"{model}-{m}.npy")) for m in ("eliminated", "multipliers"))
    difference = np.abs(a - b).max(axis=0) / np.where(np.abs(a).max(axis=0) > 0, np.abs(a).max(axis=0), 1.0)
    rows.append((f"{label}: largest |Δu| / largest |u| per unit load", ", ".join(f"{d:.1e}" for d in difference)))
    return rows


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child(sys.argv[2], float(sys.argv[3]) if sys.argv[3] else None, sys.argv[4], sys.argv[5])
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", default="hybrid,solid")
    parser.add_argument("--solid-mesh-mm", type=float, default=16.0)
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    rows = []
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        for model in args.models.split(","):
            rows += run(model, args.solid_mesh_mm if model == "solid" else None, Path(folder))
    rows.append(("script runtime", f"{time.perf_counter() - started:.0f} s"))
    publish("bench_ties.py: distributing ties eliminated (dense) against kept with multipliers", rows, load_before,
            not args.no_record)


if __name__ == "__main__":
    main()
