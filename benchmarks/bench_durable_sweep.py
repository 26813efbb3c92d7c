"""Per-case cost of durable sweep results next to the per-case cost of solving (issue 12, part 5).

A 1,000-case superposition sweep of the reference rig (beam model) is solved (nothing written),
then its 1,000 JSON records are written (each figure the best of 3 runs):

- to the journal ``sweep`` writes (:class:`rvcoax.results.io.sweep_files.CaseStore`: one checksummed line per
  case, handed to the OS at once, fsync'ed every 256 cases or every second and at the end);
- as one atomically written, fsync'ed file per case (the layout before the journal), as a baseline.

Turning a case into its JSON record is timed on its own (a sweep needs it for sweep.json anyway).
The folder is a temporary one on the same disk as the repository (``$TMPDIR`` is often a RAM
disk, where an fsync costs nothing).

Run: ``.venv/bin/python benchmarks/bench_durable_sweep.py``. Prints the figures and appends them to
benchmarks/RESULTS.md with the machine, date and load.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import record  # noqa: E402

from rvcoax.geometry.rigfile import load_rig  # noqa: E402
from rvcoax.loadcases.cases import grid_cases  # noqa: E402
from rvcoax.results.io import run_durable_sweep  # noqa: E402
from rvcoax.results.io.records import case_record  # noqa: E402
from rvcoax.results.io.sweep_files import CaseStore, case_inputs, inputs_sha256, sweep_inputs  # noqa: E402
from rvcoax.results.io.writers import write_json_atomic  # noqa: E402
from rvcoax.results.sweep import SweepSettings, prepare_model, run_sweep  # noqa: E402

N_CASES = 1000
REPEATS = 3


def best_of(function) -> float:
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    rig = load_rig()
    settings = SweepSettings()
    cases = grid_cases([0.05 * (i + 1) for i in range(40)], [8.0 * (j + 1) for j in range(25)])
    assert len(cases) == N_CASES
    prepared = prepare_model(rig, settings)
    common = sweep_inputs("benchmark", settings)
    hashes = [inputs_sha256(case_inputs("benchmark", case, settings, common)) for case in cases]
    scratch = Path(tempfile.mkdtemp(prefix=".bench_durable_", dir=Path(__file__).resolve().parent))
    load_before = os.getloadavg()[0]
    try:
        def solve_only():
            return run_sweep(rig, cases, settings, prepared=prepared)

        def records_only():
            run_sweep(rig, cases, settings, prepared=prepared, on_case=lambda i, c: case_record(c))

        records = [case_record(c) for c in solve_only().cases]

        def journal():
            store = CaseStore(scratch / "journal")
            store.clear()
            with store:
                for i, entry in enumerate(records):
                    store.save(i, hashes[i], entry)

        def file_per_case():
            folder = scratch / "files"
            shutil.rmtree(folder, ignore_errors=True)
            for i, entry in enumerate(records):
                write_json_atomic(folder / f"case_{i:04d}.json", {"format": 1, "inputs": hashes[i], "record": entry},
                                  durable=True)

        t_solve, t_records = best_of(solve_only), best_of(records_only)
        t_journal, t_files = best_of(journal), best_of(file_per_case)
        journal_bytes = (scratch / "journal" / "journal.jsonl").stat().st_size
        reading = CaseStore(scratch / "journal").load(hashes, "no model")
        assert len(reading.cases) == N_CASES and not reading.rejected
        start = time.perf_counter()
        CaseStore(scratch / "journal").load(hashes, "no model")
        t_read = time.perf_counter() - start
        end_to_end = scratch / "cli"
        start = time.perf_counter()
        run_durable_sweep(rig, cases, settings, "benchmark rig text", CaseStore(end_to_end / "cases"), resume=False)
        t_cli = time.perf_counter() - start
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    per = 1e3 / N_CASES
    figures = [
        ("sweep", f"{N_CASES} load cases, reference rig, beam model, superposition (model prepared once)"),
        ("solving only, per case", f"{t_solve * per:.3f} ms"),
        ("turning a case into its JSON record (needed for sweep.json anyway)", f"{(t_records - t_solve) * per:.3f} ms"),
        ("journal (CaseStore: checksummed line, fsync every 256 cases / 1 s), per case", f"{t_journal * per:.3f} ms"),
        ("file per case, atomic and fsync'ed each (the layout before the journal), per case", f"{t_files * per:.3f} ms"),
        ("journal size", f"{journal_bytes / N_CASES / 1e3:.1f} kB per case"),
        ("resume: read and verify the journal", f"{t_read * per:.3f} ms per case"),
        ("run_durable_sweep end to end (journal, assembly)", f"{t_cli * per:.3f} ms per case"),
        ("load average (1 min) before / after", f"{load_before:.2f} / {os.getloadavg()[0]:.2f}"),
    ]
    width = max(len(name) for name, _ in figures)
    for name, value in figures:
        print(f"{name:<{width}}  {value}")
    record("bench_durable_sweep.py: durable sweep results, per-case write vs solve cost", figures)


if __name__ == "__main__":
    main()
