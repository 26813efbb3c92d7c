"""The check's Y–T picture drawn in a worker process (rvcoax.results.io.picture_process): the same PNG as the serial
call, written atomically, its errors raised in the parent, no process left behind."""

from __future__ import annotations

import errno

import pytest

from rvcoax.geometry.rigfile import load_rig
from rvcoax.loadcases.cases import paper_cases, paper_table
from rvcoax.results.io.picture_process import PictureProcess, PictureProcessError, picture_request
from rvcoax.results.io.pictures import plot_y_vs_torque
from rvcoax.results.sweep import run_sweep


@pytest.fixture(scope="module")
def sweep():
    return run_sweep(load_rig(), paper_cases()[::9])  # beam model, 3 cases


def _drawing(sweep, path):
    return {"model_rows": {"blind": sweep, "calibrated": sweep.cases}, "path_png": path, "published": paper_table(),
            "title": "reference rig: $x_1$ 50 %", "micro": True, "published_label": "published (paper 000)"}


def test_the_worker_draws_the_serial_png_byte_for_byte_and_ends(tmp_path, sweep):
    drawing = _drawing(sweep, tmp_path / "serial.png")
    serial = plot_y_vs_torque(drawing.pop("model_rows"), drawing.pop("path_png"), **drawing)
    with PictureProcess() as pictures:
        worker = pictures._process
        assert worker is not None
        pictures.submit(picture_request(**_drawing(sweep, tmp_path / "worker.png")))
        path = pictures.result()
    assert path == tmp_path / "worker.png"
    assert path.read_bytes() == serial.read_bytes()
    assert worker.returncode == 0  # waited for: no zombie
    assert sorted(p.name for p in tmp_path.iterdir()) == ["serial.png", "worker.png"]  # no temporary file left


def test_a_file_that_cannot_be_written_is_the_serial_oserror(tmp_path, sweep):
    blocker = tmp_path / "file"
    blocker.write_text("a file where the folder should be")
    target = blocker / "y.png"
    drawing = _drawing(sweep, target)
    with pytest.raises(OSError) as serial:
        plot_y_vs_torque(drawing.pop("model_rows"), drawing.pop("path_png"), **drawing)
    with PictureProcess() as pictures, pytest.raises(OSError) as raised:
        pictures.submit(picture_request(**_drawing(sweep, target)))
        pictures.result()
    assert raised.value.errno == serial.value.errno in (errno.ENOTDIR, errno.EEXIST)
    assert raised.value.filename == serial.value.filename == str(target)


def test_any_other_error_of_the_drawing_is_raised_with_its_message(tmp_path):
    request = {"model_rows": {"T1_input_Nm": [1.0]}, "path_png": str(tmp_path / "y.png"), "published": None}
    with PictureProcess() as pictures, pytest.raises(PictureProcessError, match="rows lack T2_output_Nm"):
        assert not pictures.submitted
        pictures.submit(request)
        assert pictures.submitted
        with pytest.raises(ValueError, match="one process draws one picture"):
            pictures.submit(request)
        pictures.result()
    assert not (tmp_path / "y.png").exists()


def test_a_worker_gone_before_answering_leaves_the_drawing_to_this_process(tmp_path, sweep):
    with PictureProcess() as pictures:
        pictures._process.kill()
        pictures._process.wait()
        pictures.submit(picture_request(**_drawing(sweep, tmp_path / "y.png")))
        assert pictures.result().stat().st_size > 10_000


def test_closing_without_a_picture_ends_the_worker(tmp_path):
    pictures = PictureProcess()
    worker = pictures._process
    pictures.close()
    assert worker.returncode == 0
    pictures.close()  # twice: nothing left to do
    with pytest.raises(ValueError, match="no picture was submitted"):
        pictures.result()


def test_a_worker_gone_under_the_default_sigpipe_action_is_not_the_end_of_this_process(tmp_path, sweep):
    """A host may restore SIGPIPE's default action (it ends a process that writes to a closed pipe): the request to a
    worker that has ended must still fall back to drawing here, and the action is restored afterwards."""
    import signal

    previous = signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    try:
        with PictureProcess() as pictures:
            pictures._process.kill()
            pictures._process.wait()
            pictures._process.poll = lambda: None  # as if it ended between the check and the write
            pictures.submit(picture_request(**_drawing(sweep, tmp_path / "y.png")))
            assert pictures.result().stat().st_size > 10_000
        assert signal.getsignal(signal.SIGPIPE) == signal.SIG_DFL
    finally:
        signal.signal(signal.SIGPIPE, previous)

