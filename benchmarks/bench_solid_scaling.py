"""Solid model at ~50 k, ~300 k and ~1 M DOF: time and peak memory of every phase.

The model is the reference rig's output shaft as a cantilever: Ø35/30/35/30/30 mm steps over
160 mm (shifted to start at x = 0), Q460 (E = 206 GPa, ν = 0.28), clamped on its end face x = 0,
100 N in −y as a uniform traction on the end face x = 160 mm. Curved quadratic tets from
rvcoax.geometry.meshing (gmsh, one thread) at three mesh sizes:

    50k   h = 4.0 mm    52,698 DOF
    300k  h = 2.1 mm   298,017 DOF
    1M    h = 1.35 mm 1,043,940 DOF

Phases: meshing (gmsh, cache bypassed), basis (scikit-fem), stiffness (rvcoax.fem.solid.stiffness_matrix:
element matrices added in chunks straight into the 3 × 3-block pattern, no triplet arrays), load vector,
constraint elimination (the clamped DOFs' rows and columns dropped in one pass over the stiffness's own
arrays: rvcoax.fem.assembly.keep_rows_and_columns), probes and rigid-body modes (after which the basis is
dropped: 1.1 GB at 1 M DOF), solver set-up and solve (rvcoax.fem.solvers.prepare,
method "auto": PARDISO or AMG-CG with the rigid-body modes, whichever the measured cost model of
rvcoax.fem.solver_cost expects to be faster for one right-hand side in the memory available; AMG stops
at its default accuracy) and probing (interpolation at 41 points on the axis, tip-face mean). Each size
runs in a fresh Python process, so the peak resident memory read after every phase (VmHWM, the
process's high-water mark of resident memory: ru_maxrss without the parent's share) is that size's
own; the table also gives the rise of that high-water mark during each phase, the CPU time (user and
system, all threads) of each phase, and the cost model's estimates for both methods.

The previous triplet assembly (element matrices, then ``rvcoax.fem.assembly.assemble_matrix``) is
compared with the chunked one in bench_assembly_memory.py.

Run: ``.venv/bin/python benchmarks/bench_solid_scaling.py [--sizes 50k,300k,1M]``. Prints the
figures and appends them to benchmarks/RESULTS.md (``--no-record``: print only).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import record  # noqa: E402

# the reference rig's output shaft, shifted to x = 0: (x_start, x_end, outer Ø, inner Ø) in mm
SEGMENTS = ((0.0, 15.0, 35.0, 0.0), (15.0, 35.0, 30.0, 0.0), (35.0, 85.0, 35.0, 0.0),
            (85.0, 105.0, 30.0, 0.0), (105.0, 160.0, 30.0, 0.0))
LENGTH_MM = 160.0
YOUNGS_PA, POISSON = 206e9, 0.28  # Q460, paper 000
TIP_FORCE_N = (0.0, -100.0, 0.0)
SIZES = {"50k": 4.0, "300k": 2.1, "1M": 1.35}  # label -> mesh size (mm)
TARGET_1M = (60.0, 6.0)  # issue 27: the 1 M-DOF cantilever in ≤ 60 s and ≤ 6 GB
N_PROBES = 41


def geometry(label: str):
    from rvcoax.geometry.meshing import SolidPartGeometry

    return SolidPartGeometry(f"cantilever_{label}", SEGMENTS, (), SIZES[label])


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far, MB.

    VmHWM from /proc/self/status: the high-water mark of this program's own address space. (The
    ru_maxrss of a child started by subprocess also carries the parent's resident memory at the
    time of the fork, which VmHWM, reset by exec, does not.) ru_maxrss where there is no /proc.
    """
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except (OSError, ValueError, IndexError):
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def nodes_at_x(basis, x_m: float, tol: float = 1e-9):
    """Node coordinates (k, 3) and DOFs (k, 3) of all P2 nodes on the plane x = x_m."""
    from rvcoax.fem import solid

    coordinates, dofs = solid.dof_locations(basis)
    on_plane = abs(coordinates[:, 0] - x_m) < tol
    return coordinates[on_plane], dofs[on_plane]


def first_touch_seconds_per_gib() -> tuple[float, float]:
    """Seconds to allocate and fill 1 GiB: memory new to this process, then the same amount again at once.

    On a virtual machine whose host backs guest memory lazily (and takes free pages back, e.g.
    virtio-balloon free page reporting) the first figure can be 5–10× the second: every phase that
    raises a process's memory high-water mark pays it, in system time.
    """
    import numpy as np

    seconds = []
    for _ in range(2):
        start = time.perf_counter()
        block = np.ones(2**27)
        seconds.append(time.perf_counter() - start)
        del block
    return seconds[0], seconds[1]


class Phases:
    """Wall time, CPU time (user, system; all threads) and ru_maxrss after each phase."""

    def __init__(self) -> None:
        self.rows: list[dict] = []
        self._rss = peak_rss_mb()
        self.baseline_mb = self._rss

    def run(self, name: str, function, *args):
        before = resource.getrusage(resource.RUSAGE_SELF)
        start = time.perf_counter()
        result = function(*args)
        elapsed = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_SELF)
        rss = peak_rss_mb()
        self.rows.append({"phase": name, "seconds": elapsed, "peak_rss_mb": rss, "increase_mb": rss - self._rss,
                          "user_seconds": after.ru_utime - before.ru_utime,
                          "system_seconds": after.ru_stime - before.ru_stime})
        self._rss = rss
        return result


def run_one(label: str) -> dict:
    """One size in this process: every phase timed; returns the figures."""
    import numpy as np

    from rvcoax.fem import blas_threads, hugepages, solid
    from rvcoax.fem.assembly import keep_rows_and_columns
    from rvcoax.fem.memory import available_memory_bytes
    from rvcoax.fem.rigid_body import rigid_body_modes
    from rvcoax.fem.solver_cost import COST_MODEL
    from rvcoax.fem.solvers import choose_method, prepare
    from rvcoax.geometry.meshing import mesh_part

    hugepages.avoid_compaction_stalls()  # as the rvcoax command does at start
    blas_threads.single_threaded_openblas()
    load_before = os.getloadavg()[0]
    phases = Phases()
    mesh = phases.run("meshing (gmsh, 1 thread)", lambda: mesh_part(geometry(label), use_cache=False))
    basis = phases.run("basis (scikit-fem, intorder 2)", lambda: solid.solid_basis(mesh))
    n = int(basis.N)
    stiffness = phases.run("stiffness (chunked 3×3-block assembly)", solid.stiffness_matrix, basis, YOUNGS_PA, POISSON)
    matrix_mb = (stiffness.data.nbytes + stiffness.indices.nbytes + stiffness.indptr.nbytes) / 2**20

    def load_vector():
        tip_facets = mesh.facets_satisfying(lambda x: np.isclose(x[0], LENGTH_MM * 1e-3, rtol=0.0, atol=1e-9))
        return solid.force_traction_vector(mesh, tip_facets, TIP_FORCE_N)

    force = phases.run("load vector (tip traction)", load_vector)

    def eliminate(stiffness, basis):
        _, clamped = nodes_at_x(basis, 0.0)
        keep = np.ones(n, dtype=bool)
        keep[clamped.ravel()] = False
        free = np.flatnonzero(keep)
        # one pass over the rows, written over the stiffness's own arrays: no second matrix
        return free, keep_rows_and_columns(stiffness, keep, overwrite=True), force[free]

    free, reduced, reduced_force = phases.run("constraint elimination (clamped DOFs, in place)", eliminate, stiffness,
                                              basis)
    del stiffness

    def probes(basis):
        _, tip_dofs = nodes_at_x(basis, LENGTH_MM * 1e-3)
        points = np.column_stack([np.linspace(0.0, LENGTH_MM * 1e-3, N_PROBES), np.zeros(N_PROBES), np.zeros(N_PROBES)])
        return tip_dofs, solid.probe_matrix(basis, points), rigid_body_modes(basis.doflocs.T)[free]

    # what the solution's output and the AMG set-up need from the basis, then the basis goes (1.1 GB at 1 M DOF)
    tip_dofs, axis_probes, modes = phases.run("probes and rigid-body modes (the basis is dropped after)", probes,
                                           basis)
    del basis

    def set_up():
        return prepare(reduced, method="auto", near_null_space=modes)

    available = available_memory_bytes()
    chosen = choose_method(reduced.shape[0], reduced.nnz, 1, available)
    estimates = {"pardiso_s": COST_MODEL.pardiso_seconds(reduced.shape[0]), "amg_s": COST_MODEL.amg_seconds(reduced.nnz, 1, reduced.shape[0]),
                 "pardiso_gb": COST_MODEL.pardiso_bytes(reduced.shape[0], reduced.nnz) / 1e9,
                 "amg_gb": COST_MODEL.amg_bytes(reduced.nnz) / 1e9, "available_gb": (available or 0.0) / 1e9,
                 "chosen": chosen}
    solver = phases.run("solver set-up", set_up)
    q = phases.run("solve", lambda: solver.solve(reduced_force))
    report = solver.report
    solver.release()

    def probe():
        u = np.zeros(n)
        u[free] = q
        along_axis = (axis_probes @ u).reshape(-1, 3)
        return float(u[tip_dofs[:, 1]].mean()), along_axis

    tip_mean_uy, along_axis = phases.run("probing (41 axis points + tip-face mean)", probe)
    load_after = os.getloadavg()[0]

    result = {
        "label": label,
        "mesh_size_mm": SIZES[label],
        "n_dofs": n,
        "n_free": int(free.size),
        "n_tets": int(mesh.t.shape[1]),
        "n_nodes": int(mesh.doflocs.shape[1]),
        "matrix_mb": matrix_mb,
        "nnz": int(reduced.nnz),
        "cost_model": estimates,
        "phases": phases.rows,
        "baseline_rss_mb": phases.baseline_mb,
        "solver": report.name,
        "iterations": [int(i) for i in report.iterations],
        "error_estimates": [float(e) for e in report.error_estimates],
        "residual": max(report.relative_residuals),
        "tip_mean_uy_um": 1e6 * tip_mean_uy,
        "axis_tip_uy_um": 1e6 * float(along_axis[-1, 1]),
        "load_average": [load_before, load_after],
    }
    return result


def fmt_mb(mb: float) -> str:
    return f"{mb / 1024:.2f} GB" if mb >= 1024 else f"{mb:.0f} MB"


def hugepage_policy() -> str:
    """How the measured runs treat numpy's huge-page requests (fem/hugepages.py), in words."""
    from rvcoax.fem import hugepages

    defrag = hugepages.defrag_mode()
    if "NUMPY_MADVISE_HUGEPAGE" in os.environ:
        return f"as set in the environment (NUMPY_MADVISE_HUGEPAGE={os.environ['NUMPY_MADVISE_HUGEPAGE']})"
    if defrag in hugepages.STALLING_DEFRAG_MODES:
        return f"off, as in the rvcoax command (THP defrag = {defrag}: a first touch would wait for compaction)"
    return f"numpy's default, as in the rvcoax command (THP defrag = {defrag})"


def openblas_policy() -> str:
    """How many threads OpenBLAS gets in the measured runs (fem/blas_threads.py), in words."""
    from rvcoax.fem import blas_threads

    if blas_threads.ENVIRONMENT_KEY in os.environ:
        return f"as set in the environment ({blas_threads.ENVIRONMENT_KEY}={os.environ[blas_threads.ENVIRONMENT_KEY]})"
    return "1, as in the rvcoax command (its spinning threads would take the cores MKL PARDISO needs)"


def figures_of(result: dict) -> list[tuple[str, str]]:
    tag = f"{result['label']} ({result['n_dofs']:,} DOF)"
    rows = [(f"{tag}: model", f"h = {result['mesh_size_mm']} mm, {result['n_tets']:,} tets, {result['n_nodes']:,} nodes, "
                              f"stiffness {fmt_mb(result['matrix_mb'])} (CSR), {result['nnz']:,} nonzeros after elimination")]
    total = cpu = 0.0
    for row in result["phases"]:
        total += row["seconds"]
        cpu += row["user_seconds"] + row["system_seconds"]
        rows.append((f"{tag}: {row['phase']}",
                     f"{row['seconds']:.2f} s (CPU user {row['user_seconds']:.2f} s, system {row['system_seconds']:.2f} s), "
                     f"peak RSS {fmt_mb(row['peak_rss_mb'])} (+{fmt_mb(row['increase_mb'])})"))
    by_name = {row["phase"]: row["seconds"] for row in result["phases"]}
    assembly = by_name["stiffness (chunked 3×3-block assembly)"]
    peak_gb = result["phases"][-1]["peak_rss_mb"] / 1024
    rows.append((f"{tag}: total", f"{total:.1f} s (meshing to probed displacement); peak RSS "
                                  f"{fmt_mb(result['phases'][-1]['peak_rss_mb'])}, of which {fmt_mb(result['baseline_rss_mb'])} "
                                  "before meshing (interpreter and imports)"))
    rows.append((f"{tag}: CPU time, all phases", f"{cpu:.1f} s (user + system, all threads)"))
    if result["n_dofs"] > 900_000:
        seconds, gigabytes = TARGET_1M
        peak_bytes = result["phases"][-1]["peak_rss_mb"] * 2**20
        rows.append((f"{tag}: issue 27 target ≤ {seconds:.0f} s, ≤ {gigabytes:.0f} GB (10⁹ bytes)",
                     f"time {'met' if total <= seconds else 'NOT met'} ({total:.1f} s), memory "
                     f"{'met' if peak_bytes <= gigabytes * 1e9 else 'NOT met'} ({peak_bytes / 1e9:.2f} GB = "
                     f"{peak_gb:.2f} GiB)"))
    rows.append((f"{tag}: stiffness assembly", f"{assembly:.2f} s = {result['n_dofs'] / assembly / 1e3:.0f} k DOF/s"))
    model = result["cost_model"]
    rows.append((f"{tag}: cost model (one right-hand side)",
                 f"PARDISO {model['pardiso_s']:.1f} s, {model['pardiso_gb']:.1f} GB; AMG-CG {model['amg_s']:.1f} s, "
                 f"{model['amg_gb']:.1f} GB; available {model['available_gb']:.1f} GB → {model['chosen']}"))
    iterations = f", {result['iterations'][0]} CG iterations" if result["iterations"] else ""
    estimate = (f", estimated relative energy-norm error {result['error_estimates'][0]:.1e}"
                if result.get("error_estimates") else "")
    rows.append((f"{tag}: solver", f"{result['solver']}{iterations}{estimate}, relative residual {result['residual']:.1e}"))
    rows.append((f"{tag}: tip deflection", f"tip-face node mean u_y {result['tip_mean_uy_um']:.4f} µm, "
                                           f"axis point at the tip {result['axis_tip_uy_um']:.4f} µm"))
    rows.append((f"{tag}: load average (1 min) before / after", "{:.2f} / {:.2f}".format(*result["load_average"])))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default=",".join(SIZES), help=f"comma-separated, from {', '.join(SIZES)}")
    parser.add_argument("--no-record", action="store_true", help="print only, do not append to RESULTS.md")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(run_one(args.child)))
        return
    labels = [s.strip() for s in args.sizes.split(",") if s.strip()]
    unknown = [s for s in labels if s not in SIZES]
    if unknown:
        parser.error(f"unknown size(s) {unknown}: choose from {', '.join(SIZES)}")
    cold, warm = first_touch_seconds_per_gib()
    figures: list[tuple[str, str]] = [
        ("model", f"stepped cantilever (output shaft, L = {LENGTH_MM:.0f} mm), clamped at x = 0, "
                  f"{-TIP_FORCE_N[1]:.0f} N tip traction; curved P2 tets; one fresh process per size"),
        ("machine: allocate + fill 1 GiB", f"{cold:.2f} s new to the process, {warm:.2f} s reused at once "
                                           "(the difference is paid by every phase that raises the peak memory)"),
        ("numpy huge-page requests", hugepage_policy()),
        ("OpenBLAS threads", openblas_policy()),
    ]
    for name, value in figures:
        print(f"{name}: {value}", flush=True)
    for label in labels:
        start = time.perf_counter()
        completed = subprocess.run([sys.executable, __file__, "--child", label], capture_output=True, text=True)
        wall = time.perf_counter() - start
        if completed.returncode != 0:
            print(completed.stderr, file=sys.stderr)
            last = (completed.stderr.strip().splitlines() or ["(no message)"])[-1]
            figures.append((f"{label}: FAILED", f"exit status {completed.returncode} after {wall:.0f} s: {last}"))
            print(f"{figures[-1][0]}: {figures[-1][1]}", flush=True)
            continue
        result = json.loads(completed.stdout.strip().splitlines()[-1])
        rows = figures_of(result)
        rows.append((f"{label} ({result['n_dofs']:,} DOF): child process wall time", f"{wall:.1f} s"))
        for name, value in rows:
            print(f"{name}: {value}", flush=True)
        figures += rows
    if not args.no_record:
        record("bench_solid_scaling.py: solid cantilever, time and peak memory per phase", figures)


if __name__ == "__main__":
    main()
