"""The command line's boundary checks: numeric options, torque lists, scheduler addresses, write errors."""

from __future__ import annotations

import errno
import os

import pytest
from hostile._files import FORCES
from typer.testing import CliRunner

from rvcoax.results.cli.app import app
from rvcoax.results.cli.support import UserError, finite_option, scheduler_address, torque_list, write_error_text
from rvcoax.results.io import writers


@pytest.mark.parametrize(("value", "expected"), [("4", 4.0), (" 0.05 ", 0.05), ("1e3", 1000.0), (2, 2.0)])
def test_finite_option_accepts_plain_numbers_in_range(value, expected):
    assert finite_option(value, "--mesh-size-mm", 0.05, 1000.0, "mm") == expected


@pytest.mark.parametrize(("value", "words"), [
    ("nan", "not a finite number"), (float("inf"), "not a finite number"), ("1e-300", "outside the range"),
    ("1_00", "digit separators"), ("٧٠", "not ASCII"), ("", "the value is empty"), (True, "is not a number"),
])
def test_finite_option_refuses_with_the_option_range_and_unit(value, words):
    with pytest.raises(UserError) as caught:
        finite_option(value, "--mesh-size-mm", 0.05, 1000.0, "mm")
    assert str(caught.value).startswith("--mesh-size-mm: ")
    assert words in str(caught.value) and "0.05 … 1000 mm" in str(caught.value)


def test_finite_option_integers_and_open_ranges():
    assert finite_option("7", "--seed", 0, 10, integer=True) == 7
    assert isinstance(finite_option("7", "--seed", 0, 10, integer=True), int)
    with pytest.raises(UserError, match="not a whole number"):
        finite_option("7.0", "--seed", 0, 10, integer=True)
    with pytest.raises(UserError, match=r"give a number in \(0, 1\)"):
        finite_option("1", "--warp-fraction", 0.0, 1.0, exclusive=True)
    assert finite_option("0.999", "--warp-fraction", 0.0, 1.0, exclusive=True) == 0.999


def test_torque_list_names_the_empty_item():
    assert torque_list(" 0.5, 1.43", "--t1") == [0.5, 1.43]
    with pytest.raises(UserError, match=r"--t1 '1,,2', item 2 of 3: is empty"):
        torque_list("1,,2", "--t1")
    with pytest.raises(UserError, match=r"item 1 of 1: 2e\+06 N·m is beyond"):
        torque_list("2e6", "--t1")


@pytest.mark.parametrize("address", ["local", "serial", "tcp://127.0.0.1:8786", "tcp://[::1]:8786"])
def test_scheduler_address_accepts(address):
    assert scheduler_address(address) == address


def test_a_tls_scheduler_needs_the_tls_settings_of_dask():
    """tls:// without certificates ended in distributed's TypeError about ssl_context; with them it is accepted."""
    import dask.config

    with dask.config.set({"distributed.comm.tls.ca-file": None, "distributed.comm.tls.client.cert": None}), \
            pytest.raises(UserError, match=r"--scheduler: 'tls://scheduler.lan:8786': a tls:// scheduler needs"):
        scheduler_address("tls://scheduler.lan:8786")
    with dask.config.set({"distributed.comm.tls.ca-file": "ca.pem", "distributed.comm.tls.client.cert": "me.pem"}):
        assert scheduler_address("tls://scheduler.lan:8786") == "tls://scheduler.lan:8786"


@pytest.mark.parametrize(("address", "words"), [("garbage://x", "protocol 'garbage'"), ("tcp://x", "HOST:PORT"),
                                                ("tcp://x:0", "port 1 … 65535"), ("tcp://x:８７", "port 1 … 65535"),
                                                ("dask", "is not auto, local, serial")])
def test_scheduler_address_refuses(address, words):
    with pytest.raises(UserError, match="--scheduler") as caught:
        scheduler_address(address)
    assert words in str(caught.value)


def test_write_error_text_never_says_none():
    assert write_error_text(OSError(errno.ENOSPC, "No space left on device")) == \
        "cannot write the result files (--out): no space left on device"
    assert write_error_text(OSError(errno.EACCES, "Permission denied", "out/x.csv")) == \
        "cannot write out/x.csv: permission denied"


def test_full_disk_names_the_file_being_written(tmp_path, monkeypatch):
    """ENOSPC comes from write()/fsync() without a file name: the writer names the result file, the CLI the reason."""
    def full_disk(descriptor):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(writers.os, "fsync", full_disk)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["chain-error", "--forces", str(FORCES), "--tilt", "none", "--out", str(out)])
    assert result.exit_code == 2, result.output
    message = " ".join(result.stderr.split())
    assert message == f"error: cannot write {out / 'chain_error.csv'}: no space left on device"
    left = list(out.iterdir()) if out.exists() else []
    assert not [p for p in left if p.name.endswith(".tmp")], left  # the temporary file is removed
    assert not (out / "chain_error.csv").exists()
