"""numpy's requests for transparent huge pages: off where they make fresh memory slow to touch.

numpy asks the kernel for transparent huge pages (``madvise(MADV_HUGEPAGE)``) on every large
array. Where the kernel's ``/sys/kernel/mm/transparent_hugepage/defrag`` is ``madvise`` or
``defer+madvise``, such a request makes each first touch of a 2 MB region wait for the kernel to
reclaim and compact memory into a huge page. On the 2-core test machines (virtual machines, THP
``enabled = madvise``, ``defrag = madvise``) that stall is most of the system time of a solid
model's set-up, measured in a fresh process (benchmarks/RESULTS.md):

- 298 k DOF, element matrices + sparse assembly: 6.1–6.8 s with the requests, 2.3 s without
  (130 k DOF/s); mesh → displacement 22.5–23.6 s against 18.6 s;
- 53 k DOF: 1.44–1.82 s against 1.40–1.45 s, once earlier jobs had fragmented the memory.

Without the requests the arrays get ordinary 4 KiB pages (more page faults, no compaction). A
solve's results do not depend on it. This is a process-wide setting of numpy, so the library never
changes it on import: the ``rvcoax`` command calls :func:`avoid_compaction_stalls` once at start
(which also sets ``NUMPY_MADVISE_HUGEPAGE=0`` for the processes it starts, such as Dask workers),
and a program using the packages may do the same. An explicit ``NUMPY_MADVISE_HUGEPAGE`` in the
environment is the user's choice and is left alone.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

__all__ = ["STALLING_DEFRAG_MODES", "THP_DEFRAG", "avoid_compaction_stalls", "compaction_stalls", "defrag_mode",
           "selected_mode"]

THP_DEFRAG = Path("/sys/kernel/mm/transparent_hugepage/defrag")
STALLING_DEFRAG_MODES = frozenset({"madvise", "defer+madvise"})


def selected_mode(text: str) -> str | None:
    """The bracketed choice of a sysfs setting such as ``always defer [madvise] never``."""
    for word in text.split():
        if word.startswith("[") and word.endswith("]"):
            return word[1:-1]
    return None


def defrag_mode(defrag_path: Path = THP_DEFRAG) -> str | None:
    """The kernel's THP defrag mode (``madvise``, ``always`` …), or None where it cannot be read."""
    try:
        return selected_mode(defrag_path.read_text())
    except OSError:  # not Linux, or no THP support
        return None


def compaction_stalls(defrag_path: Path = THP_DEFRAG) -> bool:
    """Whether numpy's huge-page requests make first touches wait for compaction on this machine."""
    return defrag_mode(defrag_path) in STALLING_DEFRAG_MODES


def avoid_compaction_stalls(defrag_path: Path = THP_DEFRAG) -> bool:
    """Stop numpy's huge-page requests where they stall (see the module text); True if it did.

    Parameters
    ----------
    defrag_path : Path
        The kernel's transparent-huge-page defrag setting (read to see whether requests stall).

    Returns
    -------
    bool
        True when the requests were switched off (``NUMPY_MADVISE_HUGEPAGE=0`` set for this process and
        the processes it starts); False when they do not stall here or the user set the variable.
    """
    if "NUMPY_MADVISE_HUGEPAGE" in os.environ or not compaction_stalls(defrag_path):
        return False
    os.environ["NUMPY_MADVISE_HUGEPAGE"] = "0"  # child processes (Dask workers) start the same way
    if "numpy" not in sys.modules:  # numpy reads the variable when it is first imported
        return True
    from rvcoax.fem.compat import numpy_madvise_switch

    setter = numpy_madvise_switch()
    if setter is None:  # pragma: no cover - numpy without the switch
        return False
    setter(False)
    return True
