"""ROSS's import is quiet (ccp has CoolProp print REFPROP notices when it loads: "Good news: It is possible to use
REFPROP on your system! …"), but an import that fails shows what it printed. A module standing in for ``ross`` prints
as ccp does, from Python and on the file descriptors (importing the real ROSS takes 10–20 s: its silence is what
``rvcoax export --format ross`` shows)."""

from __future__ import annotations

import sys

import pytest

from rvcoax.results.export.ross import RossUnavailableError, import_ross


@pytest.fixture
def fake_ross(tmp_path, monkeypatch):
    """``write(body)``: make ``import ross`` load a module of that body (the real one, if loaded, is put back after)."""
    real = sys.modules.pop("ross", None)
    monkeypatch.syspath_prepend(str(tmp_path))

    def write(body: str) -> None:
        (tmp_path / "ross.py").write_text("import os, sys\n" + body, encoding="utf-8")

    yield write
    sys.modules.pop("ross", None)
    if real is not None:
        sys.modules["ross"] = real


NOISE = ("print('Good news: It is possible to use REFPROP on your system!')\n"
         "os.write(1, b'REFPROP not configured (fd 1)\\n')\nos.write(2, b'CoolProp notice (fd 2)\\n')\n")


def test_what_the_import_prints_is_not_shown(fake_ross, capfd):
    fake_ross(NOISE + "VALUE = 7\n")
    assert import_ross().VALUE == 7
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_a_failing_import_shows_what_it_printed(fake_ross):
    fake_ross(NOISE + "raise ImportError('libfoo.so: cannot open shared object file')\n")
    with pytest.raises(RossUnavailableError) as error:
        import_ross()
    message = str(error.value)
    assert 'pip install "rvcoax[ross]"' in message and "libfoo.so" in message
    said = message.split("the import printed: ")[1]
    assert all(text in said for text in ("Good news", "REFPROP not configured (fd 1)", "CoolProp notice (fd 2)"))


def test_another_error_of_the_import_is_raised_with_its_output_on_stderr(fake_ross, capfd):
    fake_ross(NOISE + "raise RuntimeError('numba cache is corrupt')\n")
    with pytest.raises(RuntimeError, match="numba cache is corrupt"):
        import_ross()
    assert "REFPROP not configured (fd 1)" in capfd.readouterr().err
