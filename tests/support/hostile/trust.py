"""Trust: results not written by this run are never taken as they are. Issue 12, part 6.

``sweep --resume`` reads ``OUT/cases/journal.jsonl``: a line that was edited, cut short, has the
wrong type or shape, or came from other inputs is solved again, the console says how many and why,
and ``sweep.csv`` ends byte-identical to an uninterrupted run (so it holds the recomputed values).
An output folder that another command holds (``OUT/.rvcoax.lock``) is refused at once.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
from pathlib import Path

from typer.testing import CliRunner

from hostile import Hostile
from hostile._files import TOLERANCES
from rvcoax.results.cli.app import app
from rvcoax.results.io.sweep_files import journal_line

K = "trust"
SWEEP = ("sweep", "--t1", "0.5,1,2", "--t2", "10,50,200")
CHECKSUM = "(checksum does not match (edited or cut short))"
SHAPE = "(not a case record (wrong type or fields))"
INPUTS = "(solved from other inputs"


def _journal(folder: Path) -> Path:
    return folder / "out" / "cases" / "journal.jsonl"


def _solved_sweep(folder: Path, *options: str) -> None:
    """A complete sweep in ``folder/out``; its sweep.csv is kept as ``folder/straight.csv``."""
    result = CliRunner().invoke(app, [*SWEEP, "--out", str(folder / "out"), *options])
    assert result.exit_code == 0, result.output
    (folder / "straight.csv").write_bytes((folder / "out" / "sweep.csv").read_bytes())


def _lines(folder: Path) -> list[bytes]:
    return _journal(folder).read_bytes().splitlines(keepends=True)


def _resume_after(change):
    """argv of ``sweep --resume`` after ``change(lines) -> lines`` rewrote the journal of a solved sweep."""
    def argv(folder: Path) -> list[str]:
        _solved_sweep(folder)
        _journal(folder).write_bytes(b"".join(change(_lines(folder))))
        return [*SWEEP, "--out", str(folder / "out"), "--resume"]
    return argv


def _recomputed(folder: Path, stdout: str, stderr: str) -> None:
    """sweep.csv holds the recomputed values: the same bytes as the uninterrupted run."""
    assert (folder / "out" / "sweep.csv").read_bytes() == (folder / "straight.csv").read_bytes()


def _resumed(label: str, change, *expected: str) -> Hostile:
    return Hostile(f"{K}: {label}", K, _resume_after(change), tuple(expected), exit_code=0, stream="output",
                   check=_recomputed)


def _case_at(lines: list[bytes], index: int) -> int:
    return next(k for k, line in enumerate(lines) if f'"kind":"case","index":{index},'.encode() in line)


def _replace_case(index: int, new_line):
    """Replace case ``index``'s line with ``new_line(old line) -> line``."""
    def change(lines: list[bytes]) -> list[bytes]:
        at = _case_at(lines, index)
        return lines[:at] + [new_line(lines[at])] + lines[at + 1:]
    return change


def _body(line: bytes) -> dict:
    return json.loads(line.partition(b" ")[2])


def _signed(edit):
    """A line whose checksum is right but whose fields ``edit(body)`` changed (written as rvcoax writes lines)."""
    def new_line(line: bytes) -> bytes:
        body = edit(_body(line))
        return journal_line(body["kind"], body["index"], body["inputs_sha256"], body["record"])
    return new_line


def _field(key: str, value):
    return _signed(lambda body: body | {key: value})


def _edited_y(line: bytes) -> bytes:
    body = _body(line)
    text = line.decode("ascii")
    old = json.dumps(body["record"]["row"]["Y_input_mm"])
    assert f'"Y_input_mm":{old}' in text
    return text.replace(f'"Y_input_mm":{old}', '"Y_input_mm":0.123', 1).encode("ascii")


def _model_line(lines: list[bytes]) -> int:
    return next(k for k, line in enumerate(lines) if b'"kind":"model"' in line)


def _foreign(folder: Path) -> list[str]:
    """The journal of a sweep with --method direct, resumed with superposition: every case from other inputs."""
    _solved_sweep(folder, "--method", "direct")
    CliRunner().invoke(app, [*SWEEP, "--out", str(folder / "fresh")])
    (folder / "straight.csv").write_bytes((folder / "fresh" / "sweep.csv").read_bytes())
    return [*SWEEP, "--out", str(folder / "out"), "--resume"]


def _locked(argv_of):
    """Hold ``folder/out``'s lock (as a running command would) and return the command's argv."""
    def argv(folder: Path) -> list[str]:
        out = folder / "out"
        out.mkdir()
        handle = os.open(out / ".rvcoax.lock", os.O_RDWR | os.O_CREAT, 0o644)
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        os.write(handle, b"4242\n")
        _HELD.append(handle)  # released when the test process ends (the lock is per open file)
        return argv_of(out)
    return argv


_HELD: list[int] = []


def _lock(label: str, argv_of) -> Hostile:
    return Hostile(f"{K}: locked output folder, {label}", K, _locked(argv_of),
                   ("--out", "another rvcoax command (process 4242) is writing into this folder", ".rvcoax.lock",
                    "give another --out folder"))


def _stale_lock(folder: Path) -> list[str]:
    """A lock file left by a killed command (nobody holds it): the sweep runs."""
    (folder / "out").mkdir()
    (folder / "out" / ".rvcoax.lock").write_text("999999\n", encoding="ascii")
    CliRunner().invoke(app, [*SWEEP, "--out", str(folder / "fresh")])
    (folder / "straight.csv").write_bytes((folder / "fresh" / "sweep.csv").read_bytes())
    return [*SWEEP, "--out", str(folder / "out")]


CASES: list[Hostile] = [
    # edited or damaged lines: the checksum of the line's bytes does not match
    _resumed("hand-edited Y", _replace_case(1, _edited_y), "resuming: 2 of 3", f"1 {CHECKSUM}"),
    _resumed("torn last line", lambda lines: lines[:-1] + [lines[-1][:40]], "resuming: 3 of 3", f"1 {CHECKSUM}"),
    _resumed("line cut short mid-journal", _replace_case(0, lambda line: line[:len(line) // 2] + b"\n"),
             "resuming: 2 of 3", f"1 {CHECKSUM}"),
    _resumed("binary garbage line", lambda lines: lines + [b"\x00\xff\xfe garbage \x80\n"], "resuming: 3 of 3",
             f"1 {CHECKSUM}"),
    _resumed("checksum of another line", _replace_case(2, lambda line: _lines_checksum_swap(line)),
             "resuming: 2 of 3", f"1 {CHECKSUM}"),
    # lines with a right checksum and the wrong type or shape: never crash, solved again
    _resumed("record is a number", _replace_case(0, _field("record", 5)), "resuming: 2 of 3", f"1 {SHAPE}"),
    _resumed("row is a list", _replace_case(1, _signed(lambda b: b | {"record": {"row": [1, 2], "entry": {}}})),
             "resuming: 2 of 3", f"1 {SHAPE}"),
    _resumed("index is text", _replace_case(2, _field("index", "2")), "resuming: 2 of 3", f"1 {SHAPE}"),
    _resumed("index beyond the sweep", _replace_case(2, _field("index", 99)), "resuming: 2 of 3", f"1 {SHAPE}"),
    _resumed("unknown kind", _replace_case(0, _field("kind", "sample")), "resuming: 2 of 3", f"1 {SHAPE}"),
    _resumed("JSON array with a valid checksum",
             lambda lines: lines + [hashlib.sha256(b"[1, 2, 3]").hexdigest().encode() + b" [1, 2, 3]\n"],
             "resuming: 3 of 3", f"1 {SHAPE}"),
    _resumed("model line of the wrong type", lambda lines: [line if b'"kind":"model"' not in line else
                                                           _field("record", [1])(line) for line in lines],
             "resuming: 3 of 3", f"1 {SHAPE}"),
    # lines from other inputs: a case moved to another index, a journal of another method
    _resumed("case line under another index", _replace_case(0, _field("index", 1)), "resuming: 2 of 3",
             f"1 {INPUTS}"),
    Hostile(f"{K}: journal of another method", K, _foreign, ("resuming: 0 of 3", f"3 {INPUTS}"), exit_code=0,
            stream="output", check=_recomputed),
    _resumed("empty journal", lambda lines: [], "resuming: 0 of 3 case(s) already solved"),
    # locked output folders: every command that writes --out goes through the same lock
    _lock("sweep", lambda out: [*SWEEP, "--out", str(out)]),
    _lock("sweep --resume", lambda out: [*SWEEP, "--out", str(out), "--resume"]),
    _lock("montecarlo", lambda out: ["montecarlo", "--tolerances", str(TOLERANCES), "--scheduler", "serial",
                                     "--samples", "2", "--out", str(out)]),
    _lock("check", lambda out: ["check", "--out", str(out)]),
    _lock("picture", lambda out: ["picture", "--t1", "1", "--t2", "10", "--out", str(out)]),
    Hostile(f"{K}: stale lock file of a killed command", K, _stale_lock, ("wrote",), exit_code=0, stream="output",
            check=_recomputed),
]


def _lines_checksum_swap(line: bytes) -> bytes:
    """``line`` with its checksum replaced by the checksum of other bytes (a line pasted from elsewhere)."""
    return journal_line("case", 0, "other", {})[:64] + line[64:]
