"""Peak memory of a solid's stiffness assembly: triplets then sort (before issue 17) against chunks into the pattern.

The solid cantilever of bench_solid_scaling.py (the reference rig's output shaft, Ø35/30 mm steps over
160 mm, P2 tets) at ~50 k and ~300 k DOF (mesh sizes 4.4 and 2.3 mm). Each method runs in a fresh process on the same cached mesh:

- ``triplets``: :func:`rvcoax.fem.solid.stiffness_triplets` (900 entries per element) summed by
  :func:`rvcoax.fem.assembly.assemble_matrix`;
- ``chunked``: :func:`rvcoax.fem.solid.stiffness_matrix`, element matrices in blocks of 512 added
  straight into the precomputed 3 × 3-block pattern.

Reported: wall time, the peak of Python-visible allocations during the assembly (tracemalloc: numpy
arrays included), the rise of the process's resident high-water mark (VmHWM), the size of the final
matrix, and the largest difference between the two matrices (same pattern required).

Run: ``.venv/bin/python benchmarks/bench_assembly_memory.py [--sizes 50k,300k]``; appends to
benchmarks/RESULTS.md (``--no-record``: print only).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_solid_scaling import SEGMENTS  # noqa: E402
from machine import publish  # noqa: E402

SIZES = {"50k": 4.4, "300k": 2.3}  # label -> mesh size (mm) for the mirror-symmetric mesher (MESHER_VERSION 2)


def geometry(label: str):
    from rvcoax.geometry.meshing import SolidPartGeometry

    return SolidPartGeometry(f"cantilever_{label}", SEGMENTS, (), SIZES[label])


def _high_water_mb() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024.0
    return 0.0


def child(label: str, method: str, out: str) -> None:
    import tracemalloc

    import numpy as np

    from rvcoax.fem import solid
    from rvcoax.fem.assembly import assemble_matrix
    from rvcoax.geometry.meshing import mesh_part

    basis = solid.solid_basis(mesh_part(geometry(label)))
    before = _high_water_mb()
    tracemalloc.start()
    start = time.perf_counter()
    if method == "triplets":
        matrix = assemble_matrix(basis.N, [solid.stiffness_triplets(basis, 206e9, 0.28)])
    else:
        matrix = solid.stiffness_matrix(basis, 206e9, 0.28)
    seconds = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    size = matrix.data.nbytes + matrix.indices.nbytes + matrix.indptr.nbytes
    np.savez(out + ".npz", data=matrix.data, indices=matrix.indices, indptr=matrix.indptr)
    Path(out + ".json").write_text(json.dumps({"dofs": int(basis.N), "nnz": int(matrix.nnz), "seconds": seconds,
                                               "traced_peak_MB": peak / 1e6, "matrix_MB": size / 1e6,
                                               "hwm_rise_MB": _high_water_mb() - before}))


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child(*sys.argv[2:5])
        return
    import tempfile

    import numpy as np

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="50k,300k")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for label in args.sizes.split(","):
            if label not in SIZES:
                raise SystemExit(f"--sizes: {label} is not one of {', '.join(SIZES)}")
            found = {}
            for method in ("triplets", "chunked"):
                out = str(Path(folder) / f"{label}-{method}")
                subprocess.run([sys.executable, __file__, "--child", label, method, out], check=True,
                               env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
                found[method] = f = json.loads(Path(out + ".json").read_text())
                rows.append((f"{label} ({f['dofs']:,} DOF), {method}",
                             f"{f['seconds']:.2f} s; traced peak {f['traced_peak_MB']:.0f} MB = "
                             f"{f['traced_peak_MB'] / f['matrix_MB']:.2f} × the matrix ({f['matrix_MB']:.0f} MB, "
                             f"{f['nnz'] / 1e6:.1f} M nonzeros); resident high-water rise {f['hwm_rise_MB']:.0f} MB"))
            a, b = (np.load(str(Path(folder) / f"{label}-{m}.npz")) for m in ("triplets", "chunked"))
            same = np.array_equal(a["indptr"], b["indptr"]) and np.array_equal(a["indices"], b["indices"])
            diff = float(np.abs(a["data"] - b["data"]).max() / np.abs(a["data"]).max()) if same else float("nan")
            rows.append((f"{label}: same pattern / largest |ΔK| / largest |K|", f"{same} / {diff:.1e}"))
    publish("bench_assembly_memory.py: solid stiffness assembly, triplets against chunks into the pattern", rows,
            load_before, not args.no_record)


if __name__ == "__main__":
    main()
