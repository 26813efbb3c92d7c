"""Processes (issue 24, part 5): a helper program that times out is ended with all of its children.

After the PDF timeout, headless Chromium's child processes (renderer, zygote) kept running: only the browser
itself was killed. Here a stand-in browser starts a child that outlives it, records the child's PID and hangs;
``report --pdf --pdf-timeout-s 2`` must refuse with the timeout named and leave no process of the group alive.
The new option obeys issue 12's rules for numeric options (finite, in range, ASCII, named).
"""

from __future__ import annotations

import os
import time
from pathlib import Path

from hostile import Hostile
from hostile._files import run

K = "processes"
BROWSER = """#!/bin/sh
# a browser that hangs: its child (a renderer) would outlive it
sleep 300 &
echo $! > "$FAKE_BROWSER_CHILD"
sleep 300
"""


def _hanging_browser(folder: Path, monkeypatch) -> None:
    script = folder / "browser.sh"
    script.write_text(BROWSER, encoding="ascii")
    script.chmod(0o755)
    monkeypatch.setenv("RVCOAX_BROWSER", str(script))
    monkeypatch.setenv("FAKE_BROWSER_CHILD", str(folder / "child.pid"))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie (ended, not yet reaped by its new parent) counts as ended
        with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _children_ended(folder: Path, stdout: str, stderr: str) -> None:
    pid = int((folder / "child.pid").read_text(encoding="ascii"))
    for _ in range(50):  # (SIGKILL is delivered at once; the process table may take a moment)
        if not _alive(pid):
            break
        time.sleep(0.1)
    alive = _alive(pid)
    if alive:
        os.kill(pid, 9)
    assert not alive, f"the browser's child {pid} kept running after the timeout"
    assert not (folder / "out" / "report.pdf").exists()


CASES: list[Hostile] = [
    Hostile(f"{K}: PDF timeout ends the browser's children", K,
            lambda folder: ["report", "--t1", "1", "--t2", "10", "--no-deformed", "--pdf", "--pdf-timeout-s", "2",
                            "--out", str(folder / "out")],
            ("browser.sh did not print", "report.html to PDF within 2 s; it and its child processes were ended"),
            patch=_hanging_browser, check=_children_ended),
]
for value, words in (("nan", "is not a finite number"), ("0", "is outside the range"), ("-5", "is outside the range"),
                     ("1e300", "is outside the range"), ("", "the value is empty"), ("１０", "characters that are not ASCII"),
                     ("2 s", "'2 s' is not a number")):
    CASES.append(Hostile(f"{K}: report --pdf-timeout-s {value!r}", K,
                         run("report", "--pdf", "--pdf-timeout-s", value), ("--pdf-timeout-s", words, "1 … 3600 s")))
