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
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io.records import canonical, entry_path_rows, rvcoax_version
from rvcoax.results.io.writers import write_csv_atomic, write_json_atomic, write_text_atomic

__all__ = ["CaseStore", "CASE_DELAY_VARIABLE", "JOURNAL_FORMAT", "JOURNAL_NAME", "JournalReading", "RECORD_FORMAT", "REJECTIONS",
           "SYNC_EVERY_CASES", "SYNC_EVERY_S", "case_inputs", "inputs_sha256", "journal_line", "read_journal",
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
    "inputs": "solved from other inputs (rig file, torques, settings or rvcoax version)",
}


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


RECORD_FORMAT = 3
"""What a case record holds: 2 adds the engineering quantities (issue 15); 3 the coupling misalignment from the
unloaded geometry under its own name, the bearings' operating stiffness and ball loads, the housings' reactions
and the applied-load resultant (issue 24). A journal line of another
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


@dataclass
class JournalReading:
    """What a journal held for one sweep: the records that verify, and how many lines did not, by reason."""

    cases: dict[int, dict] = field(default_factory=dict)
    model: dict | None = None
    rejected: dict[str, int] = field(default_factory=dict)

    def reject(self, reason: str) -> None:
        self.rejected[reason] = self.rejected.get(reason, 0) + 1

    def describe_rejections(self) -> str:
        """``'3 (checksum does not match …), 1 (not a case record …)'``, or '' when every line verified."""
        return ", ".join(f"{self.rejected[key]} ({text})" for key, text in REJECTIONS.items() if key in self.rejected)


def read_journal(path: Path, case_hashes: list[str], model_hash: str) -> JournalReading:
    """The verified records of ``path`` for a sweep whose cases have ``case_hashes`` (index order).

    A line is kept when it parses, its ``sha256`` matches its fields, it has the shape of a case
    (or model) record and its ``inputs_sha256`` is this sweep's. A later line for the same case
    replaces an earlier one. Nothing in the file can raise: every other line is counted in
    :attr:`JournalReading.rejected`.
    """
    reading = JournalReading()
    try:
        raw = path.read_bytes()
    except OSError:
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

    def load(self, case_hashes: list[str], model_hash: str) -> JournalReading:
        """The verified records for these inputs; then the journal is rewritten with only those
        (atomically), so that lines appended from now on follow complete, verified lines."""
        reading = read_journal(self.path, case_hashes, model_hash)
        kept = [journal_line("case", i, case_hashes[i], reading.cases[i]) for i in sorted(reading.cases)]
        if reading.model is not None:
            kept.append(journal_line("model", -1, model_hash, reading.model))
        if self.path.exists() or kept:
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
        self.folder.mkdir(parents=True, exist_ok=True)
        self._stream = open(self.path, "ab")  # noqa: SIM115 (closed in __exit__)
        self._last_sync = time.monotonic()
        return self

    def __exit__(self, *exc) -> None:
        if self._stream is not None:
            self.sync()
            self._stream.close()
            self._stream = None

    def sync(self) -> None:
        """Make every line written so far durable (fsync)."""
        self._stream.flush()
        os.fsync(self._stream.fileno())
        self._unsynced = 0
        self._last_sync = time.monotonic()

    def _append(self, line: bytes) -> None:
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
