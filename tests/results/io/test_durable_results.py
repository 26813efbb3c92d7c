"""Issue 12, parts 5 and 6: size estimates made before the work, and output folders that one command
at a time writes into (the journal's trust checks run through the hostile corpus, class ``trust``)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from rvcoax.geometry.model import workload
from rvcoax.geometry.model.beam import build_rig_model
from rvcoax.geometry.model.workload import available_memory_bytes
from rvcoax.geometry.rigfile import load_rig, parse_rig, reference_rig_text
from rvcoax.results.cli.app import app
from rvcoax.results.io.out_lock import FolderLockedError, output_folder_lock


def flat(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize("element_mm", [5.0, 1.0, 0.3])
def test_beam_nodes_are_counted_before_building_as_an_upper_bound(element_mm):
    text = reference_rig_text().replace("max_element_length_mm = 5.0", f"max_element_length_mm = {element_mm}")
    rig = parse_rig(tomllib.loads(text), "edited reference rig")
    counted = workload.beam_size(rig).nodes
    built = build_rig_model(rig).structure.n_nodes
    assert built <= counted <= 1.5 * built + 200, (counted, built)


def test_sweeps_up_to_the_largest_fitting_size_are_accepted_and_twice_that_refused():
    largest = workload._largest_fitting(workload.sweep_workload)  # (memory varies a little between calls)
    assert workload._fits(workload.sweep_workload(largest // 2), available_memory_bytes())
    workload.check_cases(largest // 2, "--cases")  # accepted
    with pytest.raises(workload.WorkloadError, match=r"--cases: .* load cases would take about .* split the load"):
        workload.check_cases(2 * largest, "--cases")


def test_reference_rig_is_small_and_needs_no_announcement():
    work = workload.beam_size(load_rig()).workload(5.0)
    assert work.seconds < workload.REPORT_AFTER_S and workload.rig_problem(load_rig()) is None


def test_a_second_lock_on_the_same_folder_is_refused_and_released_after(tmp_path):
    with output_folder_lock(tmp_path / "out"):
        with pytest.raises(FolderLockedError, match=rf"process {os.getpid()}"):
            with output_folder_lock(tmp_path / "out"):
                pass
    with output_folder_lock(tmp_path / "out"):  # released
        pass
    assert not (tmp_path / "out").exists()  # created for a command that wrote nothing: removed again


@pytest.mark.subprocess
def test_two_sweeps_into_one_folder_the_second_is_refused_and_the_first_keeps_its_cases(tmp_path):
    cases = tmp_path / "cases.csv"
    cases.write_text("T1_input_Nm,T2_output_Nm\n" + "".join(f"{0.1 * i:.1f},{10 * i}\n" for i in range(1, 9)),
                     encoding="utf-8")
    out = tmp_path / "out"
    script = Path(sys.executable).with_name("rvcoax")
    first = subprocess.Popen([str(script), "sweep", "--cases", str(cases), "--out", str(out)],
                             env=dict(os.environ, RVCOAX_CASE_DELAY_S="0.3"), stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE)
    journal = out / "cases" / "journal.jsonl"
    deadline = time.monotonic() + 90
    try:
        while not (journal.exists() and journal.stat().st_size > 0):
            assert first.poll() is None, first.stderr.read()
            assert time.monotonic() < deadline, "no case journalled in 90 s"
            time.sleep(0.05)
        second = CliRunner().invoke(app, ["sweep", "--cases", str(cases), "--out", str(out)])
        assert second.exit_code == 2, second.output
        message = flat(second.stderr)
        assert f"--out {out}: another rvcoax command (process {first.pid}) is writing into this folder" in message
        assert journal.stat().st_size > 0  # the second sweep did not clear the first one's journal
        assert first.wait(timeout=120) == 0
    finally:
        if first.poll() is None:
            first.send_signal(signal.SIGKILL)
            first.wait(timeout=30)
    assert len((out / "sweep.csv").read_text(encoding="utf-8").splitlines()) == 9
