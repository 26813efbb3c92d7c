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


FAKE_ADDRESS = 4096 * 1000 + 16  # where a recorded malloc says it put a block (like glibc: 16 bytes into a page)
MADV_POPULATE_WRITE = 23


@pytest.fixture
def libc(monkeypatch):
    """Recorders in place of mallopt and malloc_trim (and of malloc, free and madvise, so that nothing is mapped), the
    heap's state restored afterwards."""
    mallopt, trim = Recorder(), Recorder()
    monkeypatch.setattr(memory, "_mallopt", lambda: mallopt)
    monkeypatch.setattr(memory, "_malloc_trim", lambda: trim)
    monkeypatch.setattr(memory, "_heap_calls", lambda: (Recorder(FAKE_ADDRESS), Recorder(None), Recorder(0)))
    monkeypatch.setattr(memory, "_heap", {"kept": False})
    return mallopt, trim


@pytest.fixture
def heap_calls(monkeypatch, libc):
    """The malloc, free and madvise recorders prefault_heap gets."""
    calls = (Recorder(FAKE_ADDRESS), Recorder(None), Recorder(0))
    monkeypatch.setattr(memory, "_heap_calls", lambda: calls)
    return calls


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


@pytest.mark.parametrize(("peak", "ahead"), [
    (1.87e9, int(0.35 * 1.87e9)),  # the hybrid reference rig: 0.65 GB, below the 1.13 GB its heap then holds
    (7.15e9, 1 << 30),  # at most 1 GiB
    (0.2e9, 0),  # a beam model: too few pages to pay for a thread
    (None, 0),
])
def test_a_share_of_the_estimated_peak_is_mapped_ahead(peak, ahead):
    assert memory.prefault_bytes(peak) == ahead


def test_a_kept_heap_gets_its_next_pages_mapped_ahead_by_a_thread_that_writes_nothing(heap_calls):
    malloc, free, madvise = heap_calls
    memory.apply_heap_policy(1.87e9, available_bytes=24e9)
    running = memory._heap["prefault"]
    assert running is not None
    running[0].join()
    n_bytes = memory.prefault_bytes(1.87e9)
    assert malloc.calls == [(n_bytes,)] and free.calls == [(FAKE_ADDRESS,)]  # freed at once: free memory of the heap
    start, end = 4096 * 1001, (FAKE_ADDRESS + n_bytes) // 4096 * 4096  # the block's whole pages
    assert [c[2] for c in madvise.calls] == [MADV_POPULATE_WRITE] * len(madvise.calls)  # asks for pages, never writes
    assert madvise.calls[0][0] == start and sum(c[1] for c in madvise.calls) == end - start
    assert all(c[1] <= 64 << 20 for c in madvise.calls)  # in chunks: a stop request waits for one at most
    memory.keep_freed_heap(False)
    assert memory._heap["prefault"] is None


def test_nothing_is_mapped_ahead_for_a_heap_that_is_not_kept_or_off_the_main_thread(heap_calls):
    import threading

    malloc, _, _ = heap_calls
    assert memory.prefault_heap(256 << 20) is None  # not kept
    memory.apply_heap_policy(7.15e9, available_bytes=24e9)  # not kept
    assert memory.keep_freed_heap()
    assert memory.prefault_heap(0) is None
    elsewhere = []
    worker = threading.Thread(target=lambda: elsewhere.append(memory.prefault_heap(256 << 20)))
    worker.start()
    worker.join()
    assert elsewhere == [None] and malloc.calls == []


def test_a_stop_request_ends_the_thread_after_its_chunk(heap_calls):
    import threading

    _, _, madvise = heap_calls
    entered, release = threading.Event(), threading.Event()

    def slow(*arguments):
        madvise.calls.append(arguments)
        entered.set()
        release.wait(10)
        return 0

    memory._heap_calls = lambda: (heap_calls[0], heap_calls[1], slow)  # restored by the fixture's monkeypatch
    assert memory.keep_freed_heap()
    thread = memory.prefault_heap(1 << 30)
    stop = memory._heap["prefault"][1]
    assert entered.wait(10)
    stopper = threading.Thread(target=memory.keep_freed_heap, args=(False,))
    stopper.start()
    assert stop.wait(10)  # asked to stop while on its first chunk
    release.set()
    stopper.join(10)
    assert not thread.is_alive() and len(madvise.calls) == 1  # 16 chunks asked for, one done


@pytest.mark.subprocess
@pytest.mark.skipif(not sys.platform.startswith("linux") or memory._mallopt() is None, reason="glibc only")
def test_a_kept_heap_serves_the_next_array_without_page_faults():
    """In a fresh process: a 64 MB array allocated and freed 8 times faults its pages in each time with glibc's
    defaults (above the 32 MB mmap threshold), once with the heap kept; pages mapped ahead by the prefault thread are
    not faulted in again by the array that takes them; given back, resident memory falls."""
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
        before = resident_mb()
        memory.prefault_heap(192 << 20).join()  # mapped ahead; then an array too large for the 64 MB freed above
        mapped_ahead = resident_mb() - before
        thread_faults = resource.getrusage(resource.RUSAGE_THREAD).ru_minflt
        b = np.ones(20 << 20)
        ahead = resource.getrusage(resource.RUSAGE_THREAD).ru_minflt - thread_faults
        last = b[-1]
        del b
        held = resident_mb()
        assert memory.keep_freed_heap(False) and not memory.heap_kept()
        print(default, kept, held - resident_mb(), mapped_ahead, ahead, last)
    """)
    environment = {**os.environ, "NUMPY_MADVISE_HUGEPAGE": "0"}  # 4 KiB pages, as the rvcoax command has them
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60, check=True,
                            env=environment)
    default, kept, given_back_mb, mapped_ahead_mb, ahead, _ = (float(word) for word in result.stdout.split())
    pages = 8 * (64 << 20) / 4096  # one first touch per 4 KiB page of each array
    assert default > 0.9 * pages
    assert kept < 0.3 * pages
    assert given_back_mb > 150.0  # the 192 MB block and the arrays' pages, free again
    # a kernel with MADV_POPULATE_WRITE (Linux 5.14) mapped the 128 MB of the block beyond the resident 64 MB freed
    # above: the 160 MB array found its pages there
    if mapped_ahead_mb > 100.0:
        assert ahead < 0.2 * (160 << 20) / 4096
