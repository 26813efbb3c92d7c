"""The export formats, declared once: a registry of writers that the command line loops over.

Each :class:`ExportFormat` names its files, says what it needs before a solve (an optional package,
cases that fit it) and writes a :class:`rvcoax.results.export.dynamics.DynamicsExport` into a folder.
:func:`write_export` writes any of them from Python; ``rvcoax export --format NAME`` calls the same
function. A new format is one more entry of :data:`EXPORT_FORMATS` (its writer in its own module).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from rvcoax.fem.errors import RvcoaxError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.export.dynamics import DynamicsExport, write_dynamics_csv, write_dynamics_json

__all__ = ["EXPORT_FORMATS", "ExportFiles", "ExportFormat", "ExportFormatError", "ExportTable", "export_format",
           "write_export"]


class ExportFormatError(RvcoaxError, ValueError):
    """An unknown export format, or a format asked to write without what it needs (the message says which)."""


@dataclass(frozen=True)
class ExportTable:
    """A summary a format gives with its files (the command line prints it), every cell as text."""

    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]


@dataclass(frozen=True)
class ExportFiles:
    """The files one format wrote, and the tables it reports with them."""

    paths: tuple[Path, ...]
    tables: tuple[ExportTable, ...] = ()


@dataclass(frozen=True)
class _Provenance:
    """The rig file as the user named it, and its text (recorded by the formats that record it)."""

    source: str | None
    text: str | None


def _nothing_needed(*_) -> None:
    """Every case fits, no package is missing."""


@dataclass(frozen=True)
class ExportFormat:
    """One export format.

    Attributes
    ----------
    name : str
        What ``--format`` and :func:`write_export` call it.
    description : str
        Its files, in a few words (the command line's help lists it after the name).
    write : callable
        ``write(export, folder, provenance) -> ExportFiles``.
    check_ready : callable
        Raises an :class:`rvcoax.RvcoaxError` when the format cannot be written here (a missing optional
        package); called before solving, so that it costs no sweep.
    check_cases : callable
        ``check_cases(cases)`` raises an :class:`rvcoax.RvcoaxError` when the load cases cannot make the format.
    """

    name: str
    description: str
    write: Callable[[DynamicsExport, Path, _Provenance], ExportFiles]
    check_ready: Callable[[], None] = _nothing_needed
    check_cases: Callable[[Sequence], None] = _nothing_needed


def _write_json(export: DynamicsExport, folder: Path, provenance: _Provenance) -> ExportFiles:
    if provenance.source is None or provenance.text is None:
        raise ExportFormatError("the json export records the rig file: give rig_source and rig_text")
    return ExportFiles((write_dynamics_json(export, folder / "dynamics.json", provenance.source, provenance.text),))


def _write_csv(export: DynamicsExport, folder: Path, _: _Provenance) -> ExportFiles:
    return ExportFiles(tuple(write_dynamics_csv(export, folder)))


def _write_adams(export: DynamicsExport, folder: Path, _: _Provenance) -> ExportFiles:
    from rvcoax.results.export.adams import write_adams

    return ExportFiles(tuple(write_adams(export, folder)))


def _adams_cases(cases) -> None:
    from rvcoax.results.export.adams import spline_layout

    for shaft in MEASURED_SHAFTS:
        spline_layout(cases, shaft)


def _ross_ready() -> None:
    from rvcoax.results.export.ross import import_ross

    import_ross()


def _write_ross(export: DynamicsExport, folder: Path, _: _Provenance) -> ExportFiles:
    from rvcoax.results.export.ross import write_ross

    written = write_ross(export, folder)
    rows = tuple((c.line.which, str(c.line.node_x_mm.size), ", ".join(s.spring.name for s in c.line.supports),
                  f"{c.largest_sag_m * 1e9:.4g}", f"{abs(c.ross_uy_m).max() * 1e9:.4g}", f"{c.relative_difference:.1e}")
                 for c in written.comparisons)
    table = ExportTable("ROSS static analysis (gravity, rigid supports) vs rvcoax on the same shaft",
                        ("shaft", "nodes", "supports", "largest sag rvcoax nm", "largest sag ROSS nm",
                         "largest difference"), rows)
    return ExportFiles(written.paths, (table,))


EXPORT_FORMATS: tuple[ExportFormat, ...] = (
    ExportFormat("json", "dynamics.json", _write_json),
    ExportFormat("csv", "dynamics_*.csv", _write_csv),
    ExportFormat("adams", "dynamics.adm, an ADAMS/Solver dataset fragment", _write_adams, check_cases=_adams_cases),
    ExportFormat("ross", "ROSS rotors of the measured shafts, misalignment fault parameters, static check; needs the "
                         "rvcoax[ross] extra", _write_ross, check_ready=_ross_ready),
)
"""Every export format, in the order the command line lists them."""


def export_format(name: str) -> ExportFormat:
    """The format called ``name``.

    Parameters
    ----------
    name : str
        ``json``, ``csv``, ``adams``, ``ross`` or any other name in :data:`EXPORT_FORMATS`.

    Returns
    -------
    ExportFormat

    Raises
    ------
    ExportFormatError
        No format has that name (the message lists those that do).
    """
    for candidate in EXPORT_FORMATS:
        if candidate.name == name:
            return candidate
    raise ExportFormatError(f"'{name}' is not one of {', '.join(f.name for f in EXPORT_FORMATS)}")


def write_export(export: DynamicsExport, folder: str | Path, format: str = "json", *, rig_source: str | None = None,
                 rig_text: str | None = None) -> ExportFiles:
    """Write ``export`` in ``format`` into ``folder`` (created when missing; every file written atomically).

    Parameters
    ----------
    export : DynamicsExport
        From :func:`rvcoax.results.export.dynamics_export`.
    folder : str or Path
    format : str
        One of :data:`EXPORT_FORMATS`: ``json``, ``csv``, ``adams`` or ``ross``.
    rig_source, rig_text : str, optional
        The rig file as the user named it, and its text: recorded (with its SHA-256) by ``json``, which needs them.

    Returns
    -------
    ExportFiles
        The files written, and the tables the format reports with them (``ross``: its static check).

    Raises
    ------
    ExportFormatError, AdamsExportError, RossUnavailableError
        An unknown format or missing provenance, cases that cannot make ADAMS splines, ROSS not installed.
    """
    chosen = export_format(format)
    chosen.check_ready()
    chosen.check_cases([c.case for c in export.sweep.cases])
    return chosen.write(export, Path(folder), _Provenance(rig_source, rig_text))
