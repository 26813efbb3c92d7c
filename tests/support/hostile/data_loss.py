"""Data loss and trust (issue 24, part 5): nothing rvcoax did not compute is trusted, and nothing it does not own
is written.

- ``OUT/.rvcoax.lock`` made a symbolic link or a hard link to a user's file, a FIFO or a large file: refused with
  the lock file named, the user's file untouched (a symbolic link's target was truncated to 0 bytes).
- ``sweep --resume`` with journal lines whose checksum was recomputed after an edit (a checksum is no
  signature): a changed Y in both the CSV row and the JSON entry, a ``nan`` in the row only, an entry emptied to
  ``{}``, the torques of another case, a residual out of range. Each is refused or recomputed, and ``sweep.csv``
  and ``sweep.json`` end byte-identical to an uninterrupted run (they hold the same, recomputed values).
- A journal that is a FIFO, a link to ``/dev/zero`` or to a user's file, or a folder: not read (no hang, no
  crash), not written through; every case is solved again.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from typer.testing import CliRunner

from hostile import Hostile
from hostile.trust import SWEEP, _case_at, _journal, _lines, _signed, _solved_sweep
from rvcoax.results.cli.app import app

K = "data_loss"
PRECIOUS = "measurements of a week\n"
NOT_A_LOCK = ("--out", ".rvcoax.lock", "not a lock file of rvcoax; nothing was written into it", "Remove it")


def _lock_file(make):
    """``folder/out/.rvcoax.lock`` made by ``make(lock, precious)``; the sweep that must refuse it."""
    def argv(folder: Path) -> list[str]:
        out = folder / "out"
        out.mkdir()
        precious = folder / "precious.txt"
        precious.write_text(PRECIOUS, encoding="utf-8")
        make(out / ".rvcoax.lock", precious)
        return [*SWEEP, "--out", str(out)]
    return argv


def _untouched(folder: Path, stdout: str, stderr: str) -> None:
    assert (folder / "precious.txt").read_text(encoding="utf-8") == PRECIOUS, "the user's file was written"
    assert not (folder / "out" / "sweep.csv").exists()


def _lock(label: str, make, *expected: str) -> Hostile:
    return Hostile(f"{K}: lock file {label}", K, _lock_file(make), NOT_A_LOCK + expected, check=_untouched)


def _same_files(folder: Path, stdout: str, stderr: str) -> None:
    """sweep.csv and sweep.json both hold the recomputed values: the bytes of an uninterrupted run."""
    out = folder / "out"
    assert (out / "sweep.csv").read_bytes() == (folder / "straight.csv").read_bytes()
    assert (out / "sweep.json").read_bytes() == (folder / "straight.json").read_bytes()


def _resume_after(change):
    """A solved sweep whose journal ``change(journal path)`` rewrote, resumed."""
    def argv(folder: Path) -> list[str]:
        _solved_sweep(folder)
        (folder / "straight.json").write_bytes((folder / "out" / "sweep.json").read_bytes())
        change(_journal(folder))
        return [*SWEEP, "--out", str(folder / "out"), "--resume"]
    return argv


def _resigned(index: int, edit):
    """Case ``index``'s line with its record changed by ``edit(record)`` and its checksum recomputed."""
    def change(journal: Path) -> None:
        lines = _lines(journal.parents[2])
        at = _case_at(lines, index)
        lines[at] = _signed(lambda body: body | {"record": edit(json.loads(json.dumps(body["record"])))})(lines[at])
        journal.write_bytes(b"".join(lines))
    return change


def _scaled_y(record: dict) -> dict:
    """Y of the input shaft 1.5 times larger in the row and the entry alike (a consistent forgery)."""
    y = record["row"]["Y_input_mm"] * 1.5
    record["row"]["Y_input_mm"] = y
    record["entry"]["input"]["Y_max_mm"] = y
    return record


def _set(where: str, key: str, value):
    def edit(record: dict) -> dict:
        record[where][key] = value
        return record
    return edit


def _resumed(label: str, change, *expected: str) -> Hostile:
    return Hostile(f"{K}: resume, {label}", K, _resume_after(change), expected, exit_code=0, stream="output",
                   check=_same_files)


VALUES = "(values not finite, out of range or not those of its load case)"


def _replaced_by(make):
    """The journal replaced by what ``make(journal, folder)`` puts at its place."""
    def change(journal: Path) -> None:
        journal.unlink()
        make(journal, journal.parents[2])
    return change


def _precious_link(journal: Path, folder: Path) -> None:
    (folder / "precious.txt").write_text(PRECIOUS, encoding="utf-8")
    journal.symlink_to(folder / "precious.txt")


def _precious_kept(folder: Path, stdout: str, stderr: str) -> None:
    _same_files(folder, stdout, stderr)
    assert (folder / "precious.txt").read_text(encoding="utf-8") == PRECIOUS, "appended through the link"
    assert not _journal(folder).is_symlink() and _journal(folder).is_file()


def _fresh_journal_link(folder: Path) -> list[str]:
    """A sweep without --resume whose journal is a link to /dev/full: the link is replaced, not written through."""
    (folder / "out" / "cases").mkdir(parents=True)
    _journal(folder).symlink_to("/dev/full")
    CliRunner().invoke(app, [*SWEEP, "--out", str(folder / "fresh")])
    for name in ("sweep.csv", "sweep.json"):
        (folder / f"straight.{name.split('.')[1]}").write_bytes((folder / "fresh" / name).read_bytes())
    return [*SWEEP, "--out", str(folder / "out")]


CASES: list[Hostile] = [
    _lock("a symbolic link to a user's file", lambda lock, precious: lock.symlink_to(precious),
          "is a symbolic link to"),
    _lock("a hard link to a user's file", lambda lock, precious: os.link(precious, lock),
          "a file with 2 names (a hard link to another file)"),
    _lock("a FIFO", lambda lock, precious: os.mkfifo(lock), "not a regular file (a FIFO, device or socket)"),
    _lock("a large file", lambda lock, precious: lock.write_text("x" * 4096, encoding="ascii"),
          "a file of 4096 bytes (a lock file holds only a process id)"),
    _lock("a symbolic link to /dev/zero", lambda lock, precious: lock.symlink_to("/dev/zero"), "/dev/zero"),
    # forged lines: edited and signed again
    _resumed("Y changed in row and entry, checksum recomputed", _resigned(1, _scaled_y),
             "resuming: 3 of 3", "checking the journal: every reused case", "solved again and compared",
             "1 of 3 reused case(s) differ from a new solve (cases 2)", "the values solved now are written"),
    _resumed("nan in the row only, checksum recomputed", _resigned(0, _set("row", "Y_output_mm", float("nan"))),
             "resuming: 2 of 3", f"1 {VALUES}"),
    _resumed("row and entry disagree, checksum recomputed", _resigned(2, _set("row", "Y_input_mm", 0.123)),
             "resuming: 2 of 3", f"1 {VALUES}"),
    _resumed("entry emptied to {}, checksum recomputed", _resigned(1, lambda r: r | {"entry": {}}),
             "resuming: 2 of 3", f"1 {VALUES}"),
    _resumed("torques of another case, checksum recomputed", _resigned(0, lambda r: _torques(r, 2.0, 50.0)),
             "resuming: 2 of 3", f"1 {VALUES}"),
    _resumed("residual out of range, checksum recomputed",
             _resigned(2, lambda r: _both(r, "solve_relative_residual", 7.0)), "resuming: 2 of 3", f"1 {VALUES}"),
    _resumed("Y of a kilometre, checksum recomputed", _resigned(1, lambda r: _y_everywhere(r, 1e6)),
             "resuming: 2 of 3", f"1 {VALUES}"),
    # journals that are not regular files
    _resumed("journal is a FIFO", _replaced_by(lambda journal, folder: os.mkfifo(journal)), "resuming: 0 of 3",
             "journal.jsonl: not a regular file", "every case is solved again"),
    _resumed("journal is a link to /dev/zero", _replaced_by(lambda journal, folder: journal.symlink_to("/dev/zero")),
             "resuming: 0 of 3", "journal.jsonl: a symbolic link", "every case is solved again"),
    Hostile(f"{K}: resume, journal is a link to a user's file", K, _resume_after(_replaced_by(_precious_link)),
            ("resuming: 0 of 3", "a symbolic link"), exit_code=0, stream="output", check=_precious_kept),
    Hostile(f"{K}: fresh sweep, journal is a link to /dev/full", K, _fresh_journal_link, ("wrote",), exit_code=0,
            stream="output", check=_same_files),
]


def _both(record: dict, key: str, value) -> dict:
    record["row"][key] = value
    record["entry"][key] = value
    return record


def _torques(record: dict, t1: float, t2: float) -> dict:
    return _both(_both(record, "T1_input_Nm", t1), "T2_output_Nm", t2)


def _y_everywhere(record: dict, y: float) -> dict:
    record["row"]["Y_output_mm"] = y
    record["entry"]["output"]["Y_max_mm"] = y
    return record



# a nonlinear sweep (ball bearings): three reused cases are solved again (first, middle, last); one that differs
# makes every reused case be solved again
BALL = ("sweep", "--rig", "BALL", "--t1", "0.5,1,1.2,1.43,2", "--t2", "10,50,100,150,200")


def _ball_sweep(folder: Path, out: str) -> list[str]:
    from rvcoax.geometry.rigfile import reference_rig_text

    rig = folder / "ball.toml"
    if not rig.exists():
        rig.write_text(reference_rig_text("ball_bearings"), encoding="utf-8")
    return [a if a != "BALL" else str(rig) for a in BALL] + ["--out", str(folder / out)]


def _ball_resumed(folder: Path) -> list[str]:
    for out in ("out", "fresh"):
        result = CliRunner().invoke(app, _ball_sweep(folder, out))
        assert result.exit_code == 0, result.output
    for name in ("sweep.csv", "sweep.json"):
        (folder / f"straight.{name.split('.')[1]}").write_bytes((folder / "fresh" / name).read_bytes())
    _resigned(2, _scaled_y)(_journal(folder))
    return [*_ball_sweep(folder, "out"), "--resume"]


CASES.append(Hostile(f"{K}: resume, nonlinear sweep, a forged middle case fails the spot check", K, _ball_resumed,
                     ("resuming: 5 of 5", "3 reused case(s) as a spot check (nonlinear: a Newton solve each)",
                      "1 of 5 reused case(s) differ from a new solve (cases 3)"), exit_code=0, stream="output",
                     check=_same_files))
