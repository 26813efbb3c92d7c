"""OpenBLAS with one thread, so that it does not take the cores MKL PARDISO's threads need.

numpy and scipy each bring their own OpenBLAS, which starts a thread per core and, after every
call, keeps those threads spinning for a while in case more work follows. On a 2-core machine the
spinning thread holds the core that MKL's OpenMP threads need for PARDISO: a solve at 52 k DOF took
0.034–0.051 s right after a numpy ``dot``, ``norm`` or 400 × 400 product, and 0.020–0.025 s with
OpenBLAS held to one thread (fem/pardiso.py; benchmarks/RESULTS.md has the figures).

Our dense BLAS work is small (the element matrices are batches of 30 × 4 products, calibration
and regression fits have tens of unknowns), so one OpenBLAS thread costs nothing measurable there.
Like :mod:`rvcoax.fem.hugepages` this is a process-wide setting, so the library never changes it on
import: the ``rvcoax`` command calls :func:`single_threaded_openblas` once at start (which also
sets ``OPENBLAS_NUM_THREADS=1`` for the processes it starts, and for an OpenBLAS loaded later), and
a program using the packages may do the same. An explicit ``OPENBLAS_NUM_THREADS`` in the
environment is the user's choice and is left alone.
"""

from __future__ import annotations

import os

__all__ = ["ENVIRONMENT_KEY", "openblas_thread_counts", "single_threaded_openblas"]

ENVIRONMENT_KEY = "OPENBLAS_NUM_THREADS"


def openblas_thread_counts() -> list[int]:
    """Threads of each OpenBLAS loaded in this process (numpy's, scipy's …), as threadpoolctl sees them."""
    from threadpoolctl import threadpool_info

    return [pool["num_threads"] for pool in threadpool_info() if pool["internal_api"] == "openblas"]


def single_threaded_openblas() -> bool:
    """Hold every OpenBLAS of this process (and of its children) to one thread; True if it did.

    Does nothing where ``OPENBLAS_NUM_THREADS`` is already set.

    Returns
    -------
    bool
        True when the thread count was set; False when the user's ``OPENBLAS_NUM_THREADS`` stands.
    """
    if ENVIRONMENT_KEY in os.environ:
        return False
    os.environ[ENVIRONMENT_KEY] = "1"  # read by an OpenBLAS when it loads: later ones and child processes
    from threadpoolctl import ThreadpoolController

    ThreadpoolController().select(internal_api="openblas").limit(limits=1)  # the ones loaded already
    return True
