"""Test-wide settings: meshes are cached in a per-session temporary folder, never in the user's cache.

What a test costs is declared in its own module (``pytestmark``, or on the tests that need it: ``slow``,
``render``, ``dask``, ``subprocess``; tests/package/test_package.py checks it), so that `make test-fast`
(-m "not slow and not dask and not render") can leave the expensive ones out. Shared helpers are in
tests/support/ (on pytest's ``pythonpath``).
"""

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
