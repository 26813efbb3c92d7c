"""numpy's huge-page requests: read the kernel's THP defrag mode, switch them off only where they stall."""

from __future__ import annotations

import os

import pytest
from numpy._core import multiarray

from rvcoax.fem import hugepages


@pytest.fixture
def numpy_hugepage_flag():
    """Restore numpy's huge-page flag and NUMPY_MADVISE_HUGEPAGE after the test, whatever it did to them."""
    before = multiarray._set_madvise_hugepage(True)
    multiarray._set_madvise_hugepage(before)
    environment = os.environ.get("NUMPY_MADVISE_HUGEPAGE")
    yield
    multiarray._set_madvise_hugepage(before)
    if environment is None:
        os.environ.pop("NUMPY_MADVISE_HUGEPAGE", None)
    else:
        os.environ["NUMPY_MADVISE_HUGEPAGE"] = environment


def defrag_file(tmp_path, text: str):
    path = tmp_path / "defrag"
    path.write_text(text + "\n")
    return path


@pytest.mark.parametrize(("text", "mode", "stalls"), [
    ("always defer defer+madvise [madvise] never", "madvise", True),
    ("always defer [defer+madvise] madvise never", "defer+madvise", True),
    ("[always] defer defer+madvise madvise never", "always", False),
    ("always [defer] defer+madvise madvise never", "defer", False),
    ("always defer defer+madvise madvise [never]", "never", False),
])
def test_defrag_mode_decides_whether_requests_stall(tmp_path, text, mode, stalls):
    assert hugepages.selected_mode(text) == mode
    assert hugepages.compaction_stalls(defrag_file(tmp_path, text)) is stalls


def test_missing_sysfs_file_means_no_stall(tmp_path):
    assert hugepages.compaction_stalls(tmp_path / "absent") is False
    assert hugepages.selected_mode("no brackets here") is None


def test_requests_are_switched_off_where_they_stall(tmp_path, monkeypatch, numpy_hugepage_flag):
    monkeypatch.delenv("NUMPY_MADVISE_HUGEPAGE", raising=False)
    multiarray._set_madvise_hugepage(True)
    assert hugepages.avoid_compaction_stalls(defrag_file(tmp_path, "always [madvise] never")) is True
    assert multiarray._set_madvise_hugepage(False) is False  # it was off already
    assert os.environ["NUMPY_MADVISE_HUGEPAGE"] == "0"  # inherited by the processes rvcoax starts


def test_requests_are_left_alone_where_they_do_not_stall(tmp_path, monkeypatch, numpy_hugepage_flag):
    monkeypatch.delenv("NUMPY_MADVISE_HUGEPAGE", raising=False)
    multiarray._set_madvise_hugepage(True)
    assert hugepages.avoid_compaction_stalls(defrag_file(tmp_path, "[always] madvise never")) is False
    assert multiarray._set_madvise_hugepage(True) is True


def test_an_explicit_environment_setting_wins(tmp_path, monkeypatch, numpy_hugepage_flag):
    monkeypatch.setenv("NUMPY_MADVISE_HUGEPAGE", "1")
    multiarray._set_madvise_hugepage(True)
    assert hugepages.avoid_compaction_stalls(defrag_file(tmp_path, "always [madvise] never")) is False
    assert multiarray._set_madvise_hugepage(True) is True
