"""The C heap's policy (fem/memory.py): a model small against the memory available keeps freed heap memory for
reuse (glibc ``mallopt``), a large one gives it back; the rule, the calls it makes, and the fallback without glibc."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

from rvcoax.fem import memory

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc's malloc.h


class Recorder:
    """Stands for glibc's ``mallopt`` or ``malloc_trim``: records its calls, answers ``result``."""

    def __init__(self, result: int = 1):
        self.calls: list[tuple] = []
        self.result = result

    def __call__(self, *arguments):
        self.calls.append(arguments)
        return self.result


@pytest.fixture
def libc(monkeypatch):
    """Recorders in place of mallopt and malloc_trim, the heap's state restored afterwards."""
    mallopt, trim = Recorder(), Recorder()
    monkeypatch.setattr(memory, "_mallopt", lambda: mallopt)
    monkeypatch.setattr(memory, "_malloc_trim", lambda: trim)
    monkeypatch.setattr(memory, "_heap", {"kept": False})
    return mallopt, trim


@pytest.mark.parametrize(("peak", "available", "keep"), [
    (1.87e9, 24.1e9, True),  # the hybrid reference rig's estimate on a 24 GB machine
    (7.15e9, 24.1e9, False),  # the all-solid reference rig's
    (2.5e9, 10e9, True),  # exactly the share
    (2.5e9 + 1.0, 10e9, False),
    (1e6, None, False),  # memory available unknown (not Linux)
    (None, 24e9, False),
    (1e6, 0.0, False),
])
def test_the_rule_keeps_freed_memory_only_for_a_model_small_against_the_memory_available(peak, available, keep):
    policy = memory.heap_policy(peak, available)
    assert policy.keep is keep
    assert ("kept for reuse" if keep else "goes back") in policy.reason
    if peak is not None and available:
        assert f"{peak / 1e9:.3g} GB" in policy.reason and f"{available / 1e9:.3g} GB available" in policy.reason


def test_keeping_raises_both_thresholds_and_stops_trimming_until_given_back(libc):
    mallopt, trim = libc
    policy = memory.apply_heap_policy(1e9, available_bytes=24e9)
    assert policy.keep and memory.heap_kept()
    assert mallopt.calls == [(M_MMAP_THRESHOLD, 2**31 - 1), (M_TRIM_THRESHOLD, 2**31 - 1)]
    assert memory.return_free_heap() is False and trim.calls == []  # PARDISO's trims are skipped
    assert memory.apply_heap_policy(1e9, available_bytes=24e9).keep and len(mallopt.calls) == 2  # set once
    policy = memory.apply_heap_policy(20e9, available_bytes=24e9)  # a large model next: glibc's thresholds
    assert not policy.keep and not memory.heap_kept()
    assert mallopt.calls[2:] == [(M_MMAP_THRESHOLD, 32 << 20), (M_TRIM_THRESHOLD, 64 << 20)]
    assert trim.calls == [(0,)]  # what the small model kept goes back at once
    assert memory.return_free_heap() is True and trim.calls == [(0,), (0,)]


def test_a_large_model_leaves_glibc_untouched(libc):
    mallopt, trim = libc
    policy = memory.apply_heap_policy(7.15e9, available_bytes=24.1e9)
    assert not policy.keep and "more than 0.25" in policy.reason
    assert mallopt.calls == [] and trim.calls == []  # glibc's own dynamic thresholds stay
    assert memory.return_free_heap() is True and trim.calls == [(0,)]


def test_without_glibc_nothing_changes_and_the_policy_says_why(monkeypatch):
    monkeypatch.setattr(memory, "_mallopt", lambda: None)
    monkeypatch.setattr(memory, "_malloc_trim", lambda: None)
    monkeypatch.setattr(memory, "_heap", {"kept": False})
    policy = memory.apply_heap_policy(1e6, available_bytes=24e9)
    assert not policy.keep and "mallopt" in policy.reason
    assert not memory.heap_kept() and memory.return_free_heap() is False
    assert memory.apply_heap_policy(20e9, available_bytes=24e9).keep is False  # nothing to set: no error either


def test_a_glibc_that_refuses_the_value_keeps_its_behaviour(libc):
    mallopt, trim = libc
    mallopt.result = 0
    policy = memory.apply_heap_policy(1e6, available_bytes=24e9)
    assert not policy.keep and not memory.heap_kept()
    assert (M_MMAP_THRESHOLD, 32 << 20) in mallopt.calls  # back to glibc's thresholds
    assert memory.return_free_heap() is True


def test_the_reference_rigs_models_fall_on_either_side_of_the_rule():
    """On a 24 GB machine the hybrid and beam models keep freed memory, the all-solid model (3.9 GB measured) does
    not: its peak stays as without the policy."""
    from rvcoax import load_rig
    from rvcoax.geometry.model.preflight import peak_memory_bytes

    rig = load_rig()
    available = 24e9
    assert memory.heap_policy(peak_memory_bytes(rig, "beam"), available).keep
    assert memory.heap_policy(peak_memory_bytes(rig, "hybrid"), available).keep
    assert not memory.heap_policy(peak_memory_bytes(rig, "solid"), available).keep
    assert peak_memory_bytes(rig, "beam") < peak_memory_bytes(rig, "hybrid") < peak_memory_bytes(rig, "solid")


@pytest.mark.skipif(not sys.platform.startswith("linux") or memory._mallopt() is None, reason="glibc only")
def test_a_kept_heap_serves_the_next_array_without_page_faults():
    """In a fresh process: a 64 MB array allocated and freed 8 times faults its pages in each time with glibc's
    defaults (above the 32 MB mmap threshold), once with the heap kept; and given back, resident memory falls."""
    script = textwrap.dedent("""
        import resource
        import numpy as np
        from rvcoax.fem import memory

        def faults(repeats=8):
            before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
            for _ in range(repeats):
                a = np.ones(8 << 20)
                del a
            return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before

        def resident_mb():
            with open("/proc/self/status") as status:
                return next(int(line.split()[1]) / 1024 for line in status if line.startswith("VmRSS:"))

        default = faults()
        assert memory.keep_freed_heap() and memory.heap_kept()
        kept = faults()
        held = resident_mb()
        assert memory.keep_freed_heap(False) and not memory.heap_kept()
        print(default, kept, held - resident_mb())
    """)
    environment = {**os.environ, "NUMPY_MADVISE_HUGEPAGE": "0"}  # 4 KiB pages, as the rvcoax command has them
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60, check=True,
                            env=environment)
    default, kept, given_back_mb = (float(word) for word in result.stdout.split())
    pages = 8 * (64 << 20) / 4096  # one first touch per 4 KiB page of each array
    assert default > 0.9 * pages
    assert kept < 0.3 * pages
    assert given_back_mb > 50.0
