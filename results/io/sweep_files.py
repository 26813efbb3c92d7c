"""A sweep's result files, and the journal of solved cases that lets an interrupted sweep resume.

``sweep`` appends each case to ``<out>/cases/journal.jsonl`` as soon as it is solved: one line
``<sha256> <json>``, where the JSON is ``{"format": 2, "kind": "case", "index": 7, "inputs_sha256": …,
"record": {…}}`` and ``<sha256>`` the SHA-256 of its exact bytes, so an edited or torn line does
not verify. ``inputs_sha256`` is the SHA-256 of the inputs the case was solved from
(:func:`case_inputs`: rvcoax version, the rig file's SHA-256, the torques and the solver settings),
so a line from another sweep is not reused. The sweep's ``model`` section is a line of kind
``model``.

Durability: every line goes to the operating system at once (a killed process loses nothing it
solved); the file is fsync'ed every :data:`SYNC_EVERY_CASES` cases or :data:`SYNC_EVERY_S` seconds,
and when the sweep ends, instead of once per case (a per-case fsync cost ~47 ms, 100 times the
solve: ``benchmarks/bench_durable_sweep.py``).

``sweep --resume`` reads the journal back and keeps the cases whose line verifies and whose inputs
match; the others are solved again and :class:`JournalReading` says how many and why. Final files
are always written from the JSON form of the cases (:func:`rvcoax.results.io.records.canonical`), so a resumed
sweep ends with the same bytes as an uninterrupted one.

``RVCOAX_CASE_DELAY_S`` (seconds, default 0) pauses after each case is written. It exists only so
that tests can kill a sweep mid-way; it changes no result.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io.records import canonical, entry_path_rows, rvcoax_version
from rvcoax.results.io.writers import naming_errors, write_csv_atomic, write_json_atomic, write_text_atomic

__all__ = ["CaseStore", "CASE_DELAY_VARIABLE", "JOURNAL_FORMAT", "JOURNAL_NAME", "JournalReading", "RECORD_FORMAT", "REJECTIONS",
           "SYNC_EVERY_CASES", "SYNC_EVERY_S", "case_inputs", "inputs_sha256", "journal_line", "read_journal", "record_problem",
           "sweep_inputs", "write_sweep_files"]

JOURNAL_FORMAT = 2
JOURNAL_NAME = "journal.jsonl"
CASE_DELAY_VARIABLE = "RVCOAX_CASE_DELAY_S"  # test hook: seconds to pause after each solved case
SYNC_EVERY_CASES = 256  # fsync after this many lines …
SYNC_EVERY_S = 1.0  # … or this many seconds since the last fsync, whichever comes first
# why a journal line was not reused (shown to the user, in this order)
REJECTIONS = {
    "checksum": "checksum does not match (edited or cut short)",
    "shape": "not a case record (wrong type or fields)",
    "values": "values not finite, out of range or not those of its load case",
    "inputs": "solved from other inputs (rig file, torques, settings or rvcoax version)",
}
MAX_Y_MM = 1000.0  # a journalled |Y| beyond a metre is no rig's deflection: the line is not trusted


def write_sweep_files(out: Path, stem: str, header: dict, records: list[dict]) -> list[Path]:
    """``<stem>.csv``, ``<stem>_paths.csv`` and ``<stem>.json`` from a header and per-case records.

    Parameters
    ----------
    out : Path
        The result folder.
    stem : str
        The files' common name (``sweep``).
    header : dict
        :func:`sweep_header`'s document.
    records : list of dict
        One record per case, in load-case order (from a sweep or the journal).

    Returns
    -------
    list of Path
        The files written, atomically.
    """
    return [
        write_csv_atomic(out / f"{stem}.csv", [r["row"] for r in records]),
        write_csv_atomic(out / f"{stem}_paths.csv", [row for r in records for row in entry_path_rows(r["entry"])]),
        write_json_atomic(out / f"{stem}.json", {**header, "cases": [r["entry"] for r in records]}),
    ]


RECORD_FORMAT = 4
"""What a case record holds: 2 adds the engineering quantities (issue 15); 3 the bearing lives and reducer checks
(issue 25); 4 the coupling misalignment from the unloaded geometry under its own name, the bearings' operating
stiffness and ball loads, the housings' reactions and the applied-load resultant (issue 24). A journal line of another
format is not reused, even from the same rvcoax version (a development build)."""


def sweep_inputs(rig_sha256: str, settings) -> dict:
    """What the model (and so every case) depends on, beyond the code: version, record format, rig file, settings."""
    return canonical({"rvcoax_version": rvcoax_version(), "record_format": RECORD_FORMAT, "rig_sha256": rig_sha256,
                      "settings": asdict(settings)})


def case_inputs(rig_sha256: str, case: LoadCase, settings, common: dict | None = None) -> dict:
    """The key a stored case must match to be reused: :func:`sweep_inputs` and the case's torques.

    ``common`` is :func:`sweep_inputs` computed once for many cases (it reads the package metadata).
    """
    common = sweep_inputs(rig_sha256, settings) if common is None else common
    return common | {"T1_input_Nm": case.input_torque_Nm, "T2_output_Nm": case.output_torque_Nm}


def inputs_sha256(inputs: dict) -> str:
    """SHA-256 of a :func:`case_inputs` / :func:`sweep_inputs` key (sorted-key JSON)."""
    text = json.dumps(inputs, sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=True)
    return hashlib.sha256(text.encode("ascii")).hexdigest()


def journal_line(kind: str, index: int, inputs_hash: str, record: dict) -> bytes:
    """One journal line (with its newline): the SHA-256 of the JSON's bytes, a space, the JSON."""
    body = {"format": JOURNAL_FORMAT, "kind": kind, "index": index, "inputs_sha256": inputs_hash, "record": record}
    text = json.dumps(body, separators=(",", ":"), ensure_ascii=True, allow_nan=True).encode("ascii")
    return hashlib.sha256(text).hexdigest().encode("ascii") + b" " + text + b"\n"


def _is_case_record(record) -> bool:
    return (isinstance(record, dict) and isinstance(record.get("row"), dict) and isinstance(record.get("entry"), dict)
            and all(isinstance(k, str) for k in record["row"]))


UNBOUNDED_KEYS = ("L10_Mrev", "L10_h", "L10r_Mrev", "L10r_h", "Lnm_h", "static_safety")
"""Keys (the end of a ``sweep.csv`` column or a ``sweep.json`` key) whose value is +inf where nothing loads the
bearing: a life or a safety factor without load is unbounded, and is written as such."""


def _leaves(value, key: str = ""):
    """(key, scalar) of every scalar of a JSON value (depth first; a list's items carry the list's key)."""
    stack = [(key, value)]
    while stack:
        name, item = stack.pop()
        if isinstance(item, dict):
            stack.extend((str(k), v) for k, v in item.items())
        elif isinstance(item, list):
            stack.extend((name, v) for v in item)
        else:
            yield name, item


def _number(value) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def record_problem(record: dict, torques: tuple[float, float] | None = None) -> str | None:
    """Why a case record read back from a journal cannot be what rvcoax wrote for these torques, or None.

    Checked: the fields the result files are written from exist with the right types (``entry`` per
    measured shaft with its path, ``row`` with the torques and Y); every number is finite (None
    stands for "not applicable"; an unloaded bearing's life or static safety may be +inf); |Y| ≤ :data:`MAX_Y_MM`, |β| ≤ 90°, residuals in 0 … 1; the torques
    of ``row`` and ``entry`` are ``torques``; ``row`` and ``entry`` hold the same Y and β (``sweep.csv``
    and ``sweep.json`` are written from one record each).

    Parameters
    ----------
    record : dict
        ``{"row": …, "entry": …}`` (:func:`rvcoax.results.io.records.case_record`).
    torques : (T1, T2) in N·m, optional
        The load case the record must belong to.

    Returns
    -------
    str or None
        The first problem found.
    """
    from rvcoax.geometry import MEASURED_SHAFTS

    row, entry = record["row"], record["entry"]
    for name, leaf in _leaves(record):
        if leaf is not None and not isinstance(leaf, str | bool | int | float):
            return "a value of an unknown type"
        if isinstance(leaf, float) and leaf != leaf or leaf == float("-inf"):
            return "a value that is not finite"
        if leaf == float("inf") and not name.endswith(UNBOUNDED_KEYS):
            return f"a value that is not finite ({name})"
    for key in ("T1_input_Nm", "T2_output_Nm"):
        if not (_number(row.get(key)) and _number(entry.get(key)) and row[key] == entry[key]):
            return f"{key} missing or different in its row and entry"
    if torques is not None and (row["T1_input_Nm"], row["T2_output_Nm"]) != tuple(torques):
        return "the torques of another load case"
    for shaft in MEASURED_SHAFTS:
        part = entry.get(shaft)
        path = part.get("path") if isinstance(part, dict) else None
        if not isinstance(path, dict) or not isinstance(path.get("station_mm"), list) \
                or not isinstance(path.get("uy_mm"), list) or len(path["station_mm"]) != len(path["uy_mm"]) \
                or not all(_number(v) for v in path["station_mm"] + path["uy_mm"]):
            return f"no {shaft} shaft path"
        y, beta = part.get("Y_max_mm"), part.get("beta_deg")
        if not (_number(y) and 0 <= y <= MAX_Y_MM and _number(beta) and abs(beta) <= 90):
            return f"{shaft} shaft Y or β missing or out of range"
        if row.get(f"Y_{shaft}_mm") != y or row.get(f"beta_{shaft}_deg") != beta:
            return f"{shaft} shaft Y or β different in its row and entry"
    for key in ("equilibrium_relative_error", "solve_relative_residual"):
        value = entry.get(key)
        if not (_number(value) and 0 <= value <= 1) or row.get(key) != value:
            return f"{key} missing or out of range"
    if not isinstance(entry.get("engineering", {}), dict):
        return "engineering is not a table"
    return None


@dataclass
class JournalReading:
    """What a journal held for one sweep: the records that verify, and how many lines did not, by reason."""

    cases: dict[int, dict] = field(default_factory=dict)
    model: dict | None = None
    rejected: dict[str, int] = field(default_factory=dict)
    journal_problem: str | None = None  # the journal file itself was not read (a FIFO, a device, a link)

    def reject(self, reason: str) -> None:
        self.rejected[reason] = self.rejected.get(reason, 0) + 1

    def describe_rejections(self) -> str:
        """``'3 (checksum does not match …), 1 (not a case record …)'``, or '' when every line verified."""
        return ", ".join(f"{self.rejected[key]} ({text})" for key, text in REJECTIONS.items() if key in self.rejected)


def _journal_bytes(path: Path) -> tuple[bytes, str | None]:
    """The bytes of the journal file, read without following a link and only from a regular file (a FIFO
    would hang the read, a link to /dev/zero fill memory); else (b"", why it was not read)."""
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        handle = os.open(path, flags)
    except FileNotFoundError:
        return b"", None
    except OSError:
        return b"", "a symbolic link" if os.path.islink(path) else "not readable"
    try:
        if not stat.S_ISREG(os.fstat(handle).st_mode):
            return b"", "not a regular file"
        with os.fdopen(handle, "rb", closefd=False) as stream:
            return stream.read(), None
    except OSError:
        return b"", "not readable"
    finally:
        os.close(handle)


def read_journal(path: Path, case_hashes: list[str], model_hash: str,
                 torques: list[tuple[float, float]] | None = None) -> JournalReading:
    """The verified records of ``path`` for a sweep whose cases have ``case_hashes`` (index order).

    A line is kept when it parses, its ``sha256`` matches its fields, it has the shape of a case
    (or model) record, its values pass :func:`record_problem` (with ``torques``, the (T1, T2) of each
    case in index order, when given) and its ``inputs_sha256`` is this sweep's. A later line for the
    same case replaces an earlier one. Nothing in the file can raise: every other line is counted in
    :attr:`JournalReading.rejected`; a journal that is not a regular file is not read at all.
    """
    reading = JournalReading()
    raw, problem = _journal_bytes(path)
    if problem is not None:
        reading.journal_problem = problem
        return reading
    for line in raw.split(b"\n"):
        if not line.strip():
            continue
        checksum, _, text = line.partition(b" ")
        if hashlib.sha256(text).hexdigest().encode("ascii") != checksum:
            reading.reject("checksum")
            continue
        try:
            body = json.loads(text.decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError):
            body = None
        if not isinstance(body, dict):
            reading.reject("shape")
            continue
        kind, index, record = body.get("kind"), body.get("index"), body.get("record")
        if body.get("format") != JOURNAL_FORMAT or kind not in ("case", "model") or type(index) is not int:
            reading.reject("shape")
        elif kind == "model":
            if not isinstance(record, dict):
                reading.reject("shape")
            elif body.get("inputs_sha256") == model_hash:  # (another sweep's model line is no case: not counted)
                reading.model = record
        elif not 0 <= index < len(case_hashes) or not _is_case_record(record):
            reading.reject("shape")
        elif body.get("inputs_sha256") != case_hashes[index]:
            reading.reject("inputs")
        elif record_problem(record, None if torques is None else torques[index]) is not None:
            reading.reject("values")
            reading.cases.pop(index, None)  # (an earlier line of this case is not trusted either)
        else:
            reading.cases[index] = record
    return reading


class CaseStore:
    """The journal of one sweep's solved cases in ``folder`` (``journal.jsonl``).

    Use as a context manager around the solving: lines are appended with :meth:`save` and
    :meth:`save_model` and the file is fsync'ed in batches and on exit.
    """

    def __init__(self, folder: Path, sync_every_cases: int = SYNC_EVERY_CASES, sync_every_s: float = SYNC_EVERY_S):
        self.folder = Path(folder)
        self.sync_every_cases = sync_every_cases
        self.sync_every_s = sync_every_s
        self._stream = None
        self._unsynced = 0
        self._last_sync = 0.0
        self._delay_s = _case_delay_s()

    @property
    def path(self) -> Path:
        return self.folder / JOURNAL_NAME

    def load(self, case_hashes: list[str], model_hash: str,
             torques: list[tuple[float, float]] | None = None) -> JournalReading:
        """The verified records for these inputs (:func:`read_journal`); then the journal is rewritten with
        only those (atomically, replacing a FIFO or link at its place), so that lines appended from now on
        follow complete, verified lines."""
        reading = read_journal(self.path, case_hashes, model_hash, torques)
        kept = [journal_line("case", i, case_hashes[i], reading.cases[i]) for i in sorted(reading.cases)]
        if reading.model is not None:
            kept.append(journal_line("model", -1, model_hash, reading.model))
        if os.path.lexists(self.path) or kept:
            write_text_atomic(self.path, b"".join(kept).decode("ascii"))  # the lines are ASCII JSON
        return reading

    def clear(self) -> None:
        """Start an empty journal (a sweep without --resume starts afresh), and remove the per-case
        files of rvcoax versions before the journal (``case_NNNN.json``, ``model.json``)."""
        if self.folder.is_dir():
            for path in [*self.folder.glob("case_*.json"), *self.folder.glob(".*.json.*.tmp"),
                         self.folder / "model.json"]:
                path.unlink(missing_ok=True)
        write_text_atomic(self.path, "")

    def __enter__(self) -> CaseStore:
        with naming_errors(self.path):
            self.folder.mkdir(parents=True, exist_ok=True)
            if os.path.islink(self.path) or (self.path.exists() and not self.path.is_file()):
                write_text_atomic(self.path, "")  # (never append through a link or into a FIFO or device)
            self._stream = open(self.path, "ab")  # noqa: SIM115 (closed in __exit__)
        self._last_sync = time.monotonic()
        return self

    def __exit__(self, *exc) -> None:
        if self._stream is not None:
            try:
                self.sync()
            finally:
                stream, self._stream = self._stream, None
                try:
                    stream.close()
                except OSError:  # (what could not be written was reported by sync)
                    pass

    def sync(self) -> None:
        """Make every line written so far durable (fsync)."""
        with naming_errors(self.path):  # a full disk's ENOSPC names no file
            self._stream.flush()
            os.fsync(self._stream.fileno())
        self._unsynced = 0
        self._last_sync = time.monotonic()

    def _append(self, line: bytes) -> None:
        with naming_errors(self.path):
            self._stream.write(line)
            self._stream.flush()  # to the operating system: a killed process loses nothing written
        self._unsynced += 1
        if self._unsynced >= self.sync_every_cases or time.monotonic() - self._last_sync >= self.sync_every_s:
            self.sync()

    def save(self, index: int, inputs_hash: str, record: dict) -> None:
        """Append one solved case; then wait ``$RVCOAX_CASE_DELAY_S`` seconds (tests only)."""
        self._append(journal_line("case", index, inputs_hash, record))
        if self._delay_s > 0:
            self.sync()
            time.sleep(self._delay_s)

    def save_model(self, model_hash: str, model: dict) -> None:
        """Append the sweep's ``model`` section (rig hash, settings, solver)."""
        self._append(journal_line("model", -1, model_hash, model))


def _case_delay_s() -> float:
    try:
        delay = float(os.environ.get(CASE_DELAY_VARIABLE, "0") or 0)
    except ValueError:
        return 0.0
    return delay if delay > 0 and delay == delay else 0.0
