"""ADAMS/Solver dataset fragment (``.adm``) of the shaft tilts, and a reader that checks such datasets.

The fragment holds, for a dynamics model in ADAMS (paper 000 feeds its ANSYS tilts into one):

- per load case and measured shaft, a ``MARKER`` whose z axis is the shaft axis tilted by β in the
  vertical plane (ADAMS joints turn about a marker's z axis). It sits on the path's start on the
  drivetrain axis; the tilt turns about global z in the direction of the shaft's least-squares
  line (:func:`rvcoax.results.export.dynamics.tilt_direction`), by paper 000's β = arcsin(Y_max / L);
- per shaft, a ``SPLINE`` of β (degrees) against that shaft's torque (N·m): a single curve when each
  case has its own torque, a family of curves (one per value of the other torque, ADAMS's
  ``Y=z, y1, …, yn``) when the cases form a full (T1, T2) grid. Use it in a function expression
  as ``AKISPL(torque, other_torque, id) * DTOR`` (radians).

Lengths are in mm (the rig's axes: x along the drivetrain from the motor flange face, y up); angles
carry ADAMS's ``D`` suffix. The fragment has no title line, ``UNITS`` or ``END``: paste it into a
dataset with ``UNITS/LENGTH = MILLIMETER`` whose part ``part_id`` is the ground (or the frame the
markers belong to).

Dataset rules kept and checked by :func:`parse_adm`: at most 80 characters per line; ``!`` starts a
comment; a line starting with ``,`` continues the statement above (also in the middle of a list of
values); ``NAME/id`` opens a statement, followed by comma-separated arguments ``KEY=v1, v2, …`` or
conditional keywords; a SPLINE needs at least four strictly increasing x values.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.results.export.dynamics import DynamicsExport, tilt_direction
from rvcoax.results.io.writers import write_text_atomic

__all__ = ["AdamsExportError", "AdamsSyntaxError", "LINE_LIMIT", "MARKER_BASE_ID", "OTHER_TORQUE", "Statement",
           "adams_angle_deg", "adams_fragment", "adams_real", "marker_euler_deg", "marker_z_axis", "parse_adm",
           "spline_curves", "spline_data", "spline_layout", "write_adams"]

LINE_LIMIT = 80
MARKER_BASE_ID = {"input": 1000, "output": 2000}
"""Marker of case i (0-based) of a shaft: base + i + 1; the shaft's SPLINE has the base id."""
OTHER_TORQUE = {"input": "output", "output": "input"}

_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([EeDd][+-]?\d+)?$")
_KEYWORD = re.compile(r"^[A-Z][A-Z0-9_]*$")
_HEAD = re.compile(r"^([A-Z][A-Z0-9_]*)(?:/(\d+))?$")


class AdamsExportError(RvcoaxError, ValueError):
    """The cases cannot be written as ADAMS splines (the message says why)."""


class AdamsSyntaxError(RvcoaxError, ValueError):
    """A dataset line that breaks the ADAMS/Solver statement rules; the message names the line."""

    def __init__(self, line: int, problem: str):
        super().__init__(f"line {line}: {problem}")
        self.line = line


def _real(value: float) -> str:
    """A real as ADAMS reads it, with every digit of the double (round trip)."""
    return f"{float(value):.16E}"


def _wrap(head: str, arguments: list[tuple[str, list[str]]]) -> list[str]:
    """``head`` then each ``KEY=v1, v2, …`` argument on continuation lines of at most 80 characters."""
    lines = [head]
    for key, values in arguments:
        line = f", {key}=" if values else f", {key}"
        for i, value in enumerate(values):
            piece = value if i == 0 else f", {value}"
            if len(line) + len(piece) > LINE_LIMIT:  # the list goes on on a continuation line
                lines.append(line)
                line = ", " + value
            else:
                line += piece
        lines.append(line)
    return lines


def _torque(case, shaft: str) -> float:
    """The torque of a :class:`rvcoax.loadcases.cases.LoadCase` that loads ``shaft``."""
    return case.input_torque_Nm if shaft == "input" else case.output_torque_Nm


def spline_layout(cases, shaft: str) -> tuple[np.ndarray, np.ndarray | None]:
    """x values (the shaft's torques) and z values (the other torque, for a grid; else None) of its SPLINE.

    Raises :class:`AdamsExportError` when the cases cannot make an ADAMS SPLINE (fewer than 4
    different torques, or repeated torques that are not a full (T1, T2) grid).

    Parameters
    ----------
    cases : sequence of LoadCase
        The exported load cases.
    shaft : str
        ``"input"`` (x is T1) or ``"output"`` (x is T2).

    Returns
    -------
    (ndarray, ndarray or None)
        The SPLINE's x values and, for a (T1, T2) grid, its z values.
    """
    own = np.array([_torque(c, shaft) for c in cases])
    other = np.array([_torque(c, OTHER_TORQUE[shaft]) for c in cases])
    xs, zs = np.unique(own), None
    if xs.size != own.size:
        zs = np.unique(other)
        if xs.size * zs.size != own.size:
            raise AdamsExportError(
                f"{shaft} shaft: a SPLINE of β against T{1 if shaft == 'input' else 2} needs one case per torque, "
                "or a full grid of (T1, T2) pairs (--grid); these cases repeat torques without forming a grid")
    if xs.size < 4:
        raise AdamsExportError(f"{shaft} shaft: an ADAMS SPLINE needs at least 4 different torques, "
                               f"these cases have {xs.size}")
    return xs, zs


def spline_curves(export: DynamicsExport, shaft: str) -> tuple[np.ndarray, list[tuple[float | None, np.ndarray]]]:
    """x (the shaft's torque) and the β curves: [(None, β)] or one (other torque, β) per curve of a grid."""
    cases = [c.case for c in export.sweep.cases]
    xs, zs = spline_layout(cases, shaft)
    beta = {(_torque(c, shaft), _torque(c, OTHER_TORQUE[shaft])): r.paths[shaft].beta_deg
            for c, r in zip(cases, export.sweep.cases)}
    if zs is None:
        by_x = {x: b for (x, _), b in beta.items()}
        return xs, [(None, np.array([by_x[x] for x in xs]))]
    return xs, [(float(z), np.array([beta[(x, z)] for x in xs])) for z in zs]


def marker_euler_deg(tilt_deg: float) -> tuple[float, float, float]:
    """3-1-3 Euler angles (ADAMS REULER) of a marker whose z axis is global x turned by ``tilt_deg`` about global z."""
    return 90.0 + tilt_deg, 90.0, 0.0


def adams_fragment(export: DynamicsExport, part_id: int = 1) -> str:
    """The ``.adm`` fragment: tilted shaft markers per case and β-versus-torque splines per shaft.

    Parameters
    ----------
    export : DynamicsExport
        From :func:`rvcoax.results.export.dynamics_export`.
    part_id : int
        The ADAMS PART the markers belong to.

    Returns
    -------
    str
        The dataset text, ready to merge into an ``.adm`` model.
    """
    sweep = export.sweep
    if len(sweep.cases) >= 1000:
        raise AdamsExportError(f"{len(sweep.cases)} cases: the marker numbering allows at most 999")
    lines = [
        f"! rvcoax dynamics export: {sweep.rig.rig.name}",
        f"! model {sweep.settings.model}; beta = arcsin(Y_max / L) from the {export.measured_from} state",
        "! lengths mm (UNITS/LENGTH = MILLIMETER), angles in degrees (D), torques N*m",
        f"! PART={part_id}: the part that carries the markers (normally the ground)",
    ]
    for shaft in MEASURED_SHAFTS:
        path = getattr(sweep.rig.paths, shaft)
        base = MARKER_BASE_ID[shaft]
        lines.append("!")
        lines.append(f"! {shaft} shaft ({path.part}), L = {path.length_mm:g} mm: marker z = tilted shaft axis")
        for i, case in enumerate(sweep.cases):
            result = case.paths[shaft]
            tilt = tilt_direction(result) * result.beta_deg
            lines.append(f"! T1 = {case.case.input_torque_Nm:g} N*m, T2 = {case.case.output_torque_Nm:g} N*m, "
                         f"beta = {result.beta_deg:.6g} deg")
            euler = [f"{_real(a)}D" for a in marker_euler_deg(tilt)]
            lines += _wrap(f"MARKER/{base + i + 1}", [("PART", [str(part_id)]),
                                                      ("QP", [_real(path.x_start_mm), _real(0.0), _real(0.0)]),
                                                      ("REULER", euler)])
        xs, curves = spline_curves(export, shaft)
        torque = "T1" if shaft == "input" else "T2"
        lines.append("!")
        if curves[0][0] is None:
            lines.append(f"! {shaft} shaft: beta (deg) against {torque} (N*m)")
            arguments = [("X", [_real(x) for x in xs]), ("Y", [_real(y) for y in curves[0][1]])]
        else:
            other = "T2" if shaft == "input" else "T1"
            lines.append(f"! {shaft} shaft: beta (deg) against {torque} (N*m), one curve per {other} (N*m)")
            arguments = [("X", [_real(x) for x in xs])]
            arguments += [("Y", [_real(z)] + [_real(y) for y in ys]) for z, ys in curves]
        lines += _wrap(f"SPLINE/{base}", arguments + [("LINEAR_EXTRAPOLATE", [])])
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class Statement:
    """One dataset statement: ``name/id`` and its arguments in order (a conditional one has no values)."""

    name: str
    id: int | None
    arguments: tuple[tuple[str, tuple[str, ...]], ...]
    line: int

    def values(self, key: str) -> list[tuple[str, ...]]:
        """Every value list given for ``key`` (a SPLINE may repeat ``Y``)."""
        return [values for k, values in self.arguments if k == key]


def adams_real(token: str) -> float:
    """An ADAMS real (Fortran exponent E or D allowed)."""
    if not _NUMBER.match(token):
        raise ValueError(f"'{token}' is not a number")
    return float(token.upper().replace("D", "E"))


def adams_angle_deg(token: str) -> float:
    """An ADAMS angle in degrees: radians unless the value ends in ``D``."""
    if token.upper().endswith("D") and _NUMBER.match(token[:-1]):
        return adams_real(token[:-1])
    return math.degrees(adams_real(token))


def _is_value(token: str) -> bool:
    return bool(_NUMBER.match(token) or (token.upper().endswith("D") and _NUMBER.match(token[:-1])))


def _statement(tokens: list[tuple[str, int]]) -> Statement:
    (head, line), rest = tokens[0], tokens[1:]
    match = _HEAD.match(head.upper())
    if not match:
        raise AdamsSyntaxError(line, f"'{head}' is not a statement name NAME/id")
    name, ident = match.group(1), match.group(2)
    arguments: list[tuple[str, list[str]]] = []
    for token, at in rest:
        if "=" in token:
            key, _, value = token.partition("=")
            key, value = key.strip().upper(), value.strip()
            if not _KEYWORD.match(key) or not value:
                raise AdamsSyntaxError(at, f"'{token}' is not an argument KEY=value")
            arguments.append((key, [value]))
        elif _is_value(token) and arguments and arguments[-1][1]:
            arguments[-1][1].append(token)
        elif _KEYWORD.match(token.upper()):
            arguments.append((token.upper(), []))
        else:
            raise AdamsSyntaxError(at, f"'{token}' is neither a value nor an argument")
    return Statement(name, int(ident) if ident is not None else None,
                     tuple((k, tuple(v)) for k, v in arguments), line)


def _check_marker(s: Statement) -> None:
    for key, count in (("PART", 1), ("QP", 3), ("REULER", 3)):
        given = s.values(key)
        if len(given) != 1 or len(given[0]) != count:
            raise AdamsSyntaxError(s.line, f"MARKER/{s.id}: {key} needs exactly {count} value(s)")
    if not s.values("PART")[0][0].isdigit():
        raise AdamsSyntaxError(s.line, f"MARKER/{s.id}: PART must be an integer id")
    try:
        [adams_real(v) for v in s.values("QP")[0]]
        [adams_angle_deg(v) for v in s.values("REULER")[0]]
    except ValueError as error:
        raise AdamsSyntaxError(s.line, f"MARKER/{s.id}: {error}") from None


def _check_spline(s: Statement) -> None:
    xs, ys = s.values("X"), s.values("Y")
    try:
        x = np.array([adams_real(v) for v in xs[0]]) if len(xs) == 1 else None
        curves = [np.array([adams_real(v) for v in y]) for y in ys]
    except ValueError as error:
        raise AdamsSyntaxError(s.line, f"SPLINE/{s.id}: {error}") from None
    if x is None or x.size < 4 or np.any(np.diff(x) <= 0):
        raise AdamsSyntaxError(s.line, f"SPLINE/{s.id}: X needs at least 4 strictly increasing values")
    if len(curves) == 1 and curves[0].size == x.size:
        return
    if len(curves) < 2 or any(c.size != x.size + 1 for c in curves) or np.any(np.diff([c[0] for c in curves]) <= 0):
        raise AdamsSyntaxError(s.line, f"SPLINE/{s.id}: Y needs {x.size} values, or one Y=z, y1..y{x.size} per "
                                       "curve with z strictly increasing")


def parse_adm(text: str) -> list[Statement]:
    """Statements of a dataset (fragment), checked against the rules above; raises :class:`AdamsSyntaxError`.

    Parameters
    ----------
    text : str
        An ``.adm`` dataset or fragment.

    Returns
    -------
    list of Statement
        Each statement with its type, id and arguments.
    """
    groups: list[list[tuple[str, int]]] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        if len(raw) > LINE_LIMIT:
            raise AdamsSyntaxError(number, f"{len(raw)} characters (at most {LINE_LIMIT})")
        content = raw.split("!", 1)[0].strip()
        if not content:
            continue
        continued = content.startswith(",")
        tokens = [(t.strip(), number) for t in content.split(",")]
        if continued:
            if not groups:
                raise AdamsSyntaxError(number, "a continuation line (starting with ',') before any statement")
            tokens = tokens[1:]
        if any(not t for t, _ in tokens):
            raise AdamsSyntaxError(number, "an empty item between commas")
        if continued:
            groups[-1].extend(tokens)
        else:
            groups.append(tokens)
    statements = [_statement(g) for g in groups]
    seen: set[tuple[str, int]] = set()
    for s in statements:
        if s.name != "END" and s.id is None:
            raise AdamsSyntaxError(s.line, f"{s.name} needs an id (NAME/id)")
        if (s.name, s.id) in seen:
            raise AdamsSyntaxError(s.line, f"{s.name}/{s.id} is defined twice")
        seen.add((s.name, s.id))
        if s.name == "MARKER":
            _check_marker(s)
        elif s.name == "SPLINE":
            _check_spline(s)
    return statements


def spline_data(s: Statement) -> tuple[np.ndarray, list[tuple[float | None, np.ndarray]]]:
    """x and the curves [(None, y)] or [(z, y), …] of a parsed SPLINE."""
    x = np.array([adams_real(v) for v in s.values("X")[0]])
    ys = [np.array([adams_real(v) for v in y]) for y in s.values("Y")]
    if len(ys) == 1 and ys[0].size == x.size:
        return x, [(None, ys[0])]
    return x, [(float(y[0]), y[1:]) for y in ys]


def marker_z_axis(s: Statement) -> np.ndarray:
    """The z axis of a parsed MARKER in its part's axes (from REULER, body 3-1-3)."""
    a, b, c = (math.radians(adams_angle_deg(v)) for v in s.values("REULER")[0])

    def rz(t):
        return np.array([[math.cos(t), -math.sin(t), 0.0], [math.sin(t), math.cos(t), 0.0], [0.0, 0.0, 1.0]])

    rx = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(b), -math.sin(b)], [0.0, math.sin(b), math.cos(b)]])
    return (rz(a) @ rx @ rz(c))[:, 2]


def write_adams(export: DynamicsExport, folder: str | Path) -> list[Path]:
    """``dynamics.adm`` in ``folder``: :func:`adams_fragment`, read back by :func:`parse_adm` before it is written.

    Raises
    ------
    AdamsExportError
        The cases cannot make the splines (:func:`spline_layout`).
    """
    text = adams_fragment(export)
    parse_adm(text)  # the fragment must read back under the dataset rules it claims to follow
    return [write_text_atomic(Path(folder) / "dynamics.adm", text)]
