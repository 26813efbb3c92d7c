"""The torque path: where each applied torque leaves its shaft line, per load case.

A *shaft line* is a set of shafts (``role = "shaft"``) joined by couplings, joints or bearings between
shafts, with the part a torque ``T1``/``T2`` acts on: the motor shaft, a coupling, the input torque sensor's
shaft and the reducer's input shaft, say. The torque applied on a line (``sign × T``, about +x) leaves it
through its *exits*: the springs with torsional stiffness from a part of the line to a part outside it, or
to the ground. On a test rig it is meant to leave through one of them, the *reaction*: the reducer (its
input gear mesh, its output flange or main bearings), so that every coupling, torque sensor and shaft
section on the way carries the whole torque. Any other exit carries a share of it to the ground past
them: a torsional spring between a brake's rotor and its stator is the usual one, since the brake torque
*is* that coupling and a spring there counts it twice.

Which exit is the reaction, in this order:

1. the spring that a torque on the line names with ``reaction_spring`` (``[torques.T2] reaction_spring = "…"``);
2. the joint of a ``[[reducers]]`` entry;
3. the exit farthest along x from where the line's torque acts (a torque applied at one end of a line is
   meant to travel it to the far end).

The torque an exit carries is the moment about x the line exerts on it, from the spring's force in the
case (from the unloaded geometry; torque flows only under load): positive in the sense of the applied
torque, and the exits' torques sum to the applied torque up to torque passed on by loads (gear meshes
given as ``[[gear_meshes]]`` forces). :func:`torque_path_warnings` says, in one line per spring, when an
exit other than the reaction carries more than :data:`LEAK_PERCENT` of the applied torque.

**Rated torques** (:class:`TorqueRating`): a coupling or a shaft (a torque sensor's measuring shaft) with
``rated_torque_Nm`` (and ``peak_torque_Nm`` where its maker gives one) is checked in every case against the torque
it carries: a coupling, the moment about x its spring transmits; a shaft, the largest torque that enters or leaves
it through one spring with torsional stiffness (its couplings, joints) or is applied to it (T1, T2) — for a shaft
held between two couplings, as a torque sensor's is, the torque through its measuring section.
:func:`rvcoax.results.engineering.torque_rating_warnings` names every case above a rating.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvcoax.loadcases import LoadCase

__all__ = ["LEAK_PERCENT", "ShaftLineTorque", "TorqueExit", "TorquePaths", "TorqueRating", "rating_sentence",
           "shaft_lines", "torque_path_warnings", "torque_paths", "torque_ratings"]

LEAK_PERCENT = 2.0
"""Share of a line's applied torque (%) above which an exit other than the reaction is warned about."""

_ZERO = 1e-9  # relative to the case's torques: an applied torque below this is no torque (no share)
_AT_RATING = 100.0 * (1.0 + 1e-9)  # % of a rating: a torque equal to it up to the solve's rounding is within it


@dataclass(frozen=True)
class TorqueExit:
    """A spring through which torque leaves a shaft line in one case.

    ``spring``: ``"<kind>:<name>"``; ``torque_Nm``: the torque it carries from the line to its other side
    (positive in the sense of the line's applied torque); ``share_percent``: of the applied torque (None when
    no torque is applied)."""

    spring: str
    torque_Nm: float
    share_percent: float | None


@dataclass(frozen=True)
class ShaftLineTorque:
    """One shaft line in one case: the torque applied on it and where it leaves.

    Attributes
    ----------
    label : str
        The torques acting on the line, joined by ``_`` (``T2``; ``T1_T2`` when both act on one line).
    parts : tuple of str
        The line's parts, in the rig file's order.
    applied_Nm : float
        Σ sign × T of the torques on the line, about +x.
    reaction : str or None
        The exit meant to take the torque out of the line (``"<kind>:<name>"``), None when the line has no exit.
    reaction_rule : str
        Why it is the reaction: ``reaction_spring``, ``reducer`` or ``far end``.
    carried_Nm : float
        The torque the reaction takes: what the line's couplings and sensors carry all the way to it.
    carried_percent : float or None
        ``carried_Nm`` over ``applied_Nm``.
    exits : tuple of TorqueExit
        Every exit with torsional stiffness, the reaction first.
    """

    label: str
    parts: tuple[str, ...]
    applied_Nm: float
    reaction: str | None
    reaction_rule: str
    carried_Nm: float
    carried_percent: float | None
    exits: tuple[TorqueExit, ...]

    @property
    def leaks(self) -> tuple[TorqueExit, ...]:
        """The exits other than the reaction."""
        return tuple(e for e in self.exits if e.spring != self.reaction)


@dataclass(frozen=True)
class TorqueRating:
    """A coupling or shaft with a rated torque, in one case: the torque it carries against its rating.

    ``kind``: ``coupling`` or ``shaft``; ``torque_Nm``: |torque| it carries (N·m); ``rated_use_percent``: of
    ``rated_torque_Nm``; ``peak_use_percent``: of ``peak_torque_Nm`` (None without one)."""

    kind: str
    name: str
    torque_Nm: float
    rated_torque_Nm: float
    peak_torque_Nm: float | None
    rated_use_percent: float
    peak_use_percent: float | None

    @property
    def verdict(self) -> str:
        """``within rating``; ``above rated torque (within peak)``; ``EXCEEDS rated torque`` (no peak given) or
        ``EXCEEDS peak torque``."""
        if self.rated_use_percent <= _AT_RATING:
            return "within rating"
        if self.peak_use_percent is None:
            return "EXCEEDS rated torque"
        return "EXCEEDS peak torque" if self.peak_use_percent > _AT_RATING else "above rated torque (within peak)"

    @property
    def column(self) -> str:
        """The ``sweep.csv`` column stem: ``coupling_<name>`` or ``shaft_<name>``."""
        return f"{self.kind}_{self.name}"


@dataclass(frozen=True)
class TorquePaths:
    """Every shaft line that carries an applied torque, in one case, and every rated coupling and shaft."""

    lines: tuple[ShaftLineTorque, ...]
    ratings: tuple[TorqueRating, ...] = ()

    def row(self) -> dict:
        """The columns this case adds to ``sweep.csv``."""
        row = {}
        for line in self.lines:
            key = f"torque_line_{line.label}"
            row[f"{key}_applied_Nm"] = line.applied_Nm
            row[f"{key}_carried_Nm"] = line.carried_Nm
            row[f"{key}_carried_percent"] = line.carried_percent
            for leak in line.leaks:
                row[f"{key}_leak_{leak.spring.replace(':', '_')}_percent"] = leak.share_percent
        for r in self.ratings:
            row[f"{r.column}_torque_Nm"] = r.torque_Nm
            row[f"{r.column}_torque_rated_percent"] = r.rated_use_percent
            if r.peak_use_percent is not None:
                row[f"{r.column}_torque_peak_percent"] = r.peak_use_percent
            row[f"{r.column}_torque_verdict"] = r.verdict
        return row

    def entry(self) -> list[dict]:
        """The list this case adds to its ``sweep.json`` entry (``engineering.torque_paths``)."""
        return [{"line": line.label, "parts": list(line.parts), "applied_Nm": line.applied_Nm,
                 "reaction": line.reaction, "reaction_rule": line.reaction_rule, "carried_Nm": line.carried_Nm,
                 "carried_percent": line.carried_percent,
                 "exits": [{"spring": e.spring, "torque_Nm": e.torque_Nm, "share_percent": e.share_percent}
                           for e in line.exits]} for line in self.lines]

    def rating_entries(self) -> list[dict]:
        """The list this case adds to its ``sweep.json`` entry (``engineering.torque_ratings``)."""
        return [{**{k: getattr(r, k) for k in TorqueRating.__dataclass_fields__}, "verdict": r.verdict}
                for r in self.ratings]


def _spring_sides(rig) -> dict[tuple[str, str], tuple[str | None, str, float]]:
    """(kind, name) → (part of side a or None for the ground, part of side b, x in mm), as the frame model
    builds its springs (:func:`rvcoax.geometry.model.beam`): side b is a bearing's shaft, a mount's part, a
    coupling's or joint's ``to``."""
    sides = {("bearing", b.name): (None if b.housing == "ground" else b.housing, b.shaft, b.x_mm) for b in rig.bearings}
    sides |= {("mount", m.name): (None, m.part, m.x_mm) for m in rig.mounts}
    sides |= {("coupling", c.name): (c.from_.part, c.to.part, c.centre_x_mm) for c in rig.couplings}
    sides |= {("joint", j.name): (j.from_.part, j.to.part, j.to.x_mm) for j in rig.joints}
    return sides


def shaft_lines(rig) -> list[tuple[str, ...]]:
    """The shaft lines that a torque acts on: for T1 and T2 (in that order, a line once), the parts joined to
    the torque's part through springs between shafts, in the rig file's order."""
    shafts = {p.name for p in rig.parts if p.role == "shaft"}
    neighbours: dict[str, set[str]] = {p.name: set() for p in rig.parts}
    for a, b, _ in _spring_sides(rig).values():
        if a is not None and a in shafts and b in shafts:
            neighbours[a].add(b)
            neighbours[b].add(a)
    lines: list[tuple[str, ...]] = []
    for key in ("T1", "T2"):
        start = getattr(rig.torques, key).part
        if any(start in line for line in lines):
            continue
        found, todo = {start}, [start]
        while todo:
            for other in neighbours[todo.pop()] - found:
                found.add(other)
                todo.append(other)
        lines.append(tuple(p.name for p in rig.parts if p.name in found))
    return lines


def _reaction(rig, torques: list[str], exits: list[tuple[str, str, float]], at_mm: float) -> tuple[str | None, str]:
    """The reaction among ``exits`` ((kind, name, x_mm)) of a line with ``torques`` acting at ``at_mm``."""
    if not exits:
        return None, "no exit"
    for key in torques:
        named = getattr(rig.torques, key).reaction_spring
        if named is not None:
            match = [e for e in exits if e[1] == named]
            if match:
                return f"{match[0][0]}:{match[0][1]}", "reaction_spring"
    reducers = {r.name for r in rig.reducers}
    for kind, name, _ in exits:
        if kind == "joint" and name in reducers:
            return f"{kind}:{name}", "reducer"
    kind, name, _ = max(exits, key=lambda e: abs(e[2] - at_mm))
    return f"{kind}:{name}", "far end"


def _share(torque_Nm: float, applied_Nm: float, scale_Nm: float) -> float | None:
    return None if abs(applied_Nm) <= _ZERO * scale_Nm else 100.0 * torque_Nm / applied_Nm


def _rating(kind: str, name: str, torque_Nm: float, rated: float, peak: float | None) -> TorqueRating:
    torque = abs(float(torque_Nm)) + 0.0
    return TorqueRating(kind=kind, name=name, torque_Nm=torque, rated_torque_Nm=rated, peak_torque_Nm=peak,
                        rated_use_percent=100.0 * torque / rated,
                        peak_use_percent=None if peak is None else 100.0 * torque / peak)


def torque_ratings(rig, states, case) -> tuple[TorqueRating, ...]:
    """Every coupling and shaft with ``rated_torque_Nm``: the torque it carries in one case against its rating.

    Parameters
    ----------
    rig : Rig
    states : ConnectionStates
        The case's spring states from the unloaded geometry (one case).
    case : LoadCase
        The case (its T1 and T2, for a shaft that a torque acts on).

    Returns
    -------
    tuple of TorqueRating
        The couplings first, then the shafts, each in the rig file's order (empty when nothing is rated).
    """
    moment = states.force_on_b[0, :, 3]  # about x, on side b; side a gets the opposite
    row_of = {(n.kind, n.name): k for k, n in enumerate(states.names)}
    torsional = states.stiffness[0, :, 3] > 0.0
    out = [_rating("coupling", c.name, moment[row_of[("coupling", c.name)]], c.rated_torque_Nm, c.peak_torque_Nm)
           for c in rig.couplings if c.rated_torque_Nm is not None]
    applied = {"T1": case.input_torque_Nm, "T2": case.output_torque_Nm}
    sides = _spring_sides(rig)
    for p in rig.parts:
        if p.rated_torque_Nm is None:
            continue
        carried = [abs(float(moment[row_of[key]])) for key, (a, b, _) in sides.items()
                   if p.name in (a, b) and key in row_of and torsional[row_of[key]]]
        carried += [abs(applied[k]) for k in ("T1", "T2") if getattr(rig.torques, k).part == p.name]
        out.append(_rating("shaft", p.name, max(carried, default=0.0), p.rated_torque_Nm, p.peak_torque_Nm))
    return tuple(out)


def torque_paths(rig, springs, u_total: np.ndarray, case, *, states=None) -> TorquePaths:
    """The torque path of every shaft line that a torque acts on, in one case.

    Parameters
    ----------
    rig : Rig
    springs : SpringMotion
        :meth:`rvcoax.geometry.model.springs.SpringMotion.of` ``(frame, rig)`` of the sweep's model.
    u_total : (n_dofs,) array
        The case's displacement from the unloaded geometry.
    case : LoadCase
        The case (its ``input_torque_Nm`` T1 and ``output_torque_Nm`` T2).
    states : ConnectionStates, optional
        The case's spring states from the unloaded geometry, when already built (with nonlinear bearings'
        own laws); else from ``springs`` and ``u_total``.

    Returns
    -------
    TorquePaths
        The lines, and the rated couplings and shafts (:func:`torque_ratings`).
    """
    states = springs.states(u_total, from_rest=False) if states is None else states
    moment = states.force_on_b[0, :, 3]  # about x, at the spring's point on the axis, on side b
    row_of = {(n.kind, n.name): k for k, n in enumerate(states.names)}
    torsional = springs.stiffness[:, 3] > 0.0
    sides = _spring_sides(rig)
    value = {"T1": case.input_torque_Nm, "T2": case.output_torque_Nm}
    scale = max(abs(value["T1"]), abs(value["T2"]), 1e-300)
    out = []
    for parts in shaft_lines(rig):
        members = set(parts)
        torques = [k for k in ("T1", "T2") if getattr(rig.torques, k).part in members]
        applied = math.fsum(getattr(rig.torques, k).sign * value[k] for k in torques)
        exits, carried = [], {}
        for (kind, name), (a, b, x_mm) in sides.items():
            k = row_of.get((kind, name))
            if k is None or not torsional[k] or (a in members) == (b in members):
                continue
            # the torque the line passes on: minus the moment the spring exerts on the line's side
            carried[f"{kind}:{name}"] = float(-moment[k] if b in members else moment[k]) + 0.0
            exits.append((kind, name, x_mm))
        at = float(np.mean([getattr(rig.torques, k).x_mm for k in torques]))
        reaction, rule = _reaction(rig, torques, exits, at)
        listed = sorted(carried, key=lambda s: s != reaction)
        reached = carried.get(reaction, 0.0)
        out.append(ShaftLineTorque(
            label="_".join(torques), parts=parts, applied_Nm=applied, reaction=reaction, reaction_rule=rule,
            carried_Nm=reached, carried_percent=_share(reached, applied, scale),
            exits=tuple(TorqueExit(s, carried[s], _share(carried[s], applied, scale)) for s in listed)))
    return TorquePaths(tuple(out), torque_ratings(rig, states, case))


def _case_text(entry: dict) -> str:
    return LoadCase(entry["T1_input_Nm"], entry["T2_output_Nm"]).text


def torque_path_warnings(entries: list[dict], limit_percent: float = LEAK_PERCENT) -> list[str]:
    """One line per spring that carries more than ``limit_percent`` of an applied torque out of its shaft line
    past the line's reaction, from the ``sweep.json`` case entries (``engineering.torque_paths``).

    Parameters
    ----------
    entries : list of dict
        The ``cases`` of ``sweep.json``.
    limit_percent : float
        The share (%) above which a spring is named.

    Returns
    -------
    list of str
        The warnings, each naming the spring, its largest share with the case it occurs in, and the torque
        that reaches the reaction there (empty when every torque takes its intended path).
    """
    worst: dict[tuple[str, str], tuple[float, dict, dict, int]] = {}
    for entry in entries:
        for line in entry.get("engineering", {}).get("torque_paths", []):
            for e in line["exits"]:
                share = e["share_percent"]
                if e["spring"] == line["reaction"] or share is None or abs(share) <= limit_percent:
                    continue
                key = (line["line"], e["spring"])
                count = worst[key][3] + 1 if key in worst else 1
                if key not in worst or abs(share) > abs(worst[key][0]):
                    worst[key] = (share, entry, line, count)
                else:
                    worst[key] = (*worst[key][:3], count)
    found = []
    for (label, spring), (share, entry, line, count) in worst.items():
        kind, name = spring.split(":", 1)
        r_kind, r_name = line["reaction"].split(":", 1)
        cases = f"in all {len(entries)} cases" if count == len(entries) else f"in {count} of {len(entries)} cases"
        found.append(f"torque path: {kind} '{name}' carries {share:.3g} % of {label.replace('_', ' + ')} out of its "
                     f"shaft line ({', '.join(line['parts'])}) past the reaction, {r_kind} '{r_name}' ({cases}; "
                     f"the largest share at {_case_text(entry)}, where the reaction takes {abs(line['carried_Nm']):.4g} "
                     f"of {abs(line['applied_Nm']):.4g} N·m). A brake's rotor–stator spring counts the brake torque "
                     f"twice: give it no torsional stiffness, or name the intended reaction with "
                     f"[torques.{label.split('_')[0]}] reaction_spring")
    return found


def rating_sentence(rating: dict, case: str) -> str:
    """The warning for a rated coupling or shaft above its rated torque in ``case``, from its ``sweep.json`` entry
    (:meth:`TorquePaths.rating_entries`); :func:`rvcoax.results.engineering.torque_rating_warnings` gives one per
    case."""
    peak = "" if rating["peak_torque_Nm"] is None else (
        f", {rating['peak_use_percent']:.3g} % of the peak {rating['peak_torque_Nm']:.4g} N·m")
    return (f"{rating['kind']} {rating['name']} (rated {rating['rated_torque_Nm']:.4g} N·m) in case {case}: "
            f"{rating['verdict']} (carries {rating['torque_Nm']:.4g} N·m = {rating['rated_use_percent']:.3g} % of "
            f"rated{peak})")
