"""The study report: one self-contained HTML file for a design review.

Everything is inside the file: pictures as ``data:image/png;base64`` URIs, the style sheet inline, no
script and no link to the network, so it opens anywhere (a browser, an e-mail attachment) and prints
to PDF (``chromium --headless --print-to-pdf``). Sections, each an ``<section id=…>``:

``rig``            parts with masses, bearings, couplings and materials, with the rig file's provenance tags
``load-cases``     the torque pairs solved
``bending-lines``  the bending line of the whole rig, and the deformed rig of the largest case
``shafts``         Y and tilt of the measured shafts against torque (pictures and table)
``decides``        what decides Y: each assumed ([A]) input halved and doubled, ranked by the change of Y
``misalignment``   couplings and bearings against their allowable values, with verdicts
``reactions``      the support reactions and the equilibrium residual
``check``          the model against a measured table (when one is given)
``discrepancy``    the result of ``rvcoax discrepancy`` (when its ``discrepancy.json`` is given)
``modes``          natural frequencies, interference diagram and mode shapes (:mod:`.modes_section`, when given)
``inputs``         every input of the rig file, key by key, with its provenance tag (or "default")
``provenance``     rvcoax version, rig file and its SHA-256, model, solver, mesh, date
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import json
import math
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.engineering import engineering_warnings
from rvcoax.results.io.writers import write_text_atomic
from rvcoax.results.reports import report_tables as tables
from rvcoax.results.reports.shaft_tables import shaft_strength_tables
from rvcoax.results.torque_path import torque_path_warnings

__all__ = ["PAPER_SIZES", "REPORT_SECTIONS", "ReportError", "ReportInputs", "read_discrepancy", "report_html", "write_report"]

REPORT_SECTIONS = {
    "rig": "The rig", "load-cases": "Load cases", "bending-lines": "Bending lines",
    "shafts": "Y and tilt against torque", "decides": "What decides Y",
    "misalignment": "Couplings and bearings: misalignment",
    "shaft-strength": "Shaft stresses and DIN 743 safety",
    "reactions": "Support reactions and equilibrium", "check": "Check against measured data",
    "discrepancy": "Discrepancy between model and measurement", "modes": "Natural frequencies and interference",
    "inputs": "Complete input listing",
    "provenance": "Provenance",
}

_STYLE = """
body { font: 14px/1.45 "DejaVu Sans", Helvetica, Arial, sans-serif; color: #1a1a1a; margin: 0 auto;
       max-width: 1200px; padding: 0 24px 48px; background: #fff; }
h1 { font-size: 24px; margin: 28px 0 4px; }
h2 { font-size: 19px; border-bottom: 2px solid #4c72b0; padding-bottom: 3px; margin-top: 34px; }
h3 { font-size: 15px; margin: 18px 0 6px; }
p.sub { color: #555; margin-top: 0; }
p.sign { color: #333; font-size: 12px; margin: 0 0 6px; overflow-wrap: anywhere; }
nav { background: #f3f5f9; padding: 8px 12px; border-radius: 4px; display: flex; flex-wrap: wrap; gap: 4px 14px; }
nav a { color: #2a4f8f; text-decoration: none; white-space: nowrap; }
table { border-collapse: collapse; margin: 6px 0 4px; font-size: 12.5px; }
caption { text-align: left; font-weight: bold; padding: 4px 0; }
th, td { border: 1px solid #cfd4dc; padding: 3px 7px; vertical-align: top; }
th { background: #eef1f6; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.fine { background: #e3f4e1; } td.within { background: #fbf3d5; } td.exceeds { background: #f8d7d7;
  font-weight: bold; } td.none { color: #666; }
p.note { color: #444; font-size: 12.5px; margin: 2px 0 14px; max-width: 1100px; }
img { max-width: 100%; border: 1px solid #e2e2e2; margin: 6px 0; }
.missing { color: #8a5a00; background: #fff6e0; padding: 6px 10px; border-left: 3px solid #e0a000; }
dl { display: grid; grid-template-columns: max-content auto; gap: 2px 16px; }
dt { font-weight: bold; } dd { margin: 0; font-family: "DejaVu Sans Mono", monospace; font-size: 12.5px; }
@media print { nav { display: none; } section { page-break-inside: avoid; }
  body { font-size: 10.5px; padding: 0; max-width: none; } h1 { font-size: 18px; } h2 { font-size: 14px; }
  table { font-size: 8px; } th, td { padding: 1px 3px; } p.note, p.sign { font-size: 9px; }
  img { max-width: 100%; page-break-inside: avoid; } tr { page-break-inside: avoid; } }
"""


class ReportError(RvcoaxError, ValueError):
    """A report input that cannot be used (the message names the file and the reason)."""


@dataclass(frozen=True)
class ReportInputs:
    """What a report is made of besides the sweep.

    Attributes
    ----------
    rig_source, rig_text : str
        The rig file's name and text (for the provenance tags and the hash).
    measured : MeasuredData, optional
        Measured Y (table or paths schema) to check the model against.
    measured_tolerance : Tolerance, optional
        Their measurement uncertainty (:func:`rvcoax.results.studies.check.measurement_tolerance`; by
        default the file's own, else a stated assumption).
    discrepancy : dict, optional
        The document of ``rvcoax discrepancy`` (``discrepancy.json``), with ``discrepancy_source``.
    """

    rig_source: str
    rig_text: str
    measured: object | None = None
    discrepancy: dict | None = None
    discrepancy_source: str = ""
    modes: object | None = None  # a ModalStudy (rvcoax.modes) for the section on natural frequencies
    measured_tolerance: object | None = None


def _png_uri(path: Path) -> str:
    return "data:image/png;base64," + base64.b64encode(path.read_bytes()).decode("ascii")


_VERDICT_CLASSES = {"within uncertainty": "fine", "EXCEEDS uncertainty": "exceeds"}


def _table_html(table: tables.Table) -> str:
    head = "".join(f"<th>{html.escape(c)}</th>" for c in table.columns)
    body = []
    for row in table.rows:
        cells = []
        for k, cell in enumerate(row):
            classes = []
            if k == table.verdict_column:
                classes.append(_verdict_class(cell))
            elif _numeric(cell):
                classes.append("num")
            attr = f' class="{" ".join(classes)}"' if classes else ""
            cells.append(f"<td{attr}>{html.escape(cell)}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    note = f'<p class="note">{html.escape(table.note)}</p>' if table.note else ""
    return (f"<table><caption>{html.escape(table.caption)}</caption><thead><tr>{head}</tr></thead>"
            f"<tbody>{''.join(body)}</tbody></table>{note}")


def _verdict_class(cell: str) -> str:
    """The colour class of a verdict cell: fine, within (near a limit) or exceeds."""
    if cell in _VERDICT_CLASSES:
        return _VERDICT_CLASSES[cell]
    if cell.startswith(("EXCEEDS", "BELOW")):
        return "exceeds"
    if cell in ("within rating", "above minimum load"):
        return "fine"
    if cell.startswith("above rated"):
        return "within"
    return {"fine": "fine", "within": "within"}.get(cell.split(" ")[0], "none")


def _numeric(text: str) -> bool:
    try:
        float(text.replace("%", "").replace("+", ""))
        return True
    except ValueError:
        return text == "–"


def _section(key: str, body: str) -> str:
    return f'<section id="{key}"><h2>{html.escape(REPORT_SECTIONS[key])}</h2>\n{body}\n</section>'


def _missing(text: str) -> str:
    return f'<p class="missing">{html.escape(text)}</p>'


def _warnings_html(sweep, entries: list[dict]) -> str:
    """The sweep's bearing and reducer warnings (:func:`rvcoax.results.engineering.engineering_warnings`, the
    console's sentences) and its torque-path warnings (:func:`rvcoax.results.torque_path.torque_path_warnings`),
    one note each."""
    points = {**sweep.solver_report.get("ball_bearing_operating_points", {}),
              **sweep.solver_report.get("rolling_bearing_operating_points", {})}
    warnings = engineering_warnings(sweep.rig, entries, points) + torque_path_warnings(entries)
    return "".join(_missing(f"Warning: {w}") for w in warnings)


def _tilt_figure(sweep, path: Path) -> Path:
    """β (paper 000) and the true tilt of both measured shafts against their torque, µrad."""
    from matplotlib.figure import Figure

    from rvcoax.results.io.writers import write_png_atomic

    figure = Figure(figsize=(12, 4.2), dpi=110, layout="constrained")
    axes = figure.subplots(1, 2)
    for axis, shaft, key, label in ((axes[0], "input", "input_torque_Nm", "T1 (input torque) [N·m]"),
                                    (axes[1], "output", "output_torque_Nm", "T2 (output torque) [N·m]")):
        torque = np.array([getattr(c.case, key) for c in sweep.cases])
        order = np.argsort(torque, kind="stable")
        beta = np.array([c.paths[shaft].beta_deg for c in sweep.cases]) * math.pi / 180 * 1e6
        tilt = np.array([c.paths[shaft].fitted_tilt_deg for c in sweep.cases]) * math.pi / 180 * 1e6
        axis.plot(torque[order], beta[order], "o-", ms=3, label="β = arcsin(Y_max / L) (paper 000)")
        axis.plot(torque[order], tilt[order], "s-", ms=3, label="true tilt (least-squares slope)")
        axis.axhline(0.0, color="black", lw=0.6)
        axis.set_xlabel(label)
        axis.set_ylabel(f"{shaft} shaft [µrad]")
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=8, loc="best")
    figure.suptitle("tilt of the measured shafts against torque")
    return write_png_atomic(path, figure)


def _pictures(sweep, folder: Path, deformed_view: bool) -> tuple[dict[str, Path], str]:
    from rvcoax.results.io.bending_line import plot_bending_line
    from rvcoax.results.io.pictures import plot_y_vs_torque

    name = sweep.rig.rig.name
    drawn = {"bending": plot_bending_line(sweep, folder / "bending_line.png", title=name),
             "y": plot_y_vs_torque(sweep, folder / "y_vs_torque.png", title=name, micro=True),
             "tilt": _tilt_figure(sweep, folder / "tilt.png")}
    note = ""
    if deformed_view:
        from rvcoax.results.io.fields import sweep_field_cases, sweep_field_mesh
        from rvcoax.results.io.pictures import RenderingUnavailableError, render_deformed

        mesh, paths = sweep_field_mesh(sweep)
        cases = sweep_field_cases(sweep)
        largest = max(range(len(cases)), key=lambda i: float(np.abs(cases[i].displacement_m).max()))
        case = cases[largest]
        try:
            info = render_deformed(mesh, case, folder / "deformed.png", paths=paths,
                                   bearings_x_mm=[b.x_mm for b in sweep.rig.bearings],
                                   title=f"{name}: T1 = {case.T1_input_Nm:g} N·m, T2 = {case.T2_output_Nm:g} N·m")
            drawn["deformed"] = info["path"]
        except RenderingUnavailableError as error:
            note = f"The deformed view was not drawn: {error}"
    return drawn, note


def _parameter_text(name: str, value) -> str:
    """``name = value unit`` for a fitted parameter, written as a number or as {value, unit, bounds}."""
    if isinstance(value, dict) and isinstance(value.get("value"), int | float):
        return f"{name} = {value['value']:.4g} {value.get('unit', '')}".rstrip()
    return f"{name} = {value:.4g}" if isinstance(value, float) else f"{name} = {value}"


def _discrepancy_html(document: dict, source: str) -> str:
    """The discrepancy section: the verdict and its figures, the gap table, the effects added (or candidates)."""
    rows = _verdict_rows(document) + _figure_rows(document)
    parts = ["<dl>" + "".join(f"<dt>{html.escape(k)}</dt><dd>{html.escape(str(v))}</dd>" for k, v in rows) + "</dl>"]
    parts += _gap_table_html(document)
    parts.append(_effects_html(document))
    parts.append(f'<p class="note">From {html.escape(source)} (rvcoax {html.escape(str(document.get("rvcoax_version", "?")))}).</p>')
    return "\n".join(parts)


def _verdict_rows(document: dict) -> list[tuple[str, str]]:
    """(label, text) of the verdict, the summary (or headline) and the reasons."""
    rows = []
    verdict = document.get("verdict")
    if isinstance(verdict, str):
        confident = document.get("confident")
        rows.append(("verdict", verdict + ("" if not isinstance(confident, bool) else
                                           " (confident)" if confident else " (not a confident single name)")))
    summary = document.get("summary")
    if isinstance(summary, str):
        rows.append(("summary", summary))
    elif isinstance(summary, list):
        rows += [("summary" if i == 0 else "", str(line)) for i, line in enumerate(summary)]
    elif isinstance(document.get("headline"), str):
        rows.append(("headline", document["headline"]))
    reasons = document.get("reasons")
    if isinstance(reasons, list):
        rows += [("why" if i == 0 else "", str(reason)) for i, reason in enumerate(reasons)]
    return rows


def _figure_rows(document: dict) -> list[tuple[str, str]]:
    """(label, text) of the measured data, the RMS gaps, the generic load, the cross-validation, the observability."""
    rows = []
    measured = document.get("measured") or {}
    if isinstance(measured, dict) and measured:
        rows.append(("measured data", f"{measured.get('source', '?')} ({measured.get('schema', '?')} schema, "
                                      f"{measured.get('observations', '?')} values in {measured.get('cases', '?')} "
                                      "cases)"))
    for key, label in (("rms_before_mm", "RMS gap before"), ("rms_after_mm", "RMS gap after")):
        value = document.get(key)
        if isinstance(value, int | float):
            rows.append((label, f"{value * 1e3:.4g} µm"))
        elif isinstance(value, dict) and value:
            rows.append((label, ", ".join(f"{shaft} shaft {v * 1e3:.4g} µm" for shaft, v in value.items()
                                          if isinstance(v, int | float))))
    sentinel = document.get("sentinel")
    if isinstance(sentinel, dict) and isinstance(sentinel.get("description"), str):
        rows.append(("closest generic load (outside the vocabulary)", sentinel["description"]))
    folds = document.get("cross_validation")
    if isinstance(folds, dict):
        for name, figures in folds.items():
            if isinstance(figures, dict) and isinstance(figures.get("reduction_of_chi2"), int | float):
                rows.append((f"cross-validation, {name}",
                             f"held-out χ² reduced by {100 * figures['reduction_of_chi2']:.1f} % over "
                             f"{figures.get('folds', '?')} folds ({figures.get('held_out_observations', '?')} "
                             f"held-out values); improves: {'yes' if figures.get('improves') else 'no'}"))
    observability = document.get("observability")
    if isinstance(observability, dict):
        visible = observability.get("detectable", observability.get("visible")) or []
        invisible = observability.get("invisible") or {}
        if isinstance(visible, list) and isinstance(invisible, dict):
            revealable = sum(1 for v in invisible.values() if isinstance(v, dict) and v.get("revealed_by"))
            rows.append(("what these data can reveal", f"{len(visible)} of {len(visible) + len(invisible)} "
                         f"effects: {', '.join(map(str, visible)) or 'none'}"))
            rows.append(("what they cannot reveal", f"{len(invisible)} effects, {revealable} of them with one "
                         "more measurement (listed in discrepancy.json under observability)"))
    return rows


def _gap_table_html(document: dict) -> list[str]:
    """The table of RMS gaps before and after, per case subset and shaft (empty without one)."""
    parts = []
    gaps = document.get("rms")
    if isinstance(gaps, dict) and gaps:
        gap_rows = []
        for subset, table in gaps.items():
            if not isinstance(table, dict):
                continue
            for shaft in (table.get("rms_before_um") or {}):
                def cell(key, shaft=shaft, table=table):
                    value = (table.get(key) or {}).get(shaft)
                    return f"{value:.4g}" if isinstance(value, int | float) else "–"
                gap_rows.append((subset.replace("_", " "), shaft, cell("rms_before_um"), cell("rms_after_um"),
                                 cell("rms_tilt_before_urad"), cell("rms_tilt_after_urad")))
        if gap_rows:
            parts.append(_table_html(tables.Table(
                "Gap between measurement and model, before and after the named effects",
                ("cases", "shaft", "RMS Y gap before [µm]", "after [µm]", "RMS tilt gap before [µrad]", "after [µrad]"),
                tuple(gap_rows), note="fit: the cases the effects were fitted on; held out: cases not used to fit.")))
    return parts


def _effects_html(document: dict) -> str:
    """The effects added to the model (explained) or the candidates (not a fix), or a sentence saying none was."""
    verdict = document.get("verdict")
    meanings = {n.get("effect"): n.get("meaning") for n in document.get("named") or [] if isinstance(n, dict)}
    selected = document.get("selected") or []
    if selected:
        effect_rows = tuple((str(s.get("effect", "?")),
                             str(meanings.get(s.get("effect")) or ""),
                             "; ".join(_parameter_text(k, v) for k, v in (s.get("parameters") or {}).items()),
                             ", ".join(str(g) for g in (s.get("group") or []) if g != s.get("effect")))
                            for s in selected if isinstance(s, dict))
        title = {"explained": "Effects added to the model",
                 "ambiguous": "Candidate effects (each one of several look-alikes that close the gap; not a fix)"}.get(
            verdict, "Candidate effects (they reduce the gap but do not explain it; not a fix)")
        return _table_html(tables.Table(title, ("effect", "what it means", "parameters",
                                               "equally well on these data"), effect_rows))
    return "<p>No effect was added to the model.</p>"


def read_discrepancy(path: str | Path) -> dict:
    """The document of a ``discrepancy.json``; :class:`ReportError` names the file when it is not one.

    Parameters
    ----------
    path : str or Path
        A ``discrepancy.json`` written by ``rvcoax discrepancy --out``.

    Returns
    -------
    dict
        Its document.
    """
    from rvcoax.geometry.inputfiles import InputFileError, read_input_text

    path = Path(path)
    try:  # (a device such as /dev/zero, a pipe or a huge file is refused before it is read)
        text = read_input_text(path, MAX_DISCREPANCY_BYTES, "a discrepancy result")
    except InputFileError as error:
        raise ReportError(f"discrepancy result {path}: {error}") from None
    try:
        document = json.loads(text)
    except json.JSONDecodeError as error:
        raise ReportError(f"discrepancy result {path}: not a JSON file ({error})") from None
    except RecursionError:
        raise ReportError(f"discrepancy result {path}: arrays or objects are nested too deeply (not a "
                          "discrepancy.json of rvcoax discrepancy)") from None
    if not isinstance(document, dict) or "verdict" not in document:
        raise ReportError(f"discrepancy result {path}: has no 'verdict' key; give the discrepancy.json written by "
                          "rvcoax discrepancy --out")
    problem = _discrepancy_type_problem(document)
    if problem is not None:
        raise ReportError(f"discrepancy result {path}: {problem}; give the discrepancy.json written by rvcoax "
                          "discrepancy --out")
    return document


MAX_DISCREPANCY_BYTES = 64_000_000  # a discrepancy.json is kilobytes; anything near this is not one

_NUMBER = (int, float)
_TEXT = (str,)
_NAMES = {dict: "an object", list: "an array", str: "a string", bool: "true or false", int: "a number",
          float: "a number", type(None): "null"}


def _kind(value) -> str:
    return "a number" if isinstance(value, _NUMBER) and not isinstance(value, bool) else _NAMES.get(type(value), "?")


def _is(value, types) -> bool:
    return isinstance(value, types) and not (isinstance(value, bool) and bool not in types)


# key → the JSON types the report reads there (any other key is not read, and not checked)
_DISCREPANCY_TYPES = {
    "verdict": _TEXT, "confident": (bool,), "summary": (str, list), "headline": _TEXT, "reasons": (list,),
    "measured": (dict,), "rms_before_mm": (int, float, dict), "rms_after_mm": (int, float, dict),
    "sentinel": (dict,), "cross_validation": (dict,), "observability": (dict,), "rms": (dict,), "named": (list,),
    "selected": (list,), "rvcoax_version": (str, int, float),
}


def _discrepancy_type_problem(document: dict) -> str | None:
    """What in ``document`` has a JSON type the report cannot read (key path, what it is, what it should be)."""
    def wrong(where: str, value, types) -> str | None:
        if value is None or _is(value, types):
            return None
        expected = " or ".join(dict.fromkeys(_NAMES[t] for t in types))
        return f"'{where}' is {_kind(value)}, expected {expected}"

    checks = [(key, document.get(key), types) for key, types in _DISCREPANCY_TYPES.items()]
    for key in ("rms_before_mm", "rms_after_mm"):
        if isinstance(document.get(key), dict):
            checks += [(f"{key}.{k}", v, _NUMBER) for k, v in document[key].items()]
    observability = document.get("observability")
    if isinstance(observability, dict):
        checks += [("observability.visible", observability.get("visible"), (list,)),
                   ("observability.invisible", observability.get("invisible"), (dict,))]
    for subset, table in (document.get("rms") or {}).items() if isinstance(document.get("rms"), dict) else ():
        checks.append((f"rms.{subset}", table, (dict,)))
        for key, values in (table.items() if isinstance(table, dict) else ()):
            checks.append((f"rms.{subset}.{key}", values, (dict,)))
            checks += [(f"rms.{subset}.{key}.{k}", v, _NUMBER) for k, v in
                       (values.items() if isinstance(values, dict) else ())]
    for key in ("named", "selected"):
        for i, item in enumerate(document.get(key) or []) if isinstance(document.get(key), list) else ():
            checks.append((f"{key}[{i}]", item, (dict,)))
            if isinstance(item, dict):
                checks += [(f"{key}[{i}].effect", item.get("effect"), _TEXT)]
                if key == "named":
                    checks.append((f"{key}[{i}].meaning", item.get("meaning"), _TEXT))
                else:
                    checks += [(f"{key}[{i}].parameters", item.get("parameters"), (dict,)),
                               (f"{key}[{i}].group", item.get("group"), (list,))]
                    for name, value in (item.get("parameters") or {}).items() \
                            if isinstance(item.get("parameters"), dict) else ():
                        checks.append((f"{key}[{i}].parameters.{name}", value, (int, float, dict, str)))
                        if isinstance(value, dict):
                            checks.append((f"{key}[{i}].parameters.{name}.value", value.get("value"), _NUMBER))
    for where, value, types in checks:
        problem = wrong(where, value, types)
        if problem is not None:
            return problem
    return None


def _provenance_html(sweep, inputs: ReportInputs, created: str) -> str:
    from rvcoax.results.io.records import model_section, rvcoax_version, text_sha256

    model = model_section(sweep)
    mesh = {k: v for k, v in model.items() if "mesh" in k or "element_length" in k or k == "solid_parts"}
    items = [("rvcoax version", rvcoax_version()), ("rig", sweep.rig.rig.name),
             ("rig file", inputs.rig_source), ("rig file SHA-256", text_sha256(inputs.rig_text)),
             ("model", sweep.settings.model), ("solver", sweep.solver or sweep.settings.solver),
             ("unknowns (DOF)", str(sweep.n_dofs)),
             ("mesh", ", ".join(f"{k} = {json.dumps(v, ensure_ascii=False)}" for k, v in mesh.items()) or "–"),
             ("Y measured from", sweep.rig.paths.measured_from.replace("_", " ")),
             ("created", created)]
    return "<dl>" + "".join(f"<dt>{html.escape(k)}</dt><dd>{html.escape(str(v))}</dd>" for k, v in items) + "</dl>"


def _modes_html(study, folder: Path) -> str:
    if study is None:
        return _missing("No modal analysis given (rvcoax report --modes N, or write_report(..., modes=rvcoax.modes(rig))).")
    from rvcoax.results.reports.modes_section import modes_section_html

    return modes_section_html(study, folder, _table_html, _png_uri)


PAPER_SIZES = {"a4": "A4", "letter": "letter"}
"""The page sizes a report prints on (``--paper``), as its CSS ``@page`` rule names them; A4 by default."""


def _signature_html(sweep, inputs: ReportInputs, created: str) -> str:
    """The line under the title that signs the report: rig file, its SHA-256, rvcoax version, date."""
    from rvcoax.results.io.records import rvcoax_version, text_sha256

    items = (("rig file", inputs.rig_source), ("SHA-256", text_sha256(inputs.rig_text)),
             ("rvcoax", rvcoax_version()), ("created", created))
    return ('<p class="sign">' + " · ".join(f"{html.escape(k)}: <code>{html.escape(v)}</code>" for k, v in items)
            + "</p>")


def _decides_html(sweep, inputs: ReportInputs) -> str:
    from rvcoax.results.studies.decides import what_decides_y

    assumed = tables.assumed_inputs(sweep.rig, inputs.rig_text)
    if not assumed:
        return _missing("The rig file tags no numeric input [A] (an assumption): nothing to vary. Tag the values "
                        "you assumed with a comment # [A] to see which of them decide Y.")
    entries = [c.case for c in sweep.cases]
    case = entries[max(range(len(entries)), key=lambda i: (abs(entries[i].output_torque_Nm),
                                                           abs(entries[i].input_torque_Nm)))]
    return _table_html(tables.decides_table(what_decides_y(sweep.rig, assumed, case, sweep.settings)))


def _shaft_strength_html(sweep, entries) -> str:
    """The shaft stresses and DIN 743 notch safeties of the report, with the note on what is not judged."""
    shaft_tables, shaft_note = shaft_strength_tables(sweep, entries)
    return ("".join(_table_html(t) for t in shaft_tables) + (_missing(shaft_note) if shaft_note else "")
            + ("" if shaft_tables else _missing("No beam shafts in this model.")))


def report_html(sweep, inputs: ReportInputs, *, deformed_view: bool = True, created: str | None = None,  # noqa: PLR0913
                paper: str = "a4", decides: bool = True) -> str:
    """The report of ``sweep`` as one self-contained HTML document (see the module's docstring).

    ``paper``: the page size it prints on (``a4``, the default, or ``letter``), set in its ``@page`` rule,
    which headless Chromium's PDF follows. ``decides``: compute the "what decides Y" table (two more
    solves per assumed input).
    """
    if paper not in PAPER_SIZES:
        raise ReportError(f"paper size must be one of {', '.join(PAPER_SIZES)}, got {paper!r}")
    created = created or _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    with tempfile.TemporaryDirectory(prefix="rvcoax-report-") as folder:
        pictures, picture_note = _pictures(sweep, Path(folder), deformed_view)
        uris = {key: _png_uri(path) for key, path in pictures.items()}
        modes = _modes_html(inputs.modes, Path(folder))
    rig = sweep.rig
    entries = tables.case_entries(sweep)
    body = []
    body.append(_section("rig", "".join(_table_html(t) for t in tables.rig_tables(sweep, inputs.rig_text))
                         + '<p class="note">Provenance tags of the rig file: '
                         + "; ".join(f"[{k}] {v}" for k, v in tables.PROVENANCE_TAGS.items())
                         + ". An untagged value has no stated source.</p>"))
    body.append(_section("load-cases", _table_html(tables.load_case_table(sweep, entries))))
    bending = (f'<img alt="bending line of the whole rig" src="{uris["bending"]}">'
               '<p class="note">u_y, u_z and the section rotations of every part along the rig axis; the strip on '
               'top names the parts (shafts blue, housings hatched), bearings ▲ and couplings ◆.</p>')
    if "deformed" in uris:
        bending += (f'<h3>Deformed rig, largest case</h3><img alt="deformed rig" src="{uris["deformed"]}">')
    elif picture_note:
        bending += _missing(picture_note)
    body.append(_section("bending-lines", bending))
    body.append(_section("shafts", f'<img alt="Y against torque" src="{uris["y"]}">'
                                   f'<img alt="tilt against torque" src="{uris["tilt"]}">'
                         + _table_html(tables.shaft_table(sweep, entries))))
    body.append(_section("decides", _decides_html(sweep, inputs) if decides else _missing(
        "Not computed (rvcoax report --no-decides).")))
    misalignment = (tables.misalignment_tables(sweep, entries) + tables.life_tables(sweep)
                    + tables.gear_mesh_tables(sweep))
    body.append(_section("misalignment", _warnings_html(sweep, entries)
                         + ("".join(_table_html(t) for t in misalignment)
                            or _missing("The rig has no couplings or bearings."))))
    body.append(_section("shaft-strength", _shaft_strength_html(sweep, entries)))
    body.append(_section("reactions", _table_html(tables.reaction_table(sweep, entries))))
    if inputs.measured is not None:
        from rvcoax.results.sweep import run_sweep

        checked = run_sweep(rig, inputs.measured.cases, sweep.settings)
        body.append(_section("check", _table_html(tables.check_table(inputs.measured, checked,
                                                                     inputs.measured_tolerance))))
    else:
        body.append(_section("check", _missing("No measured data given (rvcoax report --measured FILE, a table "
                                               "T1_input_Nm, T2_output_Nm, Y_input_mm, Y_output_mm or a paths "
                                               "file): the model is not checked here.")))
    if inputs.discrepancy is not None:
        body.append(_section("discrepancy", _discrepancy_html(inputs.discrepancy, inputs.discrepancy_source)))
    else:
        body.append(_section("discrepancy", _missing("No discrepancy result given (rvcoax report --discrepancy "
                                                     "OUT/discrepancy.json, written by rvcoax discrepancy --out).")))
    body.append(_section("modes", modes))
    body.append(_section("inputs", "".join(_table_html(t) for t in tables.input_listing(rig, inputs.rig_text))
                         + '<p class="note">Provenance: the tag of the key\'s comment in the rig file ([S] datasheet, '
                           '[P] paper 000, [R] catalogue value from memory, [A] assumption, [D] derived); a tag on '
                           'a line of its own counts for its whole entry; "default": the key is not in the file and '
                           'takes its default; "untagged": in the file without a stated source.</p>'))
    body.append(_section("provenance", _provenance_html(sweep, inputs, created)))
    nav = "".join(f'<a href="#{k}">{html.escape(v)}</a>' for k, v in REPORT_SECTIONS.items())
    lengths = ", ".join(f"{s} {getattr(rig.paths, s).length_mm:g} mm" for s in MEASURED_SHAFTS)
    title = html.escape(rig.rig.name)
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>rvcoax report: {title}</title><style>{_STYLE}"
            f"@page {{ size: {PAPER_SIZES[paper]}; margin: 14mm 12mm; }}</style></head><body>\n"
            f"<h1>rvcoax report: {title}</h1>{_signature_html(sweep, inputs, created)}"
            f"<p class=\"sub\">{html.escape(rig.rig.description)} — "
            f"{len(sweep.cases)} load cases, {html.escape(sweep.settings.model)} model, measured shafts: "
            f"{html.escape(lengths)}. Units: µm, µrad, N, N·m unless a heading says otherwise.</p>\n"
            f"<nav>{nav}</nav>\n" + "\n".join(body) + "\n</body></html>\n")


def write_report(sweep, path: str | Path, *, rig_source: str, rig_text: str, measured=None,  # noqa: PLR0913
                 discrepancy: str | Path | dict | None = None, discrepancy_source: str = "",
                 deformed_view: bool = True, modes=None, paper: str = "a4", decides: bool = True,
                 measured_tolerance=None) -> Path:
    """Write the study report of ``sweep`` to ``path`` (one self-contained HTML file), atomically.

    Parameters
    ----------
    sweep : Sweep
        The solved sweep (its rig, cases, model and solver).
    rig_source, rig_text : str
        The rig file's name and text (provenance tags and SHA-256).
    measured : path or MeasuredData, optional
        Measured Y (table or paths schema); its cases are solved with the sweep's settings.
    discrepancy : path or dict, optional
        A ``discrepancy.json`` of ``rvcoax discrepancy``, or its document (then ``discrepancy_source``
        names where it came from).
    deformed_view : bool
        Include the rendered deformed rig of the largest case (needs off-screen rendering; when it is
        unavailable the report says why instead).
    modes : ModalStudy, optional
        The rig's natural modes (:func:`rvcoax.modes`): the mode table, interference diagram and mode shapes.
    paper : str
        ``a4`` (default) or ``letter``: the page size the report prints on.
    measured_tolerance : Tolerance, optional
        The measurement uncertainty ``measured`` is judged with (by default its file's, else stated as
        assumed).
    decides : bool
        Compute the "what decides Y" table: each [A] input of the rig file halved and doubled (two beam
        solves each, seconds for a rig of tens of assumed inputs).

    Returns
    -------
    Path
        ``path``.
    """
    from rvcoax.results.studies.discrepancy.measured import read_measured

    data = read_measured(measured) if isinstance(measured, str | Path) else measured
    source = discrepancy_source
    if isinstance(discrepancy, str | Path):
        source = str(discrepancy)
        discrepancy = read_discrepancy(discrepancy)
    inputs = ReportInputs(rig_source=rig_source, rig_text=rig_text, measured=data, discrepancy=discrepancy,
                          discrepancy_source=source or "the discrepancy document given", modes=modes,
                          measured_tolerance=measured_tolerance)
    return write_text_atomic(path, report_html(sweep, inputs, deformed_view=deformed_view, paper=paper,
                                                   decides=decides))
