"""OpenBLAS held to one thread by the rvcoax command, never by importing the packages."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

# cost, for `make test-fast` (-m "not slow and not dask and not render")
pytestmark = [pytest.mark.subprocess]

CHILD = """
import json, os, sys
import numpy, scipy.linalg  # both OpenBLAS copies loaded
from rvcoax.fem import blas_threads
before = blas_threads.openblas_thread_counts()
changed = blas_threads.single_threaded_openblas() if sys.argv[1] == "call" else None
print(json.dumps({"before": before, "changed": changed, "after": blas_threads.openblas_thread_counts(),
                  "environment": os.environ.get("OPENBLAS_NUM_THREADS")}))
"""


def run_child(action: str, environment: dict[str, str]) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")}
    env.update(environment)
    out = subprocess.run([sys.executable, "-c", CHILD, action], env=env, capture_output=True, text=True,
                         check=True, cwd=os.path.dirname(os.path.dirname(os.path.dirname(__file__))))
    return json.loads(out.stdout)


@pytest.fixture(scope="module")
def cores():
    return len(os.sched_getaffinity(0))


def test_importing_leaves_openblas_alone(cores):
    result = run_child("import", {})
    assert result["after"] == result["before"] and result["environment"] is None
    assert all(n == min(cores, 64) for n in result["before"])  # OpenBLAS's default: a thread per core


def test_the_call_holds_every_openblas_to_one_thread_and_tells_child_processes():
    result = run_child("call", {})
    assert result["changed"] is True
    assert len(result["after"]) >= 2 and set(result["after"]) == {1}  # numpy's and scipy's copies
    assert result["environment"] == "1"


def test_an_explicit_setting_is_respected():
    result = run_child("call", {"OPENBLAS_NUM_THREADS": "2"})
    assert result["changed"] is False and result["environment"] == "2"
    assert set(result["after"]) == {2}


def test_the_rvcoax_command_calls_it(monkeypatch):
    import rvcoax.fem
    from rvcoax.results.cli import app as cli

    calls = []  # the command takes both from the public namespace rvcoax.fem
    monkeypatch.setattr(rvcoax.fem, "single_threaded_openblas", lambda: calls.append("openblas"))
    monkeypatch.setattr(rvcoax.fem, "avoid_compaction_stalls", lambda: calls.append("hugepages"))
    monkeypatch.setattr(cli, "app", lambda: calls.append("app"))
    cli.run()
    assert calls == ["hugepages", "openblas", "app"]
