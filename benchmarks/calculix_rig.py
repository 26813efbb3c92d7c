"""Hidden-effect data from a different code: the rig's shaft line as a CalculiX (``ccx``) beam model.

The discrepancy workflow identifies with rvcoax's beam model. These data come from CalculiX, built
from the rig's **geometry** (the parsed rig file), not from rvcoax's assembled matrices:

- every part is a line of ``B32R`` beams (3-node, quadratic) on the axis, nodes at its segment ends, at
  every position something attaches or a load acts, at the path stations, and in between at most
  ``ELEMENT_MM`` (5 mm) apart; each element gets ``*BEAM SECTION, SECTION=CIRC`` (solid: CalculiX reads the
  two *diameters*) or ``SECTION=PIPE`` (hollow: outer radius, wall thickness) and the part's material
  (E, ν from the rig's table). CalculiX expands each beam into 20-node bricks (C3D20R): its bending and
  shear come from 3-D elasticity over an 8-node section, not from beam theory — the model-form
  difference against rvcoax's Timoshenko beams;
- every bearing, mount, coupling and joint is a set of ``SPRING2``/``SPRING1`` elements (``*SPRING``
  with a direction): the radial (Y, Z) stiffness as two springs at ``x ± d`` on stiff beam arms
  (E × 1000) fixed to the attachment node, each carrying half the stiffness, with
  ``d = sqrt(k_rot / k_trans)`` so that the pair also has the item's tilt stiffness (k d²); an item with
  radial stiffness but no tilt is one spring at the node (tilt alone cannot be represented this way and
  is refused); a coupling's springs act at its centre, on stiff links to its two hubs; the axial
  stiffness is one spring in X at the node. Every node that carries a spring or a point load gets a short
  radial stub beam, so that CalculiX makes it a *knot* (a rigid section): on a plain expanded node the
  force would dent the 8-node section locally (7 nm at input_B2 on the reference rig, 17 % of the input
  shaft's Y). Torsion does not couple to bending in a straight coaxial line: the torsional springs and the
  torques themselves are left out, and every part's rotation about x is held by a soft tangential spring
  (10 N·m/rad) on a radial arm (a rotation boundary condition on an expanded node would clamp its bending);
- loads: the rig's lateral loads per unit torque and the constant ``engaged`` loads of its reducer
  (``rvcoax.geometry.model.loads.located_unit_loads``: the load-sharing forces, and any hidden lateral
  load a test adds to the rig), a force on a band spread over the nodes in the band by trapezoid weights.
  One ``ccx`` run has four ``*STEP``s (T1, T2, engaged T1, engaged T2); a case is their superposition
  (linear). Self-weight, prestrain and the force table are not modelled: the generator refuses a rig that
  has them.

Hidden effects are applied to the rig with the vocabulary's own ``Effect.apply`` (a bearing's stiffness, a
load-sharing imbalance or position error, a mesh force, a torque reaction) before the deck is written; the
out-of-vocabulary load is a lateral force proportional to T2 at one station of the output shaft. The paths
are read from the ``.dat`` file and written, with noise, in the project's own two data formats (paths file,
table) by ``blind_data.noisy_observations`` / ``csv_text`` — the files the ``discrepancy`` command reads.

Usage::

    python benchmarks/calculix_rig.py --compare          # the unmodified reference rig: ccx against rvcoax
    python benchmarks/calculix_rig.py --out tests/results/studies/data/calculix   # the 13 committed files + manifest
    python benchmarks/calculix_rig.py --full .blindcache/calculix         # 264 files for the benchmark
    python benchmarks/bench_discrepancy_blind.py --sets .blindcache/calculix   # score the workflow on them

The comparison (``--compare``) appends its figures to benchmarks/RESULTS.md (``--no-record``: print only).
Coupling offsets and angles, raised mounts, thermal growth, self-weight and bearing clearances are not
generated: the deck has no prestrain, gravity or gap elements.

Needs CalculiX's ``ccx`` on the PATH (Debian: ``apt-get install calculix-ccx``); without it the script
says so and exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import blind_data  # noqa: E402

from rvcoax.geometry import MEASURED_SHAFTS  # noqa: E402
from rvcoax.geometry.effects import candidate_effects  # noqa: E402
from rvcoax.geometry.model.beam import attachment_positions  # noqa: E402
from rvcoax.geometry.model.loads import located_unit_loads  # noqa: E402
from rvcoax.geometry.schema import Rig  # noqa: E402
from rvcoax.geometry.units import MM  # noqa: E402
from rvcoax.loadcases.cases import paper_cases  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
STEPS = ("T1", "T2", "engaged_T1", "engaged_T2")
ARM_STIFFENING = 1e3
ELEMENT_MM = 5.0
TORSION_ARM_MM = 50.0
KNOT_STUB_MM = 10.0
KNOT_STUB_DIAMETER_MM = 4.0
TORSION_HOLD_NM_PER_RAD = 10.0
CCX = "ccx"


class CalculixMissing(SystemExit):
    pass


def require_ccx() -> str:
    path = shutil.which(CCX)
    if path is None:
        print("calculix_rig.py needs CalculiX's 'ccx' on the PATH (Debian: apt-get install calculix-ccx); "
              "the committed data in tests/results/studies/data/calculix do not.", file=sys.stderr)
        raise CalculixMissing(2)
    return path


@dataclass
class Deck:
    """A CalculiX input deck and where to read the measured paths in its output."""

    text: str
    path_nodes: dict  # shaft key → node numbers printed for the path
    stations_mm: dict  # shaft key → station positions from the path start (mm)
    lengths_mm: dict
    sections: dict  # shaft key → per station (node numbers, weights summing to 1): u_y there is their weighted mean


def _referenced(rig: Rig) -> dict[str, list[float]]:
    refs = attachment_positions(rig)  # where bearings, mounts, couplings and joints attach, by part (rig data)
    for loads in located_unit_loads(rig).values():
        for load in loads:
            refs[load.part].append(load.x_mm)
            if load.band_mm is not None:
                refs[load.part].extend(load.band_mm)
    for key in MEASURED_SHAFTS:
        path = getattr(rig.paths, key)
        refs[path.part].extend(np.linspace(path.x_start_mm, path.x_start_mm + path.length_mm, path.stations))
    return refs


def _positions(part, refs: list[float], element_mm: float) -> np.ndarray:
    ends = [x for s in part.segments for x in s.x_mm]
    breaks = np.unique(np.round(np.array(ends + [x for x in refs if ends[0] - 1e-9 <= x <= max(ends) + 1e-9]), 6))
    out = [breaks[0]]
    for a, b in zip(breaks[:-1], breaks[1:]):
        pieces = max(1, math.ceil((b - a) / element_mm - 1e-9))
        out.extend(np.linspace(a, b, pieces + 1)[1:])
    return np.array(out)


def _refuse(rig: Rig) -> None:
    if rig.gravity.enabled or rig.force_table.apply or getattr(rig, "thermal", None) not in (None, {}) and \
            getattr(rig.thermal, "enabled", False):
        raise ValueError("calculix_rig: self-weight, force table and thermal loads are not modelled; switch them off")
    if any(c.parallel_offset_um or c.angular_misalignment_mrad for c in rig.couplings) or \
            any(m.vertical_offset_um for m in rig.mounts):
        raise ValueError("calculix_rig: coupling misalignment and raised mounts (prestrain) are not modelled")


def build_deck(rig: Rig, element_mm: float = ELEMENT_MM, solids: dict | None = None, read_stations: int | None = None,
               solid_ties: str = "rig") -> Deck:
    """The CalculiX deck of ``rig``'s shaft line: four steps (T1, T2, engaged T1, engaged T2).

    ``solids``: part name → a solid model of that part (``calculix_solid.SolidShaft``): its C3D10 elements replace the
    part's beams; whatever attaches to it acts on points that follow the rigid motion of the attachment's face.
    ``read_stations``: read this many stations per path (default the rig's ``[paths]`` stations).
    ``solid_ties``: how those points follow a solid's face: ``rig``, as the rig file says (rvcoax's hybrid model:
    distributing, RBE3-like, unless a location says ``tie = "rigid"``), or ``rigid`` (every face a rigid ring, RBE2-like:
    the deck before issue 28's check, kept to reproduce it)."""
    _refuse(rig)
    solids = solids or {}
    refs = _referenced(rig)
    nodes: list[tuple[int, float, float, float]] = []  # (number, x, y, z mm)
    node_of: dict[tuple[str, float], int] = {}
    lines_elements = []
    materials = {}
    counter = {"node": 0, "element": 0}

    def new_node(x_mm: float, y_mm: float = 0.0, z_mm: float = 0.0) -> int:
        counter["node"] += 1
        nodes.append((counter["node"], x_mm, y_mm, z_mm))
        return counter["node"]

    solid_first = {}  # part → number of its first solid node (node k of the solid is first + k)
    for name, shaft in solids.items():
        solid_first[name] = counter["node"] + 1
        for x, y, z in shaft.nodes_mm:
            new_node(x, y, z)
    owner: dict[int, tuple[str, float]] = {}  # a point moving rigidly with a solid's face → (part, face x)
    points: dict[tuple, int] = {}
    rigid: dict[tuple[str, float], list[int]] = {}  # (part, face x) → its points, the first the rigid body's reference

    def solid_point(part: str, x_face: float, x_mm: float, y_mm: float = 0.0) -> int:
        """A node at (x_mm, y_mm, 0) in the rigid body of ``part``'s face at ``x_face``."""
        key = (part, round(x_face, 6), round(x_mm, 6), round(y_mm, 6))
        if key not in points:
            points[key] = new_node(x_mm, y_mm)
            owner[points[key]] = (part, x_face)
            rigid.setdefault((part, x_face), []).append(points[key])
        return points[key]

    def new_element() -> int:
        counter["element"] += 1
        return counter["element"]

    def beam_elements(name, xs, diameters, material, stiffen=1.0, own_first=None, own_last=None):
        """B32R elements along xs (mm); diameters (outer, inner) per element; returns the corner nodes."""
        corners = [own_first if own_first is not None else new_node(xs[0])]
        for i, (a, b) in enumerate(zip(xs[:-1], xs[1:])):
            mid = new_node(0.5 * (a + b))
            end = own_last if (own_last is not None and i == len(xs) - 2) else new_node(b)
            number = new_element()
            outer, inner = diameters[i]
            key = (material, stiffen, outer, inner)
            elset = materials.setdefault(key, f"S{len(materials) + 1}")
            lines_elements.append((elset, f"{number}, {corners[-1]}, {mid}, {end}"))
            corners.append(end)
        return corners

    part_nodes: dict[str, tuple[np.ndarray, list[int]]] = {}
    for part in rig.parts:
        if part.name in solids:
            continue
        xs = _positions(part, refs[part.name], element_mm)
        diameters = []
        for a, b in zip(xs[:-1], xs[1:]):
            mid = 0.5 * (a + b)
            segment = next(s for s in part.segments if s.x_mm[0] <= mid <= s.x_mm[1])
            diameters.append((segment.outer_diameter_mm, segment.inner_diameter_mm or 0.0))
        corners = beam_elements(part.name, xs, diameters, part.material)
        part_nodes[part.name] = (xs, corners)
        for x, n in zip(xs, corners):
            node_of[(part.name, round(float(x), 6))] = n

    def at(part: str, x_mm: float) -> int:
        if part in solids:
            return solid_point(part, x_mm, x_mm)
        xs, corners = part_nodes[part]
        k = int(np.argmin(np.abs(xs - x_mm)))
        if abs(xs[k] - x_mm) > 1e-3:
            raise KeyError(f"calculix_rig: no node of '{part}' at x = {x_mm} mm")
        return corners[k]

    springs: dict[tuple[int, int], list[tuple[int, int | None, float]]] = {}  # (dof a, dof b) → (na, nb, k)
    fixed: list[tuple[int, int, int]] = []

    knots: set[int] = set()

    def spring(dof: int, a: int | None, b: int, k: float) -> None:
        if k > 0:
            knots.update(n for n in (a, b) if n is not None)
            springs.setdefault((dof, 0 if a is None else dof), []).append((b, a, k))

    def arm(node: int, x_mm: float, d_mm: float, material: str) -> tuple[int, int]:
        """Two stiff beam arms (E × ARM_STIFFENING, Ø40 mm) from ``node`` to x − d and x + d; their ends (on a solid
        part: two points that follow the rigid motion of the node's face)."""
        if node in owner:
            part, x_fit = owner[node]
            return solid_point(part, x_fit, x_mm - d_mm), solid_point(part, x_fit, x_mm + d_mm)
        minus = new_node(x_mm - d_mm)
        beam_elements("arm", [x_mm - d_mm, x_mm], [(40.0, 0.0)], material, ARM_STIFFENING, own_first=minus,
                      own_last=node)
        plus = beam_elements("arm", [x_mm, x_mm + d_mm], [(40.0, 0.0)], material, ARM_STIFFENING, own_first=node)
        return minus, plus[-1]

    def link(node: int, x_mm: float, centre_mm: float, material: str) -> int:
        """A stiff beam from an attachment node to the item's centre (a coupling's spring acts between its hubs,
        at its centre); the node itself when they coincide."""
        if abs(centre_mm - x_mm) < 1e-6:
            return node
        if node in owner:
            return solid_point(owner[node][0], owner[node][1], centre_mm)
        return beam_elements("link", [x_mm, centre_mm], [(40.0, 0.0)], material, ARM_STIFFENING, own_first=node)[-1]

    def connect(kind, name, a_part, a_x, b_part, b_x, x_centre, k_trans, k_rot, k_axial):
        """Springs between node a (None: ground) and node b for the two lateral planes."""
        material = rig.parts[[p.name for p in rig.parts].index(b_part)].material
        b = link(at(b_part, b_x), b_x, x_centre, material)
        a = None if a_part is None else link(at(a_part, a_x), a_x, x_centre, material)
        a_x = b_x = x_centre
        if k_axial > 0:
            if a is None:
                spring(1, None, b, k_axial)
            else:
                spring(1, a, b, k_axial)
        for dof, kt, kr in ((2, k_trans[0], k_rot[1]), (3, k_trans[1], k_rot[0])):  # Y with θz, Z with θy
            if kr > 0 and kt <= 0:
                raise ValueError(f"calculix_rig: {kind} '{name}' has tilt but no radial stiffness; not modelled")
            if kt <= 0:
                continue
            if kr <= 0:
                spring(dof, a, b, kt)
                continue
            d = 1e3 * math.sqrt(kr / kt)  # mm: two springs of kt/2 at ±d have the tilt stiffness kt d²
            b_ends = arm(b, b_x, d, material)
            a_ends = (None, None) if a is None else arm(a, a_x, d, material)
            for ae, be in zip(a_ends, b_ends):
                spring(dof, ae, be, 0.5 * kt)
        return a, b

    for br in rig.bearings:
        radial = br.radial_stiffness_N_per_um * 1e6
        housing = None if br.housing == "ground" else br.housing
        tilt = br.tilt_stiffness_Nm_per_rad or 0.0
        connect("bearing", br.name, housing, br.x_mm, br.shaft, br.x_mm, br.x_mm, (radial, radial), (tilt, tilt),
                (br.axial_stiffness_N_per_um or 0.0) * 1e6)
    for m in rig.mounts:
        t = [v * 1e6 for v in m.translational_stiffness_N_per_um]
        r = list(m.rotational_stiffness_Nm_per_rad)
        connect("mount", m.name, None, m.x_mm, m.part, m.x_mm, m.x_mm, (t[1], t[2]), (r[1], r[2]), t[0])
    for c in rig.couplings:
        radial = c.radial_stiffness_N_per_mm * 1e3
        connect("coupling", c.name, c.from_.part, c.from_.x_mm, c.to.part, c.to.x_mm, c.centre_x_mm,
                (radial, radial), (c.angular_stiffness_Nm_per_rad,) * 2, c.axial_stiffness_N_per_mm * 1e3)
    for j in rig.joints:
        t = [v * 1e6 for v in j.translational_stiffness_N_per_um]
        r = list(j.rotational_stiffness_Nm_per_rad)
        connect("joint", j.name, j.from_.part, j.from_.x_mm, j.to.part, j.to.x_mm, j.to.x_mm, (t[1], t[2]),
                (r[1], r[2]), t[0])
    loads = located_unit_loads(rig)
    # torsion: a soft tangential spring (TORSION_HOLD_NM_PER_RAD) at the end of a stiff radial arm on every part's
    # first node (a rotation boundary condition on an expanded beam node would also clamp its bending: ccx makes the
    # node a rigid knot and fixes all its rotations); (where no axial spring holds it) the axial motion: held there
    for _, (xs, corners) in part_nodes.items():
        x0 = float(xs[0])
        mid, tip = new_node(x0, 0.5 * TORSION_ARM_MM), new_node(x0, TORSION_ARM_MM)
        number = new_element()
        key = (rig.parts[0].material, ARM_STIFFENING, 40.0, 0.0)
        elset = materials.setdefault(key, f"S{len(materials) + 1}")
        lines_elements.append((elset, f"{number}, {corners[0]}, {mid}, {tip}"))
        spring(3, None, tip, TORSION_HOLD_NM_PER_RAD / (TORSION_ARM_MM * MM) ** 2)
    for name in solids:  # the same on a solid: the arm is a point on the first attachment's rigid motion
        x0 = min(x for (part, x) in owner.values() if part == name)
        spring(3, None, solid_point(name, x0, x0, TORSION_ARM_MM), TORSION_HOLD_NM_PER_RAD / (TORSION_ARM_MM * MM) ** 2)
    axially_held = {n for (dof, _), rows in springs.items() if dof == 1 for row in rows for n in row[:2] if n}
    for _, (_, corners) in part_nodes.items():
        if not axially_held & set(corners):
            fixed.append((corners[0], 1, 1))
    for name, shaft in solids.items():
        if not axially_held & {n for n, (part, _) in owner.items() if part == name}:
            x0 = min(x for (part, x) in owner.values() if part == name)
            local, _ = shaft.face_nodes(shaft.face(x0))
            fixed.append((solid_first[name] + int(local[0]), 1, 1))

    # every node a spring or a load acts on gets a short stiff radial stub: ccx then makes the node a knot (a rigid
    # section), so the force enters the whole section as in beam theory, not one expanded node (a local dent)
    for step in STEPS:
        for load in loads[step]:
            if load.band_mm is None and load.part not in solids:
                knots.add(at(load.part, load.x_mm))
    for node in sorted(knots):
        x0, y0 = next((x, y) for n, x, y, _ in nodes if n == node)
        if y0 != 0.0 or node in owner:  # the torsion arm's tip (not on the line), or a point on a solid's face
            continue
        mid, tip = new_node(x0, -0.5 * KNOT_STUB_MM), new_node(x0, -KNOT_STUB_MM)
        number = new_element()
        key = (rig.parts[0].material, 1.0, KNOT_STUB_DIAMETER_MM, 0.0)
        elset = materials.setdefault(key, f"S{len(materials) + 1}")
        lines_elements.append((elset, f"{number}, {node}, {mid}, {tip}"))
    out = ["** rvcoax rig as a CalculiX beam model (benchmarks/calculix_rig.py)", "*NODE, NSET=NALL"]
    out += [f"{n}, {x * MM:.12e}, {y * MM:.12e}, {z * MM:.12e}" for n, x, y, z in nodes]
    by_elset: dict[str, list[str]] = {}
    for elset, text in lines_elements:
        by_elset.setdefault(elset, []).append(text)
    for elset, rows in by_elset.items():
        out.append(f"*ELEMENT, TYPE=B32R, ELSET={elset}")
        out += rows
    for name, shaft in solids.items():
        out.append(f"*ELEMENT, TYPE=C3D10, ELSET=SOLID_{name.upper()}")
        for e in shaft.elements:
            number = new_element()
            out.append(f"{number}, " + ", ".join(str(solid_first[name] + int(k)) for k in e))
        mat = rig.materials[shaft.material]
        out += [f"*MATERIAL, NAME=MSOLID_{name.upper()}", "*ELASTIC",
                f"{mat.youngs_modulus_MPa * 1e6:.12e}, {mat.poisson_ratio:.6f}",
                f"*SOLID SECTION, ELSET=SOLID_{name.upper()}, MATERIAL=MSOLID_{name.upper()}"]
    for (material, stiffen, outer, inner), elset in materials.items():
        mat = rig.materials[material]
        out += [f"*MATERIAL, NAME=M{elset}", "*ELASTIC",
                f"{mat.youngs_modulus_MPa * 1e6 * stiffen:.12e}, {mat.poisson_ratio:.6f}"]
        if inner > 0:
            out += [f"*BEAM SECTION, ELSET={elset}, MATERIAL=M{elset}, SECTION=PIPE",
                    f"{0.5 * outer * MM:.12e}, {0.5 * (outer - inner) * MM:.12e}", "0.0, 0.0, 1.0"]
        else:
            out += [f"*BEAM SECTION, ELSET={elset}, MATERIAL=M{elset}, SECTION=CIRC",
                    f"{outer * MM:.12e}, {outer * MM:.12e}", "0.0, 0.0, 1.0"]
    for i, ((dof, _), rows) in enumerate(springs.items()):
        for j, (b, a, k) in enumerate(rows):
            number = new_element()
            if a is None:
                out += [f"*ELEMENT, TYPE=SPRING1, ELSET=K{i}_{j}", f"{number}, {b}",
                        f"*SPRING, ELSET=K{i}_{j}", f"{dof}", f"{k:.12e}"]
            else:
                out += [f"*ELEMENT, TYPE=SPRING2, ELSET=K{i}_{j}", f"{number}, {a}, {b}",
                        f"*SPRING, ELSET=K{i}_{j}", f"{dof}, {dof}", f"{k:.12e}"]
    position = {n: (x, y, z) for n, x, y, z in nodes}
    for i, ((part, x_face), members) in enumerate(rigid.items()):  # each face with its points
        shaft = solids[part]
        if solid_ties == "rigid" or shaft.tie(x_face) == "rigid":  # one rigid body (RBE2-like)
            local, _ = shaft.face_nodes(shaft.face(x_face))
            x, y, z = position[members[0]]
            rotation = new_node(x, y, z)
            out += ["*NODE, NSET=NALL", f"{rotation}, {x * MM:.12e}, {y * MM:.12e}, {z * MM:.12e}"]
            out += [f"*NSET, NSET=RB{i}"] + [f"{solid_first[part] + int(n)}," for n in local]
            out += [f"{n}," for n in members[1:]]
            out += [f"*RIGID BODY, NSET=RB{i}, REF NODE={members[0]}, ROT NODE={rotation}"]
        else:  # distributing (RBE3-like): each point follows the face's weighted mean motion
            out += _distributing_equations(shaft, x_face, members, position, solid_first[part])
    path_nodes, stations, lengths, sections = {}, {}, {}, {}
    for key in MEASURED_SHAFTS:
        path = getattr(rig.paths, key)
        xs = np.linspace(path.x_start_mm, path.x_start_mm + path.length_mm, read_stations or path.stations)
        if path.part in solids:
            sections[key] = []
            for x in xs:
                local, weights = solids[path.part].section(x)
                sections[key].append((solid_first[path.part] + local, weights / weights.sum()))
        else:
            sections[key] = [(np.array([at(path.part, x)]), np.ones(1)) for x in xs]
        path_nodes[key] = sorted({int(n) for nodes_, _ in sections[key] for n in nodes_})
        stations[key] = xs - path.x_start_mm
        lengths[key] = float(path.length_mm)
        out += [f"*NSET, NSET=P{key.upper()}"] + [f"{n}," for n in path_nodes[key]]
    out.append("*BOUNDARY")
    out += [f"{n}, {a}, {b}" for n, a, b in fixed]
    for step in STEPS:
        out += ["*STEP", "*STATIC", "*CLOAD, OP=NEW"]
        forces: dict[tuple[int, int], float] = {}
        for load in loads[step]:
            if any(abs(v) > 0 for v in load.moment_Nm[1:]):
                raise ValueError("calculix_rig: lateral moments are not modelled")
            if load.part in solids:
                shaft = solids[load.part]
                local, w = shaft.face_nodes(shaft.load_face(load.x_mm, load.band_mm))
                targets = [(solid_first[load.part] + int(n), wi / w.sum()) for n, wi in zip(local, w)]
            elif load.band_mm is None:
                targets = [(at(load.part, load.x_mm), 1.0)]
            else:
                xs, corners = part_nodes[load.part]
                inside = [i for i, x in enumerate(xs) if load.band_mm[0] - 1e-9 <= x <= load.band_mm[1] + 1e-9]
                w = np.zeros(len(inside))
                for i in range(len(inside) - 1):
                    h = xs[inside[i + 1]] - xs[inside[i]]
                    w[i] += h / 2
                    w[i + 1] += h / 2
                w = w / w.sum()
                targets = [(corners[i], wi) for i, wi in zip(inside, w)]
            for node, weight in targets:
                for dof, value in ((2, load.force_N[1]), (3, load.force_N[2])):
                    if value:
                        forces[(node, dof)] = forces.get((node, dof), 0.0) + weight * value
        out += [f"{n}, {dof}, {v:.12e}" for (n, dof), v in forces.items()]
        for key in MEASURED_SHAFTS:
            out += [f"*NODE PRINT, NSET=P{key.upper()}", "U"]
        out.append("*END STEP")
    return Deck("\n".join(out) + "\n", path_nodes, stations, lengths, sections)


def _distributing_equations(shaft, x_face: float, members: list[int], position: dict, first: int) -> list[str]:
    """``*EQUATION`` lines making each point of ``members`` follow the weighted mean motion of the face at ``x_face``
    (rvcoax's distributing tie, ``fem.ties.distributing_tie_operator``, with its weights: a sixth of each facet's area
    on each of its six nodes): u_P = ū + θ × (x_P − x̄). Each point is the dependent term of its own three equations
    and of no other; the face nodes are independent in all of them."""
    from rvcoax.fem.ties import FaceNodes, distributing_tie_operator

    local, weights = shaft.face_nodes(shaft.face(x_face), every_node=True)
    face = FaceNodes(shaft.nodes_mm[local], np.arange(3 * local.size).reshape(-1, 3), weights)
    out = []
    for point in members:
        operator = distributing_tie_operator(np.asarray(position[point], float), face)
        for k in range(3):
            row = operator[k]
            keep = np.flatnonzero(np.abs(row) > 1e-12 * np.abs(row).max())
            terms = [(point, k + 1, 1.0)] + [(first + int(local[j // 3]), j % 3 + 1, -float(row[j])) for j in keep]
            out += ["*EQUATION", f"{len(terms)}"]
            out += [", ".join(f"{n}, {d}, {c:.12e}" for n, d, c in terms[i:i + 4]) for i in range(0, len(terms), 4)]
    return out


def solve_units(rig: Rig, work: Path | None = None, element_mm: float = ELEMENT_MM) -> tuple[dict, Deck]:
    """Run ccx once: u_y (mm) along both paths for each unit load of :data:`STEPS`."""
    deck = build_deck(rig, element_mm)
    return run_deck(deck, work), deck


LAST_RUN: dict = {}


def run_deck(deck: Deck, work: Path | None = None) -> dict:
    """Run ccx on ``deck``: u_y (mm) at the path stations for each unit load of :data:`STEPS`."""
    ccx = require_ccx()
    start = os.times()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(work) if work else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "rig.inp").write_text(deck.text)
        run = subprocess.run([ccx, "rig"], cwd=folder, capture_output=True, text=True,
                             env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
        dat = (folder / "rig.dat").read_text() if (folder / "rig.dat").exists() else ""
        if run.returncode != 0 or "displacements" not in dat:
            raise RuntimeError(f"ccx failed (status {run.returncode}): {run.stdout[-2000:]}")
    end = os.times()
    LAST_RUN["cpu_s"] = end.children_user + end.children_system - start.children_user - start.children_system
    # the .dat lists PINPUT then POUTPUT per step
    blocks = _blocks(dat)
    units = {}
    for s, step in enumerate(STEPS):
        units[step] = {key: np.array([sum(w * blocks[2 * s + k][int(n)][1] for n, w in zip(*section))
                                      for section in deck.sections[key]]) / MM
                       for k, key in enumerate(MEASURED_SHAFTS)}
    return units


def _blocks(dat: str) -> list[dict[int, np.ndarray]]:
    blocks: list[dict[int, np.ndarray]] = []
    for line in dat.splitlines():
        if line.strip().startswith("displacements"):
            blocks.append({})
            continue
        parts = line.split()
        if blocks and len(parts) == 4:
            blocks[-1][int(parts[0])] = np.array([float(v) for v in parts[1:]])
    return blocks


def case_paths(units: dict, cases) -> np.ndarray:
    """u_y (mm) of ``cases`` from the unit responses, (cases, stations) flattened like ``blind_data``."""
    rows = []
    for case in cases:
        t1, t2 = case.input_torque_Nm, case.output_torque_Nm
        rows.append(np.concatenate([t1 * units["T1"][k] + t2 * units["T2"][k] + np.sign(t1) * units["engaged_T1"][k]
                                    + np.sign(t2) * units["engaged_T2"][k] for k in MEASURED_SHAFTS]))
    return np.concatenate(rows)


# ---- the reference rig and its hidden effects ------------------------------------------------------------

def truth_rig(datum: str = "aligned_at_rest") -> Rig:
    """The reference rig with self-weight off, Y from ``datum`` (at rest nothing is loaded: both datums agree)."""
    data = blind_data.truth_rig(datum).model_dump(by_alias=True)
    return Rig.model_validate(data)


def identification_rig(datum: str = "aligned_at_rest") -> Rig:
    """The rig the workflow identifies with: the same, Timoshenko beams (CalculiX's bricks deform in shear)."""
    return blind_data.identification_rig(datum)


def layout_for(deck: Deck, n_cases: int):
    from rvcoax.results.studies.discrepancy.responses import PathLayout
    return PathLayout(n_cases, {k: np.asarray(deck.stations_mm[k], float) for k in MEASURED_SHAFTS},
                      dict(deck.lengths_mm))


def beam_paths(rig: Rig, cases) -> np.ndarray:
    from rvcoax.results.sweep import SweepSettings
    paths, _ = blind_data.absolute_paths(rig, SweepSettings(), cases=cases, log=lambda *_: None)
    return paths


def compare(log=print) -> dict:
    """The unmodified reference rig, paper 000's 20 cases: ccx against rvcoax's beam model (Timoshenko, the
    identification model, and Euler–Bernoulli), Y along both measured shafts (41 stations each).

    Returns, per model and shaft, RMS(ccx − rvcoax) / RMS(rvcoax) over all cases and stations, and the largest
    relative difference of Y_max = max |Y| along the shaft over the cases."""
    cases = (blind_data.REST, *paper_cases())
    units, deck = solve_units(truth_rig())
    sizes = [len(deck.sections[k]) for k in MEASURED_SHAFTS]
    ccx = case_paths(units, cases).reshape(len(cases), -1)[1:]
    out = {}
    for label, rig in (("Timoshenko", identification_rig()), ("Euler-Bernoulli", truth_rig())):
        beam = beam_paths(rig, cases).reshape(len(cases), -1)[1:]
        for key, (rel, worst) in path_differences(ccx, beam, sizes).items():
            out[f"{label} {key}"] = {"rms_relative": rel, "ymax_relative_worst": worst}
            log(f"{label:16s} {key:6s}: RMS(ccx - rvcoax)/RMS(rvcoax) = {100 * rel:.3f} %, "
                f"Y_max relative difference, worst case: {100 * worst:+.3f} %")
    return out


def path_differences(paths: np.ndarray, reference: np.ndarray, sizes: list[int]) -> dict[str, tuple[float, float]]:
    """Per measured shaft, of (cases, stations) paths against a reference: RMS(difference) / RMS(reference) and the
    worst relative difference of Y_max = max |Y| along the shaft over the cases."""
    out = {}
    for i, key in enumerate(MEASURED_SHAFTS):
        columns = slice(sum(sizes[:i]), sum(sizes[:i + 1]))
        a, b = paths[:, columns], reference[:, columns]
        ymax = np.abs(a).max(axis=1) / np.abs(b).max(axis=1) - 1.0
        out[key] = (float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2))),
                    float(ymax[np.argmax(np.abs(ymax))]))
    return out


# the hidden effects (vocabulary names) and the value each is first solved at (its parameter's own unit); a linear
# effect is then scaled to TARGET of the signal (within its bounds), a nonlinear one kept at this value
HIDDEN = {
    "bearing_stiffness@output_B2": -2.0,          # log2 factor: a quarter of the stiffness
    "mesh_position_error@crankshaft_load_sharing": 1.0,   # µm
    "torque_reaction@output_bearing_block": 2.0,  # N per N·m of T2
    "mesh_force@reducer_input": 2.0,              # N per N·m of T1
}
OOV = "lateral_T2@output_x80"  # a lateral load ∝ T2 on the output shaft, 80 mm along its path (x = 485 mm)
OOV_X_MM = 485.0
BEYOND = "beyond_bound"  # a set's truth is its effect at blind_data.OUT_OF_BOUNDS times its physical bound
TARGET = 0.3  # size of a hidden change: RMS over the paths, of the signal, on the shaft it changes most
SETS = (  # name, truth, out-of-vocabulary (True) or BEYOND (the truth beyond its bound), schema, noise, notation
    ("none_paths_1", (), False, "paths", 0.01, "e"),
    ("none_table_5", (), False, "table", 0.05, "E"),
    ("bearing_stiffness_paths_1", ("bearing_stiffness@output_B2",), False, "paths", 0.01, "fixed"),
    ("bearing_stiffness_table_5", ("bearing_stiffness@output_B2",), False, "table", 0.05, "e"),
    ("position_error_paths_5", ("mesh_position_error@crankshaft_load_sharing",), False, "paths", 0.05, "mixed"),
    ("torque_reaction_paths_1", ("torque_reaction@output_bearing_block",), False, "paths", 0.01, "E"),
    ("torque_reaction_table_1", ("torque_reaction@output_bearing_block",), False, "table", 0.01, "E"),
    ("mesh_force_paths_5", ("mesh_force@reducer_input",), False, "paths", 0.05, "fixed"),
    ("pair_paths_1", ("bearing_stiffness@output_B2", "mesh_force@reducer_input"), False, "paths", 0.01, "e"),
    ("pair_table_5", ("bearing_stiffness@output_B2", "mesh_force@reducer_input"), False, "table", 0.05, "mixed"),
    ("oov_paths_1", (), True, "paths", 0.01, "e"),
    ("oov_paths_5", (), True, "paths", 0.05, "E"),
    ("oov_table_1", (), True, "table", 0.01, "fixed"),
    ("beyond_bound_paths_1", ("torque_reaction@output_bearing_block",), BEYOND, "paths", 0.01, "e"),
    ("beyond_bound_table_1", ("mesh_force@reducer_input",), BEYOND, "table", 0.01, "fixed"),
)
FILE_CASES = (0, 3, 6, 9, 12, 15, 19)  # 7 of paper 000's cases
FILE_STATIONS = 6


def committed_load(oov) -> str:
    """The load field of a committed set's row (:data:`SETS`): :data:`OOV`, :data:`BEYOND` or none."""
    return OOV if oov is True else oov or ""


def _with_oov(rig: Rig, size: float, kind: str = "proportional", x_mm: float = OOV_X_MM) -> Rig:
    """``rig`` with a lateral load ∝ T2 of ``size`` N per N·m at ``x_mm`` on the output shaft (``couple``: +size at
    x − 15 mm and −size at x + 15 mm)."""
    data = blind_data._load_rig(rig, ("hidden", kind, x_mm, False)).model_dump(by_alias=True)
    for i, entry in enumerate(data["torque_lateral_loads"][-(2 if kind == "couple" else 1):]):
        entry["force_per_torque_N_per_Nm"] = size * (-1.0 if i else 1.0)
    return Rig.model_validate(data)


def _relative_change(delta: np.ndarray, base: np.ndarray, sizes: list[int]) -> float:
    d, b = delta.reshape(-1, sum(sizes)), base.reshape(-1, sum(sizes))
    edges = np.cumsum([0, *sizes])
    return max(float(np.sqrt(np.mean(d[:, i:j] ** 2)) / np.sqrt(np.mean(b[:, i:j] ** 2)))
               for i, j in zip(edges[:-1], edges[1:]))


def detectability(paths: np.ndarray, base: np.ndarray, layout, schema: str, noise: float, cases,
                  stations: int = FILE_STATIONS) -> float:
    """RMS of the noise-free hidden change over the file's observations in units of σ, σ² = (noise × RMS of the
    shaft's values)² + (2 % of the value)² (the workflow's model-form allowance), as ``blind_data.detectability``:
    below 1 the file cannot carry the effect and ``no_gap`` is right too."""
    _, hidden = blind_data._observe(paths, layout, "aligned_at_rest", schema, cases, stations)
    template, plain = blind_data._observe(base, layout, "aligned_at_rest", schema, cases, stations)
    sigma = np.zeros_like(hidden)
    for s in MEASURED_SHAFTS:
        mask = template.shaft == s
        sigma[mask] = np.hypot(noise * np.sqrt(np.mean(hidden[mask] ** 2)), blind_data.MODEL_FORM * np.abs(plain[mask]))
    return float(np.sqrt(np.mean(((hidden - plain) / np.maximum(sigma, 1e-300)) ** 2)))


def _hidden_change(rig: Rig, effects: dict, name: str, value: float, base, solve, sizes, log,
                   solver=None) -> tuple:
    """ccx change of the paths by vocabulary effect ``name`` (a linear one scaled to :data:`TARGET`), its value."""
    units, _ = (solver or solve_units)(effects[name].apply(rig, [value]))
    delta = case_paths(units, solve) - base
    if effects[name].linear:
        p = effects[name].parameters[0]
        scaled = float(np.clip(value * TARGET / _relative_change(delta, base, sizes), p.lower, p.upper))
        delta, value = delta * scaled / value, scaled
    log(f"  ccx: {name} = {value:.4g}: {100 * _relative_change(delta, base, sizes):.1f} % of the signal")
    return delta, value


def write_sets(out: Path, sets=None, hidden=None, loads=None, case_indices=FILE_CASES, stations=FILE_STATIONS,
               log=print, solve_with=None, model: str = "") -> list[dict]:
    """Solve the hidden effects with ccx and write every data set and ``manifest.json``.

    ``sets``: (name, truth, out-of-vocabulary load name or "", schema, noise, notation, datum, seed) rows (default the
    committed :data:`SETS`); ``hidden``: effect name → the value it is first solved at (default :data:`HIDDEN`);
    ``loads``: out-of-vocabulary load name → (kind, x mm) (``proportional`` ∝ T2, or a ``couple`` 30 mm apart);
    ``solve_with``: the solver of a rig (default :func:`solve_units`, the beam deck), ``model`` its description."""
    solve_units_ = solve_with or solve_units
    sets = sets or [(name, truth, committed_load(oov), schema, noise, notation, "aligned_at_rest", seed)
                    for seed, (name, truth, oov, schema, noise, notation) in enumerate(SETS)]
    hidden = hidden or HIDDEN
    loads = loads or {OOV: ("proportional", OOV_X_MM)}
    cases = tuple(paper_cases()[i] for i in case_indices)
    solve = (blind_data.REST, *paper_cases())  # blind_data picks the files' cases from all of paper 000's
    rig = truth_rig()
    effects = {e.name: e for e in candidate_effects(rig)}
    units, deck = solve_units_(rig)
    sizes = [len(deck.sections[k]) for k in MEASURED_SHAFTS]
    base = case_paths(units, solve)
    layout = layout_for(deck, len(solve))
    deltas, values = {}, {}
    for name, value in hidden.items():
        deltas[name], values[name] = _hidden_change(rig, effects, name, value, base, solve, sizes, log, solve_units_)
    for load, (kind, x_mm) in loads.items():
        units, _ = solve_units_(_with_oov(rig, 1.0, kind, x_mm))
        delta = case_paths(units, solve) - base
        values[load] = TARGET / _relative_change(delta, base, sizes)
        deltas[load] = delta * values[load]
        log(f"  ccx: {load}: {values[load]:.4g} N per N·m of T2")
    for name in {tuple(row[1])[0] for row in sets if row[2] == BEYOND}:  # a linear effect beyond its bound: scaled
        p = effects[name].parameters[0]
        if not effects[name].linear:
            raise ValueError(f"calculix_rig: an out-of-bounds truth must be a linear effect; '{name}' is not")
        beyond = blind_data.OUT_OF_BOUNDS * (p.upper if abs(p.upper) >= abs(p.lower) else p.lower)
        deltas[(BEYOND, name)] = deltas[name] * beyond / values[name]
        values[(BEYOND, name)] = beyond
        log(f"  ccx: {name} = {beyond:.4g} ({blind_data.OUT_OF_BOUNDS:g} × its bound): "
            f"{100 * _relative_change(deltas[(BEYOND, name)], base, sizes):.1f} % of the signal")
    for row in sets:  # a pair is solved directly (a bearing stiffness is not linear), not superposed
        truth = tuple(row[1])
        if len(truth) == 2 and truth not in deltas:
            both = rig
            for member in truth:
                both = effects[member].apply(both, [values[member]])
            units, _ = solve_units_(both)
            deltas[truth] = case_paths(units, solve) - base
    out.mkdir(parents=True, exist_ok=True)
    manifest = []
    for name, truth, load, schema, noise, notation, datum, seed in sets:
        truth = tuple(truth)
        beyond = load == BEYOND
        key = (BEYOND, truth[0]) if beyond else load if load else truth if len(truth) == 2 else \
            truth[0] if truth else None
        paths = base + (deltas[key] if key is not None else 0.0)
        template, noisy = blind_data.noisy_observations(paths, layout, datum, schema, noise, seed, cases, stations)
        (out / f"{name}.csv").write_text(blind_data.csv_text(template, noisy, notation, seed))
        detect = detectability(paths, base, layout, schema, noise, cases, stations)
        group = "out_of_bounds" if beyond else "out_of_vocabulary" if load else "none" if not truth else \
            "pair" if len(truth) == 2 else "vocabulary"
        manifest.append({"id": name, "file": f"{name}.csv", "group": group, "truth": list(truth),
                         "load": "" if beyond else load, "datum": datum, "schema": schema, "noise": noise,
                         "seed": seed, "notation": notation,
                         "values": {truth[0]: round(values[key], 6)} if beyond else
                         {n: round(values[n], 6) for n in ((load,) if load else truth)},
                         "detectability": round(detect, 3), "detectable": not truth and not load or detect >= 1.0})
    (out / "manifest.json").write_text(json.dumps({
        "model": model or "CalculiX ccx: B32R beams (expanded to C3D20R) and SPRING1/SPRING2 springs built from the "
                          "reference rig's geometry (self-weight off), see benchmarks/calculix_rig.py",
        "generator": "benchmarks/calculix_solid.py" if solve_with else "benchmarks/calculix_rig.py", "oov_x_mm": OOV_X_MM, "cases": list(case_indices),
        "stations": stations, "sets": manifest}, indent=1) + "\n")
    log(f"wrote {len(manifest)} data sets to {out}")
    return manifest


# the larger benchmark set (--full): not committed, scored by bench_discrepancy_blind.py --sets DIR
FULL_HIDDEN = {
    "bearing_stiffness@input_B1": -2.0, "bearing_stiffness@output_B1": -2.0, "bearing_stiffness@output_B2": -2.0,
    "mount_compliance@reducer": 10.0, "mount_compliance@output_bearing_block": 10.0,
    "torque_reaction@input_bearing_block": 2.0, "torque_reaction@reducer": 2.0,
    "torque_reaction@output_bearing_block": 2.0, "mesh_force@reducer_input": 2.0,
    "mesh_position_error@sun_gear_load_sharing": 1.0, "mesh_position_error@crankshaft_load_sharing": 1.0,
}
FULL_PAIRS = (("bearing_stiffness@output_B2", "mesh_force@reducer_input"),
              ("mesh_force@reducer_input", "torque_reaction@output_bearing_block"),
              ("bearing_stiffness@input_B1", "torque_reaction@output_bearing_block"),
              ("mesh_position_error@sun_gear_load_sharing", "torque_reaction@reducer"))
FULL_LOADS = {"lateral_T2@output_x35": ("proportional", 440.0), "lateral_T2@output_x80": ("proportional", 485.0),
              "lateral_T2@output_x135": ("proportional", 540.0), "moment_T2@output_x80": ("couple", 485.0)}


# out-of-bounds truths (the ``load`` field of a row says BEYOND): each linear effect of FULL_HIDDEN at
# blind_data.OUT_OF_BOUNDS times its physical bound (the larger in size), scaled from its ccx solve (no solve more)
FULL_OUT_OF_BOUNDS = ("torque_reaction@input_bearing_block", "torque_reaction@reducer",
                      "torque_reaction@output_bearing_block", "mesh_force@reducer_input",
                      "mesh_position_error@sun_gear_load_sharing", "mesh_position_error@crankshaft_load_sharing")


def full_design() -> list[tuple]:
    """Every kind above, none, pairs and out-of-vocabulary loads; both schemas, both datums, 1 % and 5 % noise;
    paper 000's 20 cases, 11 stations per shaft; notations rotate. Then the out-of-bounds truths
    (:data:`FULL_OUT_OF_BOUNDS`): both schemas and noises, the datums alternating over the effects (24 sets; the
    rows before them keep their ids and seeds)."""
    items = [((name,), "", seed) for name in FULL_HIDDEN for seed in (0, 1)]
    items += [(pair, "", 0) for pair in FULL_PAIRS] + [((), load, 0) for load in FULL_LOADS]
    items += [((), "", seed) for seed in (0, 1, 2)]
    notations = ("fixed", "e", "E", "mixed")
    rows = []
    for truth, load, seed in items:
        for datum in blind_data.DATUMS:
            for schema in blind_data.SCHEMAS:
                for noise in blind_data.NOISES:
                    k = len(rows)
                    rows.append((f"{k:03d}", truth, load, schema, noise, notations[k % 4], datum, 100 * seed + k))
    for i, name in enumerate(FULL_OUT_OF_BOUNDS):
        datum = blind_data.DATUMS[i % len(blind_data.DATUMS)]
        for schema in blind_data.SCHEMAS:
            for noise in blind_data.NOISES:
                k = len(rows)
                rows.append((f"{k:03d}", (name,), BEYOND, schema, noise, notations[k % 4], datum, k))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--compare", action="store_true", help="compare ccx with rvcoax on the unmodified rig")
    parser.add_argument("--out", default="", help="write the hidden-effect data sets to this folder")
    parser.add_argument("--full", default="", help="write the larger benchmark set (288 files) to this folder")
    parser.add_argument("--no-record", action="store_true", help="print only (no RESULTS.md block)")
    parser.add_argument("--keep", default="", help="keep the unmodified rig's deck and ccx output in this folder")
    args = parser.parse_args()
    require_ccx()
    if args.keep:
        solve_units(truth_rig(), Path(args.keep))
    if args.compare:
        start = time.perf_counter()
        figures = compare()
        seconds = time.perf_counter() - start
        if not args.no_record:
            from machine import record
            rows = [(f"RMS(ccx − rvcoax)/RMS(rvcoax), {name}", f"{100 * v['rms_relative']:.3f} %") for name, v in
                    figures.items()]
            rows += [(f"Y_max relative difference, worst of the 20 cases, {name}", f"{100 * v['ymax_relative_worst']:+.3f} %")
                     for name, v in figures.items()]
            rows += [("ccx model", f"B32R beams ≤ {ELEMENT_MM:g} mm (expanded to C3D20R), SPRING1/SPRING2, one run of 4 steps"),
                     ("compare, end to end (ccx run + 2 beam sweeps)", f"{seconds:.1f} s"),
                     ("load average (1, 5, 15 min)", ", ".join(f"{v:.2f}" for v in os.getloadavg()))]
            record("CalculiX against the beam model on the reference rig (benchmarks/calculix_rig.py --compare)", rows)
    if args.out:
        write_sets(Path(args.out))
    if args.full:
        write_sets(Path(args.full), full_design(), FULL_HIDDEN, FULL_LOADS, tuple(range(20)), blind_data.STATIONS)


if __name__ == "__main__":
    main()
