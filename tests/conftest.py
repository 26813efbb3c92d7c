"""Test-wide settings: meshes are cached in a per-session temporary folder, never in the user's cache.

What a test costs is declared in its own module (``pytestmark``, or on the tests that need it: ``slow``,
``render``, ``dask``, ``subprocess``; tests/package/test_package.py checks it), so that `make test-fast`
(-m "not slow and not dask and not render") can leave the expensive ones out. Shared helpers are in
tests/support/ (on pytest's ``pythonpath``).

Parallel runs (pytest-xdist, ``make test``: ``-n 2 --dist loadfile``): each worker is its own session, so it
gets its own mesh cache (``tmp_path_factory`` gives each worker its own base folder: a cache entry found or
missed never depends on what another worker did), and the tests of one file stay on one worker (the
module fixtures, sweeps and meshes mostly, are built once; the Dask cluster's tests keep their order). The
BLAS and OpenMP pools of a worker get the cores divided among the workers (unless the environment sets them),
so that two workers on two cores do not run four spinning threads.
"""

import os

import pytest


def _share_the_cores_among_workers() -> None:
    """In an xdist worker (pytest-xdist sets PYTEST_XDIST_WORKER_COUNT before this file is imported, and before
    any test module loads numpy): OPENBLAS/OMP/MKL_NUM_THREADS = cores // workers, where the user has not set them."""
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "0") or 0)
    if workers < 2:
        return
    threads = str(max(1, len(os.sched_getaffinity(0)) // workers))
    for key in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(key, threads)


_share_the_cores_among_workers()


@pytest.fixture(scope="session", autouse=True)
def _mesh_cache(tmp_path_factory):
    folder = tmp_path_factory.mktemp("mesh-cache")
    previous = os.environ.get("RVCOAX_CACHE_DIR")
    os.environ["RVCOAX_CACHE_DIR"] = str(folder)
    yield folder
    if previous is None:
        os.environ.pop("RVCOAX_CACHE_DIR", None)
    else:
        os.environ["RVCOAX_CACHE_DIR"] = previous


@pytest.fixture(autouse=True)
def _heap_policy_per_test():
    """A test that runs a command in this process may leave the C heap keeping freed memory (the policy the command
    sets for a small model, rvcoax.fem.memory): glibc's behaviour again after it, so that no later test of this worker
    inherits it."""
    yield
    from rvcoax.fem import memory

    if memory.heap_kept():
        memory.keep_freed_heap(False)
