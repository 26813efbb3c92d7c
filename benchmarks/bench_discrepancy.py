"""Identification rate of the discrepancy workflow per hidden effect and noise level (confusion matrix).

For every candidate effect that can change the measured paths by 30 % of the signal within its
physical bounds (one location per kind is not enough for a confusion matrix: every location is
tried), synthetic paths data (11 stations per shaft, paper 000's 20 load cases) are made from the
rig *with* the effect at 30 % of the signal plus Gaussian noise, and the workflow starts from the rig
without it. A run counts as *named* when the hidden effect is the added effect or in its ambiguity
group; *exact* when it is the added effect itself. Rows: hidden effect; columns: what was added.

The data are made with a *different discretisation* than the identifying model (beam elements of
at most 2 mm instead of 5 mm). A run is a *confident mis-name* when the workflow marks an effect
confident that was not hidden. ``--timing`` instead times the whole workflow (library included) on
the paper's 20-case table and on a 360-row paths file (9 stations per shaft, 20 cases), with the
load average, as the issue's speed targets are stated for them.

Usage: python benchmarks/bench_discrepancy.py [--seeds N] [--schema paths|table] [--timing] [--no-record]
"""

from __future__ import annotations

import argparse
import collections
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))  # the tests' rig and data helpers
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "results"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "support"))  # (the helpers moved there)
sys.path.insert(0, str(Path(__file__).resolve().parent))

from discrepancy_data import LENGTHS, STATIONS, discrepancy_rig, finer  # noqa: E402
from machine import record  # noqa: E402

from rvcoax.geometry.effects import candidate_effects  # noqa: E402
from rvcoax.loadcases.cases import paper_cases  # noqa: E402
from rvcoax.results.studies.discrepancy.synthetic import effect_size_for, observation_layout, synthetic_data  # noqa: E402
from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, build_library, run_discrepancy  # noqa: E402
from rvcoax.results.sweep import SweepSettings  # noqa: E402


def _timed(start: float, cpu: float, result, load: float) -> str:
    """Wall and CPU seconds since ``start``/``cpu``, with the confidence estimate's share (issue 28 item 6)."""
    c = result.confidence
    share = "" if c is None else f"; confidence estimate {c.seconds:.2f} s wall, {c.total_draws} draws"
    return (f"{time.perf_counter() - start:.2f} s wall, {time.process_time() - cpu:.2f} s CPU (verdict "
            f"{result.verdict}{share}; load average {load:.2f})")


def timing(record_it: bool) -> None:
    """End-to-end times of the two sizes the issue names, library build included."""
    import os

    from rvcoax.geometry.rigfile import load_rig
    from rvcoax.results.studies.discrepancy.measured import read_measured

    rows = []
    table = read_measured(Path(__file__).resolve().parents[1] / "loadcases/data/paper000_coaxiality_table.csv")
    rig = load_rig()
    for label, run_rig, data in (("paper table, 20 cases, 40 observations", rig, table),):
        start, cpu = time.perf_counter(), time.process_time()
        result = run_discrepancy(run_rig, data, DiscrepancySettings())
        rows.append((f"{label}: end to end", _timed(start, cpu, result, os.getloadavg()[0])))
    rig = discrepancy_rig()
    effect = {e.name: e for e in candidate_effects(rig)}["bearing_stiffness@output_B2"]
    template = observation_layout(paper_cases(), 9, LENGTHS, "paths")
    truth = effect.apply(rig, [effect_size_for(effect, rig, paper_cases(), template, 0.3)])
    data = synthetic_data(finer(truth), template, 0.01, 1)
    start, cpu = time.perf_counter(), time.process_time()
    result = run_discrepancy(rig, data, DiscrepancySettings())
    rows.append((f"paths file, {data.n} rows, hidden bearing_stiffness@output_B2: end to end",
                 _timed(start, cpu, result, os.getloadavg()[0])))
    for label, value in rows:
        print(f"{label}: {value}")
    if record_it:
        record("bench_discrepancy.py --timing: the workflow end to end (one factorisation)", rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--schema", default="paths", choices=("paths", "table"))
    parser.add_argument("--noise", default="0.01,0.05")
    parser.add_argument("--effects", default="", help="comma-separated effect names (default: every candidate)")
    parser.add_argument("--no-record", action="store_true")
    parser.add_argument("--timing", action="store_true", help="time the paper table and a 360-row paths file")
    args = parser.parse_args()
    if args.timing:
        timing(not args.no_record)
        return
    rig = discrepancy_rig()
    cases = paper_cases()
    start = time.perf_counter()
    library = build_library(rig, cases, SweepSettings())
    library_seconds = time.perf_counter() - start
    template = observation_layout(cases, STATIONS, LENGTHS, args.schema)
    effects = {e.name: e for e in candidate_effects(rig)}
    rows: list[tuple[str, str]] = []
    counts: dict = collections.defaultdict(lambda: collections.Counter())
    unreachable = []
    seconds = []
    chosen = [n for n in args.effects.split(",") if n] or list(effects)
    for name in [None, *chosen]:
        if name is not None:
            size = effect_size_for(effects[name], rig, cases, template, 0.3)
            truth = effects[name].apply(rig, [size])
            paths_truth = synthetic_data(truth, template, 0.0, 0)
            paths_base = synthetic_data(rig, template, 0.0, 0)
            change = max(np.sqrt(np.mean((paths_truth.value_mm - paths_base.value_mm)[template.shaft == s] ** 2))
                         / np.sqrt(np.mean(paths_base.value_mm[template.shaft == s] ** 2)) for s in LENGTHS)
            if change < 0.29:
                unreachable.append(f"{name} ({100 * change:.2g} % at its bound)")
                continue
        else:
            truth = rig
        truth = finer(truth)  # a different discretisation than the identifying model
        for noise in (float(v) for v in args.noise.split(",")):
            for seed in range(args.seeds):
                t = time.perf_counter()
                result = run_discrepancy(rig, synthetic_data(truth, template, noise, 1000 + seed),
                                         DiscrepancySettings(), library=library)
                seconds.append(time.perf_counter() - t)
                added = result.selected[0].name if result.selected else "nothing"
                in_group = name is None and not result.selected or any(name in s.group for s in result.selected)
                key = (name or "none", noise)
                counts[key]["runs"] += 1
                counts[key]["named"] += bool(in_group)
                counts[key]["exact"] += added == (name or "nothing")
                counts[key]["confident_misname"] += any(s.confident and s.name != name for s in result.selected)
                counts[key]["spurious"] += max(0, len(result.selected) - (0 if name is None else 1))
                counts[key]["explained"] += result.verdict in ("explained", "no_gap")
                counts[key][f"added:{added}"] += 1
                print(f"{name or 'none':40s} noise {noise:4.2f} seed {seed}: {result.verdict:11s} added "
                      f"{[s.name for s in result.selected]}", flush=True)
    lines = [("schema / stations / cases", f"{args.schema} / {STATIONS} per shaft / {len(cases)} (paper 000)"),
             ("candidate library", f"{len(library.responses)} effects, built in {library_seconds:.1f} s"),
             ("workflow run (library reused)", f"median {np.median(seconds):.2f} s, max {np.max(seconds):.2f} s"),
             ("effects that cannot reach 30 % of the signal within their bounds", "; ".join(unreachable) or "none")]
    total = collections.Counter()
    for (name, noise), c in sorted(counts.items()):
        total["runs"] += c["runs"]
        total["named"] += c["named"]
        total["confident_misname"] += c["confident_misname"]
        added = ", ".join(f"{k[6:]} {v}" for k, v in c.most_common() if k.startswith("added:"))
        lines.append((f"{name}, noise {100 * noise:g} %",
                      f"named {c['named']}/{c['runs']}, exact {c['exact']}/{c['runs']}, spurious extra effects "
                      f"{c['spurious']}, verdict ok {c['explained']}/{c['runs']}; added: {added}"))
        rows.append((name, noise))
    lines.append(("all", f"named {total['named']}/{total['runs']} ({100 * total['named'] / total['runs']:.1f} %), "
                         f"confident mis-names {total['confident_misname']}"))
    for label, value in lines:
        print(f"{label}: {value}")
    if not args.no_record:
        record(f"bench_discrepancy.py: identification rate, {args.schema} data, {args.seeds} seeds", lines)


if __name__ == "__main__":
    main()
