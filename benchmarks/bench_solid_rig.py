"""The all-solid reference rig: a sweep of the 20 paper cases, time and peak memory per phase.

Every part of the reference rig a solid of curved quadratic tets (``rvcoax sweep --model solid``),
at the mesh sizes given (``--sizes``, mm; the rig file's default is 4 mm). Each size runs in a fresh
Python process with an empty mesh cache, so that its phases and its peak resident memory are its own:

- **mesh**: gmsh on every part (:func:`rvcoax.geometry.meshing.mesh_part`);
- **assembly**: bases, element matrices and the chunked block assembly of each solid, the beam frame,
  springs and loads (:func:`rvcoax.assemble_rig` less the two phases below);
- **ties**: the rigid and distributing tie equations of every attached face;
- **probes**: the ring probes along the two measured shafts;
- **set-up**: the solver (:func:`rvcoax.results.sweep.prepare_system`: PARDISO's analysis and
  factorisation of the saddle-point matrix with the tie multipliers, its singularity checks and
  the condition estimate);
- **condition**: the condition estimate of the set-up (about ten solves), reported apart from it;
- **solves**: the unit-load solves of the sweep;
- **results**: the rest of the sweep (Y, β, tilts, the engineering tables) and the result files.

Per phase: wall time, CPU time (user + system, all threads), the process's high-water mark of
resident memory after the phase (VmHWM) and its rise during the phase. With ``--analyse-only``
the set-up stops after PARDISO's symbolic analysis and reports what the factorisation would need
(factor nonzeros, MKL's memory estimate and the factorisation's floating-point operations) —
for sizes whose factorisation would not fit or not finish.

Run: ``.venv/bin/python benchmarks/bench_solid_rig.py [--sizes 4.5,3] [--analyse-only] [--analyse-sizes 2.8]``; run it
alone (it may need several GB). Prints the figures and appends them to benchmarks/RESULTS.md
(``--no-record``: print only). The peak resident memory is judged against issue 27's hard limits
(:data:`PEAK_LIMITS`, decimal bytes); the script exits 1 when a run misses its limit.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import publish  # noqa: E402

PHASES = ("mesh", "assembly", "ties", "probes", "set-up", "condition", "solves", "results")
PEAK_LIMITS = ((600_000, 4.0e9), (1_200_000, 12.0e9))
"""Issue 27's hard limits on the sweep's peak resident memory, bytes (decimal GB): up to 600 k DOF (the default 4 mm
mesh, 492 k DOF) 4 GB, up to 1.2 M DOF (2.8 mm, 1.04 M DOF) 12 GB. A run above its limit makes the script exit 1."""


def peak_limit(dofs: int) -> float | None:
    """The peak-memory limit (bytes) for a model of ``dofs`` DOF, or None above the sizes the issue names."""
    return next((limit for most, limit in PEAK_LIMITS if dofs <= most), None)


def peak_rss_mb() -> float:
    """This process's high-water mark of resident memory (VmHWM), MB."""
    with open("/proc/self/status", encoding="ascii") as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def cpu_seconds() -> float:
    times = os.times()
    return times.user + times.system


class Phases:
    """Wall time, CPU time and memory high-water mark per phase; nested timers subtract from their parent."""

    def __init__(self):
        self.wall = dict.fromkeys(PHASES, 0.0)
        self.cpu = dict.fromkeys(PHASES, 0.0)
        self.peak = dict.fromkeys(PHASES, 0.0)
        self.rise = dict.fromkeys(PHASES, 0.0)
        self._stack: list[str] = []

    def run(self, phase: str, function, *args, **kwargs):
        before_peak = peak_rss_mb()
        wall, cpu = time.perf_counter(), cpu_seconds()
        self._stack.append(phase)
        try:
            return function(*args, **kwargs)
        finally:
            self._stack.pop()
            spent_wall, spent_cpu = time.perf_counter() - wall, cpu_seconds() - cpu
            self.wall[phase] += spent_wall
            self.cpu[phase] += spent_cpu
            if self._stack:  # time inside a nested phase is not its parent's
                self.wall[self._stack[-1]] -= spent_wall
                self.cpu[self._stack[-1]] -= spent_cpu
            self.peak[phase] = max(self.peak[phase], peak_rss_mb())
            rise = max(0.0, peak_rss_mb() - before_peak)
            self.rise[phase] += rise
            if self._stack:
                self.rise[self._stack[-1]] -= rise

    def wrap(self, module, name: str, phase: str) -> None:
        """Count every call of ``module.name`` to ``phase`` (for the duration of this process)."""
        original = getattr(module, name)

        @functools.wraps(original)
        def timed(*args, **kwargs):
            return self.run(phase, original, *args, **kwargs)

        setattr(module, name, timed)


def analyse_only(system) -> dict:
    """PARDISO's symbolic analysis of the system's saddle-point matrix: predicted factor size, memory, flops."""
    from rvcoax.fem import pardiso
    from rvcoax.fem import system as fem_system

    long = fem_system.long_rows(system.elimination)
    operator = fem_system.constrained_stiffness(system.stiffness, system.elimination, long)
    upper = operator.saddle_point_upper()  # what the solver factorises, without the whole saddle-point matrix
    analysis = pardiso.analyse(upper, indefinite=True)
    return {"matrix_nonzeros": pardiso.stored_nonzeros(upper), "unknowns": int(upper.n), **analysis}


def child(size_mm: float, analyse: bool) -> dict:
    """Run ``rvcoax sweep --model solid --solver pardiso`` (or, ``analyse``, the assembly and PARDISO's
    analysis) at ``size_mm`` in this process and return its figures."""
    os.environ["RVCOAX_CACHE_DIR"] = tempfile.mkdtemp(prefix="bench_solid_rig_")
    from rvcoax.fem import system as fem_system
    from rvcoax.geometry.model import hybrid
    from rvcoax.results import sweep as sweep_module

    phases = Phases()
    phases.wrap(hybrid, "mesh_part", "mesh")
    phases.wrap(hybrid, "rigid_tie_equations", "ties")
    phases.wrap(hybrid, "distributing_tie_equations", "ties")
    phases.wrap(hybrid, "tie_contribution", "ties")
    phases.wrap(hybrid, "ring_probe", "probes")
    phases.wrap(sweep_module, "assemble_rig", "assembly")
    phases.wrap(sweep_module, "_prepare", "set-up")
    phases.wrap(fem_system.ReducedSystem, "solve", "solves")
    phases.wrap(fem_system.ReducedSystem, "condition_estimate", "condition")
    captured = {}
    out = {"size_mm": size_mm}
    start = time.perf_counter()
    if analyse:
        from rvcoax import load_rig

        system = sweep_module.assemble_rig(load_rig(), "solid", mesh_size_mm=size_mm)
        out["analysis"] = phases.run("set-up", analyse_only, system)
    else:
        original = sweep_module.prepare_system

        def keep(system, settings, **options):
            captured["prepared"] = prepared = original(system, settings, **options)
            return prepared

        sweep_module.prepare_system = keep
        from rvcoax.results.cli.app import run

        folder = tempfile.mkdtemp(prefix="bench_solid_rig_out_")
        sys.argv = ["rvcoax", "sweep", "--model", "solid", "--solver", "pardiso", "--mesh-size-mm", str(size_mm),
                    "--out", folder]
        try:
            phases.run("results", functools.partial(run, end_process=False))
        except SystemExit as exit_:
            if exit_.code not in (0, None):
                raise
        system = captured["prepared"].system
        out["solver"] = captured["prepared"].solver_name
        out["report"] = {k: v for k, v in captured["prepared"].report.items()
                         if isinstance(v, (int, float, str, type(None)))}
        out["sweep_csv"] = (Path(folder) / "sweep.csv").read_text()
    out["dofs"] = int(system.n_dofs)
    out["stiffness_nonzeros"] = int(system.stiffness.nnz)
    out["total_s"] = time.perf_counter() - start
    out["phases"] = {p: {"wall_s": phases.wall[p], "cpu_s": phases.cpu[p], "peak_MB": phases.peak[p],
                         "rise_MB": phases.rise[p]} for p in PHASES}
    out["peak_MB"] = peak_rss_mb()
    return out


def _limit_row(figures: dict) -> tuple[tuple[str, str], bool]:
    """The peak against :data:`PEAK_LIMITS`, in bytes: (row, whether within the limit)."""
    peak = figures["peak_MB"] * 2**20  # VmHWM is in KiB
    limit = peak_limit(figures["dofs"]) if "solver" in figures else None
    text = f"{peak:.4g} bytes = {peak / 2**30:.2f} GiB (VmHWM {round(figures['peak_MB'] * 1024):,} kB)"
    if limit is None:
        return (f"  {figures['size_mm']:g} mm: peak resident memory", text), True
    within = peak <= limit
    return ((f"  {figures['size_mm']:g} mm: peak resident memory",
             f"{text}; issue 27 limit {limit / 1e9:g}e9 bytes: {'met' if within else 'NOT met'} "
             f"({(limit - peak) / 1e9:+.2f} GB margin)"), within)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="4.5,3", help="global mesh sizes, mm, comma-separated")
    parser.add_argument("--analyse-only", action="store_true", help="stop the set-up after PARDISO's analysis")
    parser.add_argument("--analyse-sizes", default="", help="further sizes, mm, run with --analyse-only")
    parser.add_argument("--no-record", action="store_true")
    parser.add_argument("--child", type=float, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child is not None:
        print(json.dumps(child(args.child, args.analyse_only)))
        return
    load_before = os.getloadavg()[0]
    rows, all_within = [], True
    runs = [(float(text), args.analyse_only) for text in args.sizes.split(",") if text]
    runs += [(float(text), True) for text in args.analyse_sizes.split(",") if text]
    for size, analyse in runs:
        command = [sys.executable, __file__, "--child", str(size)] + (["--analyse-only"] if analyse else [])
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode:
            rows.append((f"solid rig at {size:g} mm", f"failed (exit {done.returncode}): "
                                                      f"{' '.join(done.stderr.strip().splitlines()[-3:])}"))
            continue
        figures = json.loads(done.stdout.strip().splitlines()[-1])
        rows.append(_summary_row(figures))
        row, within = _limit_row(figures)
        rows.append(row)
        all_within &= within
        for phase, f in figures["phases"].items():
            if f["wall_s"] or f["rise_MB"]:
                rows.append((f"  {size:g} mm: {phase}", f"{f['wall_s']:.1f} s wall, {f['cpu_s']:.1f} s CPU, "
                                                        f"peak {f['peak_MB'] / 1e3:.2f} GB (+{f['rise_MB'] / 1e3:.2f} GB)"))
        if "analysis" in figures:
            a = figures["analysis"]
            rows.append((f"  {size:g} mm: PARDISO analysis", f"{a['unknowns']:,} unknowns, {a['matrix_nonzeros'] / 1e6:.1f} M "
                         f"nonzeros; factor {a['factor_nonzeros'] / 1e6:.0f} M nonzeros, "
                         f"{a['factorisation_gflop']:.0f} GFLOP, MKL memory {a['memory_MB'] / 1e3:.2f} GB "
                         f"(analysis {a['analysis_peak_MB'] / 1e3:.2f} GB)"))
    publish("bench_solid_rig.py: the all-solid reference rig, 20 paper cases, per phase", rows, load_before,
            not args.no_record)
    if not all_within:
        sys.exit(1)


def _summary_row(figures: dict) -> tuple[str, str]:
    size = figures["size_mm"]
    text = (f"{figures['dofs']:,} DOF, {figures['stiffness_nonzeros'] / 1e6:.1f} M nonzeros in K; total "
            f"{figures['total_s']:.1f} s (mesh to files), peak {figures['peak_MB'] / 1e3:.2f} GB")
    if "solver" in figures:
        report = figures["report"]
        lines = figures["sweep_csv"].strip().splitlines()
        header, last = lines[0].split(","), lines[-1].split(",")
        row = ", ".join(f"{k} = {v}" for k, v in zip(header, last) if k.startswith(("T1", "T2", "Y_")))
        text += (f"; {figures['solver']}; condition estimate {report.get('condition_estimate') or float('nan'):.2g}"
                 f"; last row of sweep.csv: {row}")
    return f"solid rig at {size:g} mm" + (" (assembly and PARDISO analysis only)" if "analysis" in figures else ""), text


if __name__ == "__main__":
    main()
