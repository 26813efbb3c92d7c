"""Issue 12's hostile corpus through the real command line (``tests/support/hostile/``).

Each case runs in process (typer's CliRunner on ``rvcoax.results.cli.app.app``) with its own environment
variables. It must end with its documented exit status, print the expected words (file or option,
line or key, reason), and print no traceback; an exit status of 2 must come from the CLI's own
error path (a ``SystemExit``), never from an exception that escaped.
"""

from __future__ import annotations

import pytest
from hostile import CLASSES, all_cases
from typer.testing import CliRunner

from rvcoax.results.cli.app import app

CORPUS = all_cases()


def flat(text: str) -> str:
    return " ".join(text.split())


def test_the_corpus_covers_every_class():
    assert len({case.name for case in CORPUS}) == len(CORPUS)  # unique ids
    present = {case.klass for case in CORPUS}
    assert present == set(CLASSES), f"classes without cases: {set(CLASSES) - present}"
    assert len(CORPUS) >= 150


def _real_process(case, args: list[str]):
    """``rvcoax ARGS`` as a real process (the installed console script) with stdout sent to ``case.stdout_to``."""
    import os
    import subprocess
    import sys
    from pathlib import Path
    from types import SimpleNamespace

    script = Path(sys.executable).with_name("rvcoax")
    with open(case.stdout_to, "w") as stdout:
        done = subprocess.run([str(script), *args], stdout=stdout, stderr=subprocess.PIPE, text=True, timeout=300,
                              env={**os.environ, **case.env})
    return SimpleNamespace(exit_code=done.returncode, stdout="", stderr=done.stderr, output=done.stderr,
                           exception=None)


# a case that needs the real console script (its standard output on a full device) runs it as a process
@pytest.mark.parametrize("case", [pytest.param(c, id=c.name, marks=pytest.mark.subprocess if c.stdout_to else ())
                                  for c in CORPUS])
def test_hostile_input(case, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a case without --out writes ./rvcoax_out: its own, not one another worker locks
    for key, value in case.env.items():
        monkeypatch.setenv(key, value)
    if case.patch is not None:
        case.patch(tmp_path, monkeypatch)
    args = case.argv(tmp_path)
    result = _real_process(case, args) if case.stdout_to else CliRunner().invoke(app, args)
    context = (f"rvcoax {' '.join(args)}\nexit {result.exit_code}\nstdout: {result.stdout}\n"
               f"stderr: {result.stderr}\nexception: {result.exception!r}")
    assert result.exit_code == case.exit_code, context
    assert result.exception is None or isinstance(result.exception, SystemExit), context  # nothing escaped
    assert "Traceback" not in result.output, context
    if case.exit_code == 2:
        message = flat(result.stderr)  # one error paragraph, after any warnings about the same input
        assert message.startswith(("error:", "warning:")) and "error:" in message, context
    text = flat(result.stderr if case.stream == "stderr" else result.output)
    for words in case.expected:
        assert words in text, f"{words!r} missing\n{context}"
    if case.check is not None:
        case.check(tmp_path, result.stdout, result.stderr)
