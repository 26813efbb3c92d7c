"""The reference rig's result files are what they were before the package moved under ``rvcoax``.

``tests/golden/`` holds the files ``rvcoax sweep``, ``rvcoax check`` and ``rvcoax sweep --model hybrid``
wrote on the reference rig at commit d73afe7, the last one before the library restructure (issue 13),
made on a 2-core AMD EPYC with two BLAS threads. On that machine and thread count the files after the
move were compared byte for byte (see ``benchmarks/RESULTS.md``). Here, on any machine, every key,
column, string and the layout must be identical, and every number equal to the accuracy of its solve:
the floating-point rounding of a factorisation differs between CPUs and thread counts (the hybrid
model's files differ at 3e-7 relative between one and two PARDISO threads on the same machine, on
values 1e-6 of their column's largest), so a byte comparison across machines would test the CPU, not
the code.

``tests/golden/hybrid/`` was written again on this branch (issue 17, a 2-core AMD EPYC, two BLAS threads) when
the solid meshes became mirror-symmetric about the planes through the axis (``rvcoax.geometry.meshing``): a
pure torque no longer moves a shaft sideways, which changed the reference rig's hybrid Y by at most 0.04 %
(input) and 0.08 % (output), and the DOF count from 87,687 to 108,981. The old files' own solve error (the
dense tie blocks' factorisation: 1.2e-7 of the input end-rotation column against an extended-precision
solution) was above this comparison's 1e-7; the tie multipliers' solve is 30× closer.

Issue 27 changed the hybrid solve to a Cholesky factor with the ties as a low-rank update (``rvcoax.fem.woodbury``):
only ``/model/solver`` in ``hybrid/sweep.json`` was rewritten (the solver's name); the numbers are the old files',
which the new solve meets within 3.4e-8 of each column's largest value (the old solve on the same machine: 1.5e-8).
"""

import subprocess
import sys
from pathlib import Path

import pytest
from golden_files import GOLDEN, compare_result_file

# cost, for `make test-fast` (-m "not slow and not dask and not render")
pytestmark = [pytest.mark.slow, pytest.mark.subprocess]


def _rvcoax() -> str:
    return str(Path(sys.executable).with_name("rvcoax"))


COMMANDS = {
    "sweep": ["sweep"],
    "check": ["check"],
    "hybrid": ["sweep", "--model", "hybrid"],
}


@pytest.mark.parametrize("name", list(COMMANDS))
def test_reference_rig_files_match_the_files_written_before_the_restructure(name, tmp_path):
    out = tmp_path / name
    done = subprocess.run([_rvcoax(), *COMMANDS[name], "--out", str(out)], capture_output=True, text=True)
    assert done.returncode in (0, 3), done.stdout + done.stderr
    golden_files = sorted((GOLDEN / name).iterdir())
    assert golden_files
    for golden_file in golden_files:
        produced = out / golden_file.name
        assert produced.is_file(), f"{name}: {golden_file.name} was not written"
        compare_result_file(golden_file, produced)
