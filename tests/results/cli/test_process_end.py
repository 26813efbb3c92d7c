"""The console script ends its process without the interpreter's teardown, and loses nothing by it: the exit status,
the atexit handlers, the flushed output, and a running thread the interpreter would wait for."""

from __future__ import annotations

import subprocess
import sys

import pytest

pytestmark = pytest.mark.subprocess


def _run(body: str, *args: str) -> subprocess.CompletedProcess:
    script = ("import sys\nfrom rvcoax.results.cli.app import run\n" + body
              + f"\nsys.argv = ['rvcoax', *{list(args)!r}]\nrun()\nprint('not reached')\n")
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=False)


def test_the_exit_status_output_and_atexit_handlers_are_those_of_a_normal_exit():
    done = _run("import atexit\natexit.register(lambda: print('atexit ran', flush=False))", "--version")
    assert done.returncode == 0
    assert done.stdout.startswith("rvcoax ") and done.stdout.rstrip().endswith("atexit ran")
    assert "not reached" not in done.stdout
    refused = _run("", "sweep", "--t1", "x")
    assert refused.returncode == 2 and refused.stderr.startswith("error: --t1 and --t2 go together")


def test_a_thread_the_interpreter_waits_for_is_waited_for():
    done = _run("import threading, time\n"
                "threading.Thread(target=lambda: (time.sleep(0.5), print('thread finished', flush=True))).start()",
                "--version")
    assert done.returncode == 0 and "thread finished" in done.stdout
