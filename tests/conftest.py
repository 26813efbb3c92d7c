"""Test-wide settings: meshes are cached in a per-session temporary folder, never in the user's cache."""

import os

import pytest


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


# What each test module costs, so that `make test-fast` (-m "not slow and not dask and not render") can skip
# the expensive ones; tests also carry these marks one by one where only some of a module is expensive.
# The figures behind the table are the suite's --durations, recorded in benchmarks/RESULTS.md.
MODULE_MARKS = {
    "test_discrepancy": ("slow",),
    "test_discrepancy_robustness": ("slow",),
    "test_hybrid": ("slow",),
    "test_golden_results": ("slow", "subprocess"),
    "test_montecarlo": ("dask", "slow"),
    "test_pictures": ("render",),
    "test_package": ("subprocess",),
    "test_examples": ("subprocess",),
    "test_blas_threads": ("subprocess",),
}


def pytest_collection_modifyitems(config, items):
    for item in items:
        for mark in MODULE_MARKS.get(item.module.__name__.rsplit(".", 1)[-1], ()):
            item.add_marker(getattr(pytest.mark, mark))
