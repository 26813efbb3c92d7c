"""A sweep's result files, and the per-case files that let an interrupted sweep resume.

``sweep`` writes each case to ``<out>/cases/case_0007.json`` (atomically: temporary file, then
rename) as soon as it is solved, with the inputs it was solved from: rvcoax version, the rig
file's SHA-256, the torques and the solver settings. ``sweep --resume`` reads them back, keeps
the cases whose inputs match, solves the others, and assembles ``sweep.csv``, ``sweep_paths.csv``
and ``sweep.json`` from all of them. Final files are always written from the JSON form of the
cases (:func:`results.report.canonical`), so a resumed sweep ends with the same bytes as an
uninterrupted one.

``RVCOAX_CASE_DELAY_S`` (seconds, default 0) pauses after each case file is written. It exists
only so that tests can kill a sweep mid-way; it changes no result.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import asdict
from pathlib import Path

from loadcases.cases import LoadCase
from results.report import canonical, entry_path_rows, rvcoax_version
from results.writers import write_csv_atomic, write_json_atomic

CASE_FILE_FORMAT = 1
DELAY_VARIABLE = "RVCOAX_CASE_DELAY_S"


def write_sweep_files(out: Path, stem: str, header: dict, records: list[dict]) -> list[Path]:
    """``<stem>.csv``, ``<stem>_paths.csv`` and ``<stem>.json`` from a header and per-case records."""
    return [
        write_csv_atomic(out / f"{stem}.csv", [r["row"] for r in records]),
        write_csv_atomic(out / f"{stem}_paths.csv", [row for r in records for row in entry_path_rows(r["entry"])]),
        write_json_atomic(out / f"{stem}.json", {**header, "cases": [r["entry"] for r in records]}),
    ]


def sweep_inputs(rig_sha256: str, settings) -> dict:
    """What the model (and so every case) depends on, beyond the code: version, rig file, settings."""
    return canonical({"rvcoax_version": rvcoax_version(), "rig_sha256": rig_sha256, "settings": asdict(settings)})


def case_inputs(rig_sha256: str, case: LoadCase, settings) -> dict:
    """The key a stored case must match to be reused: :func:`sweep_inputs` and the case's torques."""
    return sweep_inputs(rig_sha256, settings) | {"T1_input_Nm": case.input_torque_Nm,
                                                 "T2_output_Nm": case.output_torque_Nm}


class CaseStore:
    """The per-case files of one sweep in ``folder`` (``case_0000.json`` …, and ``model.json``)."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)

    def path(self, index: int) -> Path:
        return self.folder / f"case_{index:04d}.json"

    @property
    def model_path(self) -> Path:
        return self.folder / "model.json"

    def _read(self, path: Path, inputs: dict) -> dict | None:
        """The stored ``record`` if ``path`` holds one for exactly ``inputs``; None if absent, damaged or stale."""
        try:
            stored = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError):
            return None
        if not isinstance(stored, dict) or stored.get("format") != CASE_FILE_FORMAT or stored.get("inputs") != inputs:
            return None
        record = stored.get("record")
        return record if isinstance(record, dict) else None

    def _remove_temporaries(self) -> None:
        """Half-written files a killed sweep left behind (``.case_0007.json.*.tmp``)."""
        for path in self.folder.glob(".*.json.*.tmp"):
            path.unlink(missing_ok=True)

    def load(self, inputs: list[dict]) -> dict[int, dict]:
        """Records of the cases already solved with these ``inputs`` (index → record)."""
        if self.folder.is_dir():
            self._remove_temporaries()
        found = {}
        for index, key in enumerate(inputs):
            record = self._read(self.path(index), key)
            if record is not None and {"row", "entry"} <= set(record):
                found[index] = record
        return found

    def save(self, index: int, inputs: dict, record: dict) -> Path:
        """Write one solved case (atomically); then wait ``$RVCOAX_CASE_DELAY_S`` seconds (tests only)."""
        path = write_json_atomic(self.path(index), {"format": CASE_FILE_FORMAT, "inputs": inputs, "record": record},
                                 durable=True)
        try:
            delay = float(os.environ.get(DELAY_VARIABLE, "0") or 0)
        except ValueError:
            delay = 0.0
        if delay > 0:
            time.sleep(delay)
        return path

    def load_model(self, inputs: dict) -> dict | None:
        """The stored ``model`` section of ``sweep.json`` for these inputs (rig hash, settings), or None."""
        return self._read(self.model_path, inputs)

    def save_model(self, inputs: dict, model: dict) -> Path:
        return write_json_atomic(self.model_path, {"format": CASE_FILE_FORMAT, "inputs": inputs, "record": model})

    def clear(self) -> None:
        """Remove the per-case files of an earlier sweep (a new sweep without --resume starts afresh)."""
        if not self.folder.is_dir():
            return
        for path in self.folder.glob("case_*.json"):
            path.unlink(missing_ok=True)
        self.model_path.unlink(missing_ok=True)
        self._remove_temporaries()
