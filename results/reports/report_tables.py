"""The tables of the study report (:mod:`rvcoax.results.reports.report`), as plain rows.

Each function returns a :class:`Table`: a caption, column headings with their units, and rows of
already formatted cells, so that the HTML writer only lays them out. Numbers follow one policy:
displacements in µm, angles in µrad (and degrees or arcminutes where datasheets use them), forces
in N, torques in N·m.

:func:`misalignment_tables` is the one place the coupling and bearing judgements come from; it
reads the spring states of :mod:`rvcoax.results.connections` and the allowable values of the rig
file when the schema has them (``allowable_parallel_offset_mm``, ``allowable_angular_misalignment_deg``
of a coupling; ``allowable_misalignment_arcmin`` of a bearing).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.engineering import reaction_sum

__all__ = ["BEARING_COLUMNS", "COUPLING_COLUMNS", "Column", "LISTED_SECTIONS", "PROVENANCE_TAGS", "Table",
           "assumed_inputs", "case_entries", "case_label", "decides_table", "housing_table", "input_listing",
           "check_table", "largest_case", "load_case_table", "misalignment_tables", "provenance_tags", "reaction_table",
           "rig_tables", "shaft_table", "verdict_of", "worst_cases"]

PROVENANCE_TAGS = {"S": "datasheet or catalogue", "P": "paper 000", "R": "catalogue value from memory (estimate)",
                   "A": "assumption", "D": "derived from tagged numbers"}
_TAG = re.compile(r"\[([SPRAD])\]")


@dataclass(frozen=True)
class Table:
    """A table of the report: ``caption``, ``columns`` (heading with unit) and formatted ``rows``.

    ``verdict_column``: index of a column whose cells are verdicts (coloured in the HTML), or None.
    """

    caption: str
    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    verdict_column: int | None = None
    note: str = ""


def _g(value: float, digits: int = 4) -> str:
    """A number with ``digits`` significant digits, plain (no 1e-05 for a µm value)."""
    if value is None or not math.isfinite(value):
        return "–"
    if value == 0:
        return "0"
    magnitude = math.floor(math.log10(abs(value)))
    if -4 <= magnitude < 7:
        decimals = max(digits - 1 - magnitude, 0)
        return f"{value:.{decimals}f}"
    return f"{value:.{digits - 1}e}"


# --------------------------------------------------------------------------------------------
# The rig file's provenance tags


def provenance_tags(rig_text: str) -> dict[tuple[str, str], dict[str, str]]:
    """(table, name) → {key: tags} from the ``# [S] …`` comments of a rig file.

    ``table`` is the array-of-tables a line belongs to (``parts``, ``bearings``, ``couplings``, …;
    ``materials.<name>`` for a material) and ``name`` the entry's ``name`` key (the material's name
    for materials). Tags on a line without a key (a comment line inside the entry) count for the
    entry as a whole (key ``""``).
    """
    found: dict[tuple[str, str], dict[str, str]] = {}
    table, name, pending = "", "", []
    for raw in rig_text.splitlines():
        line = raw.strip()
        code, _, comment = line.partition("#")
        header = re.match(r"^\[\[?\s*([A-Za-z0-9_.\-]+)\s*\]\]?", code.strip())
        if header:
            for key, tags in pending:  # a plain table ([gravity], [thermal], …): its tags count for the table
                _add(found, table, "", key, tags)
            table = header.group(1)
            name = table.split(".", 1)[1] if table.startswith("materials.") else ""
            table = "materials" if table.startswith("materials.") else table
            pending = []
            continue
        key_match = re.match(r"^([A-Za-z0-9_\-]+)\s*=", code.strip())
        if key_match and key_match.group(1) == "name":
            value = re.search(r"=\s*\"([^\"]*)\"", code)
            name = value.group(1) if value else name
            for key, tags in pending:
                _add(found, table, name, key, tags)
            pending = []
        tags = "".join(f"[{t}]" for t in _TAG.findall(comment))
        if not tags:
            continue
        key = key_match.group(1) if key_match else ""
        if name or table == "materials":
            _add(found, table, name, key, tags)
        else:
            pending.append((key, tags))
    for key, tags in pending:
        _add(found, table, name, key, tags)
    return found


def _add(found, table, name, key, tags):
    entry = found.setdefault((table, name), {})
    merged = dict.fromkeys(_TAG.findall(entry.get(key, "") + tags))  # each tag once, in order of appearance
    entry[key] = "".join(f"[{t}]" for t in merged)


def _tags_text(tags: dict[str, str], keys: tuple[str, ...] | None = None) -> str:
    """``key [S]; key [A]`` for the tagged keys (all when ``keys`` is None)."""
    items = [(k, v) for k, v in tags.items() if keys is None or k in keys or k == ""]
    return "; ".join(f"{k} {v}" if k else v for k, v in items) or "untagged"


# --------------------------------------------------------------------------------------------
# The rig


def _bearing_stiffness_cells(bearing) -> tuple[str, str]:
    """The radial and tilt stiffness cells of the rig's bearing table: the typed-in values of a linear bearing; for
    a bearing from internal geometry its kind (its stiffness follows from its state: see the solver's operating
    points), not the linear reference the solve is condensed on."""
    if bearing.model == "linear":
        return _g(bearing.radial_stiffness_N_per_um, 3), _g(bearing.tilt_stiffness_Nm_per_rad, 3)
    kind = {"ball": "deep-groove ball", "angular_contact": "angular-contact ball",
            "cylindrical_roller": "cylindrical roller", "tapered_roller": "tapered roller"}[bearing.model]
    pair = "" if bearing.model == "ball" or bearing.arrangement == "single" else f" {bearing.arrangement} pair"
    return f"from geometry: {kind} {bearing.designation or ''}{pair}".rstrip(), "from geometry"


def rig_tables(sweep, rig_text: str) -> list[Table]:
    """Parts (with modelled masses), bearings and couplings, each with its provenance tags."""
    rig, frame = sweep.rig, sweep.frame
    tags = provenance_tags(rig_text)
    masses = getattr(frame, "part_mass_kg", {}) or {}
    parts = []
    for p in rig.parts:
        x0, x1 = p.x_range_mm
        outer = max(s.outer_diameter_mm for s in p.segments)
        parts.append((p.name, p.role, p.material, f"{x0:g} … {x1:g}", f"{outer:g}",
                      "–" if p.mass_kg is None else _g(p.mass_kg, 3), _g(masses.get(p.name, float("nan")), 3),
                      _tags_text(tags.get(("parts", p.name), {}))))
    total = sum(masses.get(p.name, 0.0) for p in rig.parts)  # a part's modelled mass includes its coupling hubs
    tables = [Table("Parts along the rig axis", ("part", "role", "material", "x [mm]", "largest Ø [mm]",
                                                 "mass in the file [kg]", "mass as modelled [kg]", "provenance"),
                    tuple(parts), note=f"Mass of the whole rig as modelled (parts and coupling hubs): {total:.3g} kg.")]
    bearings = tuple((b.name, b.shaft, b.housing, f"{b.x_mm:g}", *_bearing_input(b),
                      _tags_text(tags.get(("bearings", b.name), {})))
                     for b in rig.bearings)
    if bearings:
        tables.append(Table("Bearings", ("bearing", "shaft", "housing", "x [mm]", "model",
                                         "radial stiffness [N/µm]", "tilt stiffness [N·m/rad]", "provenance"),
                            bearings, note="A ball bearing's stiffness follows from its geometry and load (the "
                                           "operating stiffness per case is in the bearing table below); a "
                                           "clearance's is zero inside the play."))
    couplings = tuple((c.name, f"{c.from_.part} → {c.to.part}", f"{c.centre_x_mm:g}", _g(c.mass_kg, 3),
                       _g(c.radial_stiffness_N_per_mm, 3), _g(c.angular_stiffness_Nm_per_rad, 3),
                       _tags_text(tags.get(("couplings", c.name), {}))) for c in rig.couplings)
    if couplings:
        tables.append(Table("Couplings", ("coupling", "from → to", "centre x [mm]", "mass [kg]",
                                          "radial stiffness [N/mm]", "angular stiffness [N·m/rad]", "provenance"),
                            couplings))
    if rig.housings:
        tables.append(housing_table(rig, tags))
    materials = tuple((name, _g(m.youngs_modulus_MPa, 4), _g(m.poisson_ratio, 3), _g(m.density_kg_per_m3, 4),
                       _tags_text(tags.get(("materials", name), {}))) for name, m in rig.materials.items())
    tables.append(Table("Materials", ("material", "E [MPa]", "ν", "ρ [kg/m³]", "provenance"), materials))
    return tables


LISTED_SECTIONS = ("gravity", "mesh", "beam", "paths", "torques", "parts", "bearings", "mounts", "couplings", "joints",
                   "torque_lateral_loads", "gear_meshes", "housings", "thermal", "force_table", "solid")
"""The rig file's sections the complete input listing shows (materials have their own table, load cases too)."""


def _value_text(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple | list):
        return "[" + ", ".join(_value_text(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_value_text(v)}" for k, v in value.items()) + "}"
    return str(value)


def _flatten(model, prefix: str = ""):
    """(key path, value, typed in?) of every field of a rig-file object, nested objects and lists of them
    opened (``on.part``, ``segments[1].x_mm``)."""
    from pydantic import BaseModel

    fields_set = model.model_fields_set
    for name, info in type(model).model_fields.items():
        key = info.alias or name
        value = getattr(model, name)
        if value is None:
            continue
        path = f"{prefix}{key}"
        if isinstance(value, BaseModel):
            yield from _flatten(value, f"{path}.")
        elif isinstance(value, tuple | list) and value and all(isinstance(v, BaseModel) for v in value):
            for i, item in enumerate(value):
                yield from _flatten(item, f"{path}[{i}].")
        else:
            yield path, value, name in fields_set


def input_listing(rig, rig_text: str) -> list[Table]:
    """Every input of the rig file that sets the answer, key by key, with its provenance tags: one table per
    section (mounts, joints with the reducer's main bearings, the torque-to-lateral-load table with its
    imbalance, gear stages, housings, thermal inputs, …). A key the file leaves out shows its default."""
    tags = provenance_tags(rig_text)
    tables = []
    for section in LISTED_SECTIONS:
        value = getattr(rig, section, None)
        if value is None or (isinstance(value, tuple | list) and not value):
            continue
        entries = value if isinstance(value, tuple | list) else (value,)
        rows = []
        for k, entry in enumerate(entries):
            name = getattr(entry, "name", None) or (f"[{k}]" if isinstance(value, tuple | list) else "")
            entry_tags = tags.get((section, getattr(entry, "name", None) or ""), {})
            for path, item, typed in _flatten(entry):
                if path == "name":
                    continue
                top = path.split(".", 1)[0].split("[", 1)[0]
                source = (entry_tags.get(top) or entry_tags.get("") or "untagged") if typed else "default"
                rows.append((name, path, _value_text(item), source))
        tables.append(Table(f"[{section}]" if not isinstance(value, tuple | list) else f"[[{section}]]",
                            ("entry", "key", "value", "provenance"), tuple(rows)))
    return tables


def assumed_inputs(rig, rig_text: str) -> list[tuple[str, str, str, float]]:
    """The numeric inputs tagged [A] (an assumption) in the rig file: (section, entry, key, value), for the
    "what decides Y" study. Lists (a mount's three stiffnesses) count as one input, scaled together."""
    tags = provenance_tags(rig_text)
    found = []
    for section in LISTED_SECTIONS:
        value = getattr(rig, section, None)
        if not isinstance(value, tuple | list):
            continue
        for entry in value:
            name = getattr(entry, "name", None)
            if name is None:
                continue
            entry_tags = tags.get((section, name), {})
            for key, tag in entry_tags.items():
                field = next((f for f, info in type(entry).model_fields.items() if (info.alias or f) == key), None)
                if "[A]" not in tag or field is None:
                    continue
                item = getattr(entry, field)
                numbers = item if isinstance(item, tuple | list) else (item,)
                if all(isinstance(v, int | float) and not isinstance(v, bool) for v in numbers) and any(numbers):
                    found.append((section, name, key, item))
    return found


def decides_table(decides, shown: int = 15) -> Table:
    """The "what decides Y" table of :func:`rvcoax.results.studies.decides.what_decides_y`: the assumed inputs
    ranked by the largest change of Y when halved or doubled."""
    rows = []
    for rank, influence in enumerate(decides.ranked[:shown], start=1):
        cells = [str(rank), f"{influence.section}.{influence.entry}.{influence.key}", _value_text(influence.value)]
        for shaft in MEASURED_SHAFTS:
            cells += [_g(v, 3) for v in influence.y_change_um[shaft]]
            cells += [_g(v, 3) for v in influence.tilt_change_urad[shaft]]
        rows.append(tuple(cells))
    case = decides.case
    headings = ["rank", "assumed input [A]", "value"]
    for shaft in MEASURED_SHAFTS:
        headings += [f"ΔY {shaft} ×½ [µm]", f"ΔY {shaft} ×2 [µm]", f"Δtilt {shaft} ×½ [µrad]", f"Δtilt {shaft} ×2 [µrad]"]
    base = "; ".join(f"{s}: Y = {_g(decides.y_um[s], 4)} µm, tilt = {_g(decides.tilt_urad[s], 4)} µrad"
                     for s in MEASURED_SHAFTS)
    skipped = "; ".join(f"{a}: {why}" for a, why in decides.not_varied)
    more = len(decides.ranked) - len(rows)
    return Table(f"What decides Y: each assumed input halved and doubled, case T1 = {case.input_torque_Nm:g}, "
                 f"T2 = {case.output_torque_Nm:g} N·m", tuple(headings), tuple(rows),
                 note=f"The rig as given: {base}. Every numeric key tagged [A] in the rig file is scaled by ½ and by 2 on "
                      "its own (a list of stiffnesses as a whole) and the rig solved again (beam model); ranked by the "
                      f"largest |ΔY| of either shaft. {len(decides.ranked)} inputs varied"
                      + (f", the {more} with the smallest effect not shown" if more > 0 else "") + "."
                      + (f" Not varied: {skipped}." if skipped else ""))


def housing_table(rig, tags: dict) -> Table:
    """Each condensed housing with what a bearing sees at its seats, in the load patterns that occur (N/µm)."""
    from rvcoax.geometry.model import housing_condensation, seat_stiffness

    rows = []
    for housing in rig.housings:
        condensed = housing_condensation(rig, housing)  # cached by the solve
        described = (f"{housing.shape}, {housing.material}, mesh {housing.mesh_size_mm:g} mm, feet {housing.feet}"
                     + (f", × {housing.stiffness_factor:g}" if housing.stiffness_factor != 1 else ""))
        for seat in seat_stiffness(housing, condensed.matrix):
            rows.append((housing.name, described, f"{seat.seat_x_mm:g}", seat.direction, _g(seat.together_N_per_um, 4),
                         _g(seat.alone_N_per_um, 4), _g(seat.held_N_per_um, 4),
                         _tags_text(tags.get(("housings", housing.name), {}))))
    return Table("Housings condensed from solid models: stiffness at the bearing seats",
                 ("housing", "shape", "seat x [mm]", "direction", "both seats pushed together [N/µm]",
                  "this seat alone [N/µm]", "held: diagonal of K_c [N/µm]", "provenance"), tuple(rows),
                 note="What a bearing sees at a seat depends on how the seats are loaded: together, the force per seat "
                      "when every seat is pushed the same way (a shaft's weight, a lateral gear force); alone, one seat "
                      "loaded and the other free; held, the other seat and all rotations held (the diagonal entry of "
                      "the condensed matrix, an upper bound no bearing sees). The bearing's own stiffness is in series "
                      "with these. Every dimension is in the complete input listing.")


def _bearing_input(b) -> tuple[str, str, str]:
    """(model, radial, tilt stiffness) cells of a bearing as the rig file describes it: a linear bearing's typed-in
    springs; a bearing from internal geometry by its kind, designation and clearance (its stiffness follows from
    geometry and load, per case in the bearing table), never the linear reference the solve is condensed on."""
    if b.model == "linear":
        model = f"linear, radial play {b.radial_clearance_um:g} µm" if b.radial_clearance_um > 0 else "linear"
        return model, _g(b.radial_stiffness_N_per_um, 3), _g(b.tilt_stiffness_Nm_per_rad, 3)
    kind, _ = _bearing_stiffness_cells(b)
    clearance_um, clearance_class = getattr(b, "clearance_um", None), getattr(b, "clearance_class", None)
    preload = getattr(b, "preload_N", 0.0)
    extra = ", ".join(v for v in (f"{clearance_um:g} µm clearance" if clearance_um is not None else
                                  f"clearance class {clearance_class}" if clearance_class else "",
                                  f"preload {preload:g} N" if preload else "") if v)
    return kind + (f" ({extra})" if extra else ""), "from geometry and load", "from geometry and load"


def load_case_table(sweep, entries: list[dict] | None = None) -> Table:
    entries = case_entries(sweep) if entries is None else entries
    rows = tuple((str(i + 1), f"{e['T1_input_Nm']:g}", f"{e['T2_output_Nm']:g}") for i, e in enumerate(entries))
    return Table("Load cases", ("case", "T1 input torque [N·m]", "T2 output torque [N·m]"), rows)


def shaft_table(sweep, entries: list[dict] | None = None) -> Table:
    """Per case and measured shaft: Y, the paper's β, the true tilt and the end slopes (sweep.json's
    ``engineering.shafts``)."""
    entries = case_entries(sweep) if entries is None else entries
    rows = []
    for i, entry in enumerate(entries):
        for shaft in MEASURED_SHAFTS:
            q = entry["engineering"]["shafts"][shaft]
            rows.append((str(i + 1), f"{entry['T1_input_Nm']:g}", f"{entry['T2_output_Nm']:g}", shaft,
                         _g(q["Y_max_um"]), _g(q["beta_paper_urad"]), _g(q["tilt_urad"]),
                         _g(q["end_slopes_urad"][0]), _g(q["end_slopes_urad"][1])))
    return Table("Measured shafts: displacement and tilt",
                 ("case", "T1 [N·m]", "T2 [N·m]", "shaft", "Y_max [µm]", "β paper 000 = arcsin(Y_max/L) [µrad]",
                  "true tilt: slope of the least-squares line [µrad]", "slope at start [µrad]",
                  "slope at end [µrad]"), tuple(rows),
                 note="β as paper 000 defines it is not a tilt: a symmetric bow with level ends has β > 0. "
                      "The true tilt is the slope of the least-squares line through u_y(x). sweep.csv: Y_<shaft>_um, "
                      "beta_paper_<shaft>_urad, tilt_<shaft>_urad, end_slope_start/end_<shaft>_urad.")


# --------------------------------------------------------------------------------------------
# Couplings and bearings: misalignment against the allowable values


def verdict_of(ratio: float | None) -> str:
    """A verdict from value / allowable: ``no allowable given``, ``fine``, ``within allowable``, ``EXCEEDS``."""
    if ratio is None:
        return "no allowable given"
    if ratio <= 0.5:
        return "fine (≤ 50 % of allowable)"
    if ratio <= 1.0:
        return "within allowable"
    return "EXCEEDS allowable"


def case_entries(sweep) -> list[dict]:
    """The sweep's cases as ``sweep.json`` holds them (:func:`rvcoax.results.io.records.case_entry`): every
    table below reads these, so the report shows the numbers the result files hold, under their names."""
    from rvcoax.results.io.records import canonical, case_entry

    return [canonical(case_entry(case)) for case in sweep.cases]


def case_label(index: int, entry: dict) -> str:
    """``3: T1 = 0.5, T2 = 70`` (the case's number in the load-case table and its torques in N·m; no-break
    spaces around the equals signs, so that a narrow column wraps only after the comma)."""
    return (f"{index + 1}: T1\u00a0=\u00a0{entry['T1_input_Nm']:g}, "
            f"T2\u00a0=\u00a0{entry['T2_output_Nm']:g}")


def _item(entry: dict, group: str, name: str) -> dict:
    return next(q for q in entry["engineering"][group] if q["name"] == name)


def worst_cases(entries: list[dict], group: str, name: str, criteria) -> list[tuple[str, int]]:
    """The worst cases of item ``name`` of ``group`` (``couplings``, ``bearings``): for each criterion
    ``(label, key)`` the case with the largest ``key``; criteria met by the same case share a row.

    Returns ``[(labels joined by "and", case index), …]`` in case order. On a tie (a bearing that carries
    nothing in every case) a case already chosen for an earlier criterion is taken, else the earliest."""
    picks: dict[int, list[str]] = {}
    for label, key in criteria:
        values = np.array([_item(e, group, name)[key] for e in entries], dtype=float)
        if not np.isfinite(values).any():
            continue
        tied = np.flatnonzero(values == np.nanmax(values))
        chosen = next((int(i) for i in tied if int(i) in picks), int(tied[0]))
        picks.setdefault(chosen, []).append(label)
    return [(" and ".join(labels), i) for i, labels in sorted(picks.items())]


@dataclass(frozen=True)
class Column:
    """A column of a worst-case table: its heading (with unit) and its cell from the item's quantities
    (a ``sweep.json`` couplings/bearings entry) in the row's case. Extend a table by adding columns."""

    heading: str
    cell: object  # callable(quantities: dict) -> str


def _percent_of(*uses) -> float | None:
    given = [u for u in uses if u is not None]
    return max(given) / 100.0 if given else None


COUPLING_COLUMNS = (
    Column("offset [µm]", lambda q: _g(q["offset_um"])),
    Column("angle [µrad]", lambda q: _g(q["angle_urad"])),
    Column("angularity [mm/100 mm]", lambda q: _g(q["angularity_mm_per_100mm"], 3)),
    Column("offset from unloaded geometry [µm]", lambda q: _g(q["offset_from_unloaded_um"])),
    Column("angle from unloaded geometry [µrad]", lambda q: _g(q["angle_from_unloaded_urad"])),
    Column("allowable offset", lambda q: f"{q['allowable_offset_mm']:g} mm" if q["allowable_offset_mm"] else "–"),
    Column("allowable angle", lambda q: f"{q['allowable_angle_deg']:g}°" if q["allowable_angle_deg"] else "–"),
    Column("alignment grade", lambda q: q["grade"] or "– (no speed_rpm)"),
)


def _coupling_table(sweep, entries: list[dict]) -> Table:
    rows = []
    for c in sweep.rig.couplings:
        for labels, i in worst_cases(entries, "couplings", c.name, (("offset", "offset_um"), ("angle", "angle_urad"))):
            q = _item(entries[i], "couplings", c.name)
            rows.append((c.name, labels, case_label(i, entries[i]), *(col.cell(q) for col in COUPLING_COLUMNS),
                         verdict_of(_percent_of(q["offset_use_percent"], q["angle_use_percent"]))))
    reference = entries[0]["engineering"]["couplings"][0]["reference"] if entries else ""
    headings = ("coupling", "largest", "case", *(col.heading for col in COUPLING_COLUMNS), "verdict")
    return Table("Couplings: misalignment between the hubs, worst cases of the sweep",
                 headings, tuple(rows), verdict_column=len(headings) - 1,
                 note=f"Each row is one load case (its number in the load-case table and its torques, N·m): the case "
                      f"with the largest offset or angle, every value from that case. Offset and angle: of the to hub "
                      f"against the from hub at the coupling centre, {reference} (the columns coupling_<name>_offset_um "
                      "and _angle_urad of sweep.csv); the verdict judges them against the coupling maker's allowable "
                      "values (rig keys allowable_parallel_offset_mm, allowable_angular_misalignment_deg). From "
                      "unloaded geometry: the same misalignment including the rig's sag under its own weight "
                      "(sweep.csv: coupling_<name>_offset_from_unloaded_um, _angle_from_unloaded_urad).")


def _maybe(value, digits=4) -> str:
    return "–" if value is None else _g(value, digits)


BEARING_COLUMNS = (
    Column("model", lambda q: q["model"]),
    Column("radial force [N]", lambda q: _g(q["force_radial_N"])),
    Column("radial force change under load [N]", lambda q: _g(q["force_radial_change_N"])),
    Column("tilt [µrad]", lambda q: _g(q["tilt_urad"])),
    Column("tilt change under load [µrad]", lambda q: _g(q["tilt_change_urad"])),
    Column("tilt [′]", lambda q: _g(q["tilt_arcmin"], 3)),
    Column("radial stiffness, operating [N/µm]", lambda q: _g(q["radial_stiffness_N_per_um"], 3)),
    Column("tilt stiffness, operating [N·m/rad]", lambda q: _g(q["tilt_stiffness_Nm_per_rad"], 3)),
)
BALL_COLUMNS = (  # a bearing from geometry's rolling elements (balls or rollers)
    Column("loaded rolling elements", lambda q: "–" if q["loaded_elements"] is None else str(q["loaded_elements"])),
    Column("largest rolling-element load [N]", lambda q: _maybe(q["max_element_load_N"])),
)


def _bearing_table(sweep, entries: list[dict]) -> Table:
    columns = BEARING_COLUMNS + (BALL_COLUMNS if any(b.model != "linear" for b in sweep.rig.bearings) else ())
    rows = []
    for b in sweep.rig.bearings:
        for labels, i in worst_cases(entries, "bearings", b.name,
                                     (("radial force", "force_radial_N"), ("tilt", "tilt_urad"))):
            q = _item(entries[i], "bearings", b.name)
            allowable = q["allowable_tilt_arcmin"]
            rows.append((b.name, f"{b.x_mm:g}", labels, case_label(i, entries[i]), *(col.cell(q) for col in columns),
                         f"{allowable:g}′" if allowable else "–",
                         verdict_of(None if q["tilt_use_percent"] is None else q["tilt_use_percent"] / 100.0)))
    headings = ("bearing", "x [mm]", "largest", "case", *(col.heading for col in columns), "allowable tilt", "verdict")
    return Table("Bearings: radial force on the shaft and tilt of the inner ring against the outer, worst cases of "
                 "the sweep", headings, tuple(rows), verdict_column=len(headings) - 1,
                 note="Each row is one load case (its number and torques, N·m): the case with the largest radial force "
                      "or tilt, every value from that case. Radial force and tilt: from the unloaded geometry "
                      "(self-weight included); change under load: since the rig at rest (sweep.csv: "
                      "bearing_<name>_force_radial_N, _force_radial_change_N, _tilt_urad, _tilt_change_urad). "
                      "Operating stiffness: the typed-in spring of a linear bearing; the tangent of the force law of a "
                      "bearing from geometry or a clearance in that case (radial: mean of y and z; tilt: mean about y and z). "
                      "Allowable tilt: rig key allowable_misalignment_arcmin (deep-groove ball bearings: 2′ … 10′ "
                      "in catalogues).")


def _life_text(value) -> str:
    if value is None:
        return "–"
    if not math.isfinite(value) or value > 1e9:
        return "> 1e9"
    return f"{value:.3g}" if value >= 1e5 else _g(value, 3)  # a life to three digits, not 5230017


def life_tables(sweep) -> list[Table]:
    """Bearing life, static safety and minimum load per case (every row names its case), the lives over the rig
    file's duty cycle, and each reducer against its rating table per case."""
    from rvcoax.results.engineering import case_name, duty_cycle_of_lives, sweep_lives, sweep_reducer_checks

    out = []
    balls = [b for b in sweep.rig.bearings if b.model == "ball"]
    if balls:
        from rvcoax.geometry.ball_model import clearance_range_um_of, operating_geometry

        rows = []
        for b in balls:
            low, high = clearance_range_um_of(sweep.rig, b)
            rows.append((b.name, b.designation or "explicit geometry", b.clearance_class or ("–" if b.clearance_um is not None else "CN"),
                         f"{b.shaft_fit or '–'} / {b.housing_fit or '–'}", f"{_g(low, 3)} … {_g(high, 3)}",
                         _g(operating_geometry(sweep.rig, b).clearance_m * 1e6, 3)))
        out.append(Table("Ball bearings: operating radial clearance (diametral)",
                         ("bearing", "designation", "class", "fits shaft / housing", "operating range [µm]",
                          "solved with [µm]"), tuple(rows),
                         note="The class's unmounted range (ISO 5753-1) less the rings' expansion by the fits' "
                              "interference (ISO 286, ISO 492, thick rings), tightest to loosest, plus the [thermal] "
                              "change; solved with the middle (fit_clearance = mean) unless chosen otherwise."))
    per_case = sweep_lives(sweep)
    rows = tuple((life.case, life.name, "–" if life.speed_rpm is None else f"{life.speed_rpm:g}",
                  _g(life.equivalent_load_N, 3), _life_text(life.L10_Mrev), _life_text(life.L10_h),
                  _life_text(life.L10r_h if life.speed_rpm else life.L10r_Mrev), _life_text(life.Lnm_h),
                  _life_text(life.static_safety), _g(life.minimum_load_N, 3), life.minimum_load_status)
                 for lives in per_case for life in lives)
    if rows:
        out.append(Table("Bearings: life, static safety and minimum load, per case",
                         ("case", "bearing", "speed [1/min]", "equivalent load P [N]", "L10 [10⁶ rev]", "L10 [h]",
                          "L10r [h, or 10⁶ rev without a speed]", "L_nm = a_ISO L [h]", "static safety s0",
                          "minimum load [N]", "minimum load"), rows, verdict_column=10,
                         note="L10: ISO 281 basic rating life (C/P)^p, p = 3 ball, 10/3 roller, from P = X F_r + "
                              "Y F_a with the X/Y of the bearing's type and set (deep groove, angular contact single/"
                              "tandem or DB/DF pair, tapered single or pair, cylindrical NJ) and its load rating C "
                              "(rig key dynamic_load_rating_kN, the catalogue, or ISO 281 from the internal geometry; "
                              "a set of i rows: i^0.7 C ball, i^(7/9) C roller); a preload the rings carry counts in P. "
                              "L10r: ISO/TS 16281 reference life from the element loads (ball loads with their contact "
                              "angles; roller lamina loads, exponent 4 per contact — (C/P)^(2/3) above L10 for a roller "
                              "bearing under C's load zone, equal at P = C); only for bearings from internal geometry. "
                              "L_nm: ISO 281's a_ISO (ball and roller) with contamination_factor and viscosity_ratio or "
                              "oil_viscosity_mm2_per_s. s0: C0/P0 (ISO 76), "
                              "or from the largest contact pressure, (4200 MPa / p_max)³ ball, (4000 MPa / p_max)² "
                              "roller. Minimum load: SKF's speed-dependent rule with the rig's minimum_load_factor "
                              "(0.02 C tapered), else 0.01 C (ball), 0.02 C (roller), on P or, from "
                              "the element loads, on the load that gives L10r (a preload counts)."))
    duty = duty_cycle_of_lives(sweep.rig, per_case)
    if duty:
        out.append(Table(f"Bearings: life over the duty cycle ({duty[0].shares} shares of the rig file's load cases)",
                         ("bearing", "L10 [h]", "L10 [10⁶ rev]", "L_nm [h]", "smallest s0", "cases below minimum load"),
                         tuple((d.name, _life_text(d.L10_h), _life_text(d.L10_Mrev), _life_text(d.Lnm_h),
                                _life_text(d.min_static_safety), "; ".join(d.cases_below_minimum_load) or "none")
                               for d in duty),
                         note="Palmgren–Miner: L = 1 / Σ (share_k / L_k) over the cases; a case at standstill adds no "
                              "damage."))
    checks = [(c.case, r) for c, case_checks in zip(sweep.cases, sweep_reducer_checks(sweep)) for r in case_checks]
    if checks:
        out.append(Table("Reducers against the maker's rating table, per case",
                         ("case", "reducer", "torque [N·m]", "of rated", "of peak", "of momentary", "moment on the "
                          "main bearings [N·m]", "of allowable moment", "axial force [N]", "of max. axial", "verdict"),
                         tuple((case_name(sweep.rig, case.input_torque_Nm, case.output_torque_Nm),
                                f"{r.name} ({r.designation})", _g(r.torque_Nm), f"{r.torque_rated_percent:.3g} %",
                                f"{r.torque_peak_percent:.3g} %", f"{r.torque_momentary_percent:.3g} %",
                                _g(r.moment_Nm, 3), f"{r.moment_use_percent:.3g} %", _g(r.axial_force_N, 3),
                                f"{r.axial_use_percent:.3g} %", r.verdict) for case, r in checks),
                         verdict_column=10,
                         note="Rated, peak (allowable acceleration/deceleration) and momentary maximum torque, "
                              "allowable moment and maximum axial load from the reducer's rating table "
                              "(geometry/data/rv_reducers.csv, tagged values); the moment is the one the model's "
                              "reducer joint carries at the main bearings' centre."))
    out.extend(torque_rating_tables(sweep))
    return out


def torque_rating_tables(sweep) -> list[Table]:
    """Each coupling and shaft (torque sensor) with a rated torque against it, per case (none without ratings)."""
    from rvcoax.results.engineering import case_name

    rated = [(c.case, r) for c in sweep.cases if c.torque_paths is not None for r in c.torque_paths.ratings]
    if not rated:
        return []
    rows = tuple((case_name(sweep.rig, case.input_torque_Nm, case.output_torque_Nm), f"{r.kind} {r.name}",
                  _g(r.torque_Nm), f"{r.rated_torque_Nm:g}", f"{r.rated_use_percent:.3g} %",
                  "–" if r.peak_torque_Nm is None else f"{r.peak_torque_Nm:g}",
                  "–" if r.peak_use_percent is None else f"{r.peak_use_percent:.3g} %", r.verdict)
                 for case, r in rated)
    return [Table("Couplings and torque sensors against their rated torque, per case",
                  ("case", "coupling or shaft", "torque carried [N·m]", "rated torque [N·m]", "of rated",
                   "peak torque [N·m]", "of peak", "verdict"), rows, verdict_column=7,
                  note="Rated (and peak) torque from the rig file's rated_torque_Nm / peak_torque_Nm (the coupling's "
                       "or torque sensor's datasheet). A coupling carries the torque about the axis its spring "
                       "transmits; a shaft (a torque sensor's measuring shaft) the largest torque entering or leaving "
                       "it through one coupling or joint, or applied to it.")]


def gear_mesh_tables(sweep) -> list[Table]:
    """Each planet mesh's misalignment in gear terms (f_Σβ, f_Σδ over the face width), per case."""
    rows = []
    for c in sweep.cases:
        if c.engineering is None:
            continue
        for g in c.engineering.gear_meshes:
            rows.append((f"T1 = {c.case.input_torque_Nm:g}, T2 = {c.case.output_torque_Nm:g}", g.name,
                         f"{g.planet} ({g.planet_angle_deg:g}°)", _g(g.face_width_mm, 3), _g(g.relative_tilt_urad, 3),
                         _g(g.f_sigma_beta_um, 3), _g(g.f_sigma_delta_um, 3)))
    if not rows:
        return []
    return [Table("Gear meshes: misalignment over the face width, per case",
                  ("case [N·m]", "gear mesh", "planet", "face width b [mm]", "relative tilt [µrad]",
                   "f_Σβ in the plane of action [µm]", "f_Σδ normal to it [µm]"), tuple(rows),
                  note="From the section rotations of the gear and its mate's carrier at the mesh (read like Y: "
                       "since the aligned rest state by default); f_Σβ is the deformation part of the mesh "
                       "misalignment ISO 6336-1's K_Hβ takes. A member modelled as a solid is left out.")]


def misalignment_tables(sweep, entries: list[dict] | None = None) -> list[Table]:
    """The coupling and bearing tables with verdicts, worst cases of the sweep, each row from one case."""
    entries = case_entries(sweep) if entries is None else entries
    tables = []
    if sweep.rig.couplings and entries:
        tables.append(_coupling_table(sweep, entries))
    if sweep.rig.bearings and entries:
        tables.append(_bearing_table(sweep, entries))
    return tables


def largest_case(entries: list[dict]) -> int:
    """The case of the largest |T2| (then |T1|): the one whose reactions the report lists."""
    return max(range(len(entries)), key=lambda i: (abs(entries[i]["T2_output_Nm"]), abs(entries[i]["T1_input_Nm"])))


SUPPORT_KINDS = {"mount": "mount", "bearing": "bearing housed in ground", "housing": "housing (as a whole)"}


def reaction_table(sweep, entries: list[dict] | None = None) -> Table:
    """Every load path to the ground (mounts, bearings housed in ground, condensed housings as a whole): the force
    and moment it exerts on the rig in the case of the largest torque, their sum against the rig's weight and
    applied forces, and the equilibrium residual."""
    entries = case_entries(sweep) if entries is None else entries
    last = largest_case(entries)
    entry = entries[last]
    reactions = entry["engineering"].get("reactions", [])
    rows = [(r["name"], SUPPORT_KINDS.get(r["kind"], r["kind"]), r["part"], f"{r['x_mm']:g}",
             *(_g(v, 4) for v in r["force_N"]), *(_g(v, 4) for v in r["moment_Nm"]), _g(r["force_change_N"][1], 4))
            for r in reactions]
    total, torque = reaction_sum(reactions)
    applied = entry["engineering"].get("applied_force_N", [0.0, 0.0, 0.0])
    rows.append(("sum of the reactions", "", "", "", *(_g(v, 4) for v in total), _g(torque, 4), "", "", ""))
    rows.append(("− (weight and applied loads)", "", "", "", *(_g(-v + 0.0, 4) for v in applied),
                 _g(-entry["engineering"].get("applied_torque_x_Nm", 0.0) + 0.0, 4), "", "", ""))
    residual = entry["engineering"]["equilibrium_residual"]
    worst = max(e["equilibrium_relative_error"] for e in entries)
    return Table(f"Support reactions on the rig, case {case_label(last, entry)} N·m",
                 ("support", "kind", "part", "x [mm]", "F_x [N]", "F_y [N]", "F_z [N]", "M_x [N·m]", "M_y [N·m]",
                  "M_z [N·m]", "F_y change under load [N]"), tuple(rows),
                 note="Force and moment each support to the ground exerts on the rig, from the unloaded geometry "
                      "(self-weight included), the moment about the support point (a housing: the centre of its "
                      "attachments). The reactions' forces sum to minus the loads on the rig: its weight (parts, "
                      "coupling hubs, housings with self_weight) and the applied forces (the torque-to-lateral-load "
                      "table, gear contact); their moments about the axis (M_x) to minus the applied torques. "
                      f"Residual of this case: {residual['force_N']:.1e} N, "
                      f"{residual['moment_Nm']:.1e} N·m; relative equilibrium error, largest over the {len(entries)} "
                      f"cases: {worst:.1e}. Values below 1e-9 of the largest support force are rounding and shown "
                      "as 0.")


def check_table(measured, sweep, tolerance=None) -> Table:
    """Measured data (table or paths schema) against the model, row by row (µm), each value judged with the
    measurement uncertainty (``tolerance``: :func:`rvcoax.results.studies.check.measurement_tolerance`; the
    file's own, else the stated assumption)."""
    from rvcoax.results.studies.check import measurement_tolerance
    from rvcoax.results.studies.discrepancy.measured import check_stations

    tolerance = measurement_tolerance(measured) if tolerance is None else tolerance
    lengths = {s: getattr(sweep.rig.paths, s).length_mm for s in MEASURED_SHAFTS}
    check_stations(measured, lengths)
    rows, gaps, outside = [], [], 0
    for k in range(measured.n):
        case_index = int(measured.case_index[k])
        case = sweep.cases[case_index]
        shaft = str(measured.shaft[k])
        path = case.paths[shaft]
        if measured.schema == "table":
            model = path.y_max_mm
            where = "Y_max"
        else:
            model = float(np.interp(measured.x_mm[k], path.station_mm, path.uy_mm))
            where = f"x = {measured.x_mm[k]:g} mm"
        value = float(measured.value_mm[k])
        limit = tolerance.limit(f"Y_{shaft}_mm", value, lengths[shaft])
        within = abs(model - value) <= limit
        outside += not within
        gaps.append(model - value)
        rows.append((f"{case.case.input_torque_Nm:g}", f"{case.case.output_torque_Nm:g}", shaft, where,
                     _g(value * 1e3), _g(model * 1e3), _g((model - value) * 1e3),
                     f"{100 * (model - value) / value:+.1f} %" if value else "–", _g(limit * 1e3, 3),
                     "within uncertainty" if within else "EXCEEDS uncertainty"))
    rms = float(np.sqrt(np.mean(np.square(gaps)))) * 1e3 if gaps else float("nan")
    return Table(f"Model against {measured.name} ({measured.schema} schema, file {measured.source})",
                 ("T1 [N·m]", "T2 [N·m]", "shaft", "where", "measured [µm]", "model [µm]", "model − measured [µm]",
                  "relative", "uncertainty [µm]", "verdict"), tuple(rows), verdict_column=9,
                 note=f"RMS of model − measured: {_g(rms, 3)} µm over {len(rows)} values; {outside} outside the "
                      f"uncertainty. Judged with: {tolerance.description}.")
