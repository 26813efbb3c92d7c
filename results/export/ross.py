"""ROSS adapter: the measured shafts as ``ross.Rotor`` models, their misalignment faults, ROSS's static analysis.

ROSS (the open-source rotordynamics package ``ross-rotordynamics``) is an optional dependency:
``pip install "rvcoax[ross]"``. It is imported only here, lazily, and its absence is reported
with that instruction (:class:`RossUnavailableError`).

For each measured shaft (``input``, ``output``) the adapter builds

- a :class:`ShaftLine` from the rig: the shaft's beam elements exactly as the rvcoax beam model
  has them (node positions, outer and inner diameters, material), its supports (bearings, and joints
  with lateral stiffness to a housing, such as the reducer's output flange) with their radial
  stiffness — the typed-in value, or for a ball bearing from geometry its operating tangent stiffness in the
  load case the rotor is exported for (:func:`operating_supports`; the case is named in the rotor's tag) — and
  the coupling hubs it carries (half the coupling's mass and polar inertia each, as in the rvcoax model);
- a ``ross.Rotor`` of it (:func:`build_rotor`): Timoshenko shaft elements with Cowper's shear
  coefficient, bearings, hubs as disks;
- per load case, the parameters of ROSS's flexible-coupling misalignment fault
  (``ross.MisalignmentFlex``, or ``rotor.run_misalignment(coupling="flex", **parameters)``) from the
  coupling's offset and angle computed by rvcoax (:func:`misalignment_parameters`), in the state
  Y and β are measured from (the aligned rig at rest by default: the misalignment the torque adds).

Axes: ROSS's shaft axis is its z, y is vertical, x horizontal; rvcoax's (x along the shaft, y up,
z horizontal) maps to ROSS's (z, y, −x), both right-handed. ROSS works in SI units.

ROSS's static analysis (``rotor.run_static()``) loads the shaft with gravity (9.8065 m/s², fixed in
ROSS) on rigid supports at the bearings. :func:`rvcoax_gravity_sag` solves the same shaft with
rvcoax's beam elements under the same gravity, supports held rigidly in y and z: like with like.

ROSS's undamped modal analysis at zero speed (``rotor.run_modal(0)``) is compared the same way
(:func:`compare_modal`): :func:`rvcoax_line_modes` solves the same shaft line with rvcoax's consistent
Timoshenko mass and stiffness (:mod:`rvcoax.fem.modal`) on the same radial springs, free axially and in
torsion as ROSS's rotor is.

Tested with ROSS 2.3.0 (the last release for Python 3.11; ROSS 3 needs Python ≥ 3.12 and is not tested).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcoax.errors import RvcoaxError
from rvcoax.fem import DOFS_PER_NODE
from rvcoax.fem.beam import BeamElements
from rvcoax.fem.bushing import Bushings
from rvcoax.fem.loads import PointMasses
from rvcoax.fem.model import StructuralModel
from rvcoax.fem.pieces import assemble_frame
from rvcoax.fem.system import factorize
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.model.beam import SpringId, build_rig_model
from rvcoax.geometry.schema import Rig
from rvcoax.geometry.units import MM
from rvcoax.results.export.dynamics import DynamicsExport
from rvcoax.results.io.writers import write_csv_atomic

__all__ = ["FAULT_ARGUMENTS", "Hub", "INSTALL_HINT", "ModalComparison", "ROSS_GRAVITY_M_PER_S2",
           "RossFiles", "RossUnavailableError", "ShaftLine", "StaticComparison", "Support", "build_rotor",
           "compare_modal", "compare_static", "fault_arguments", "fault_element", "import_ross", "misalignment_fault",
           "misalignment_parameters", "operating_supports", "ross_gravity_sag", "ross_modal_frequencies",
           "rvcoax_gravity_sag", "rvcoax_line_modes", "save_rotor", "shaft_line", "write_ross"]

ROSS_GRAVITY_M_PER_S2 = 9.8065
"""The gravity ``ross.Rotor.run_static`` applies (fixed inside ROSS)."""
RIGID_BODY_HZ = 1.0  # modes below this in compare_modal are a free line's rigid-body motions
INSTALL_HINT = 'pip install "rvcoax[ross]"  (the package ross-rotordynamics)'


class RossUnavailableError(RvcoaxError, RuntimeError):
    """ROSS is not installed (or cannot be imported); the message says how to install it."""


@contextlib.contextmanager
def _quiet_output(printed: list[str]):
    """Catch what is printed inside: at the file-descriptor level (CoolProp's C library: "Good news: It is possible to
    use REFPROP on your system! However, the library could not be loaded …", which ccp triggers on import) and from
    Python (``sys.stdout`` may be no file descriptor: a notebook, a test runner), into ``printed`` (one text), so that
    an import that fails can still show it. Buffers are flushed before the descriptors are given back, so nothing
    printed inside comes out later."""
    import ctypes
    import io
    import sys
    import tempfile

    python = io.StringIO()
    saved = [os.dup(1), os.dup(2)]
    with tempfile.TemporaryFile() as sink:
        try:
            for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
                with contextlib.suppress(Exception):
                    stream.flush()
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            with contextlib.redirect_stdout(python), contextlib.redirect_stderr(python):
                yield
        finally:
            for stream in (sys.__stdout__, sys.__stderr__):
                with contextlib.suppress(Exception):
                    stream.flush()
            with contextlib.suppress(Exception):
                ctypes.CDLL(None).fflush(None)  # C's stdout buffer, when it is a file or a pipe
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
            sink.seek(0)
            printed.append(sink.read().decode("utf-8", "replace") + python.getvalue())


def import_ross():
    """The ``ross`` module, or :class:`RossUnavailableError` with the install instruction.

    Returns
    -------
    module
        ``ross``, imported with its start-up output (ccp's REFPROP notices) and warnings silenced.

    Raises
    ------
    RossUnavailableError
        ROSS is not installed (the message says how to install it, and shows what the import printed).
    Exception
        Whatever else the import raises, after what it printed is written to stderr.
    """
    import sys

    printed: list[str] = []
    try:
        with _quiet_output(printed), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import ross
    except ImportError as error:
        said = " ".join("".join(printed).split())
        raise RossUnavailableError(f"the ROSS export needs ROSS: {INSTALL_HINT} ({error})"
                                   + (f"; the import printed: {said}" if said else "")) from None
    except BaseException:
        sys.stderr.write("".join(printed))
        raise
    return ross


@dataclass(frozen=True)
class Support:
    """A lateral support of a shaft line: a bearing or a joint to a housing (radial stiffness in N/m; vertical
    ``y`` and horizontal ``z`` of rvcoax, equal unless an operating point makes them differ)."""

    spring: SpringId
    x_mm: float
    radial_stiffness_N_per_m: float
    horizontal_stiffness_N_per_m: float | None = None

    @property
    def stiffness_z_N_per_m(self) -> float:
        return self.radial_stiffness_N_per_m if self.horizontal_stiffness_N_per_m is None else \
            self.horizontal_stiffness_N_per_m


@dataclass(frozen=True)
class Hub:
    """A coupling hub carried by the shaft line (mass in kg)."""

    coupling: str
    x_mm: float
    mass_kg: float
    polar_inertia_kg_m2: float = 0.0


@dataclass(frozen=True)
class ShaftLine:
    """One measured shaft as ROSS sees it (lengths in mm, material in SI)."""

    which: str
    part: str
    node_x_mm: np.ndarray
    outer_diameter_mm: np.ndarray
    inner_diameter_mm: np.ndarray
    material: str
    density_kg_per_m3: float
    youngs_modulus_Pa: float
    poisson_ratio: float
    supports: tuple[Support, ...]
    hubs: tuple[Hub, ...]
    operating_point: str = "typed-in bearing stiffness"

    def node_at(self, x_mm: float) -> int:
        hits = np.flatnonzero(np.isclose(self.node_x_mm, x_mm, atol=1e-6))
        if hits.size != 1:
            raise KeyError(f"no node of '{self.part}' at x = {x_mm} mm")
        return int(hits[0])


def _section_at(part, x_mm: float) -> tuple[float, float]:
    for s in part.segments:
        if s.x_mm[0] <= x_mm <= s.x_mm[1]:
            return s.outer_diameter_mm, s.inner_diameter_mm
    raise ValueError(f"no segment of part '{part.name}' at x = {x_mm} mm")


def shaft_line(rig: Rig, which: str, operating: dict | None = None, operating_point: str | None = None) -> ShaftLine:
    """The measured shaft ``which`` with its beam-model nodes, supports and coupling hubs.

    Parameters
    ----------
    rig : Rig
    which : str
        ``"input"`` or ``"output"``.
    operating : dict, optional
        Bearing name → (k_y, k_z) in N/m (:func:`operating_supports`): those bearings' operating tangent stiffness
        replaces their typed-in radial stiffness. A bearing with a clearance or from internal geometry needs
        one: its linear reference spring is not its stiffness (``ValueError`` naming it otherwise).
    operating_point : str, optional
        The load case the stiffness belongs to (in the rotor's tag and file).

    Returns
    -------
    ShaftLine
    """
    name = getattr(rig.paths, which).part
    part = rig.part(name)
    frame = build_rig_model(rig)
    x = np.sort(frame.node_x_mm[frame.node_part == name])
    sections = np.array([_section_at(part, 0.5 * (a + b)) for a, b in zip(x[:-1], x[1:])])
    operating = operating or {}
    nonlinear = [b.name for b in rig.bearings if b.shaft == name and (b.model != "linear" or b.radial_clearance_um > 0)
                 and b.name not in operating]
    if nonlinear:
        raise ValueError(f"bearing(s) {', '.join(nonlinear)} of the {which} shaft are nonlinear (from geometry or with "
                         "a clearance): give their operating stiffness in a load case (operating_supports)")
    supports = []
    for b in rig.bearings:
        if b.shaft != name:
            continue
        if b.name in operating:
            k_y, k_z = operating[b.name]
            supports.append(Support(SpringId("bearing", b.name), b.x_mm, float(k_y), float(k_z)))
        else:
            supports.append(Support(SpringId("bearing", b.name), b.x_mm, b.radial_stiffness_N_per_um * 1e6))
    for j in rig.joints:
        lateral = min(j.translational_stiffness_N_per_um[1:]) * 1e6
        ends = {j.from_.part: j.from_.x_mm, j.to.part: j.to.x_mm}
        if name in ends and lateral > 0 and len(ends) == 2:
            supports.append(Support(SpringId("joint", j.name), ends[name], lateral))
    hubs = [Hub(c.name, end.x_mm, c.mass_kg / 2.0, (c.polar_inertia_kg_m2 or 0.0) / 2.0)
            for c in rig.couplings for end in (c.from_, c.to) if end.part == name]
    material = rig.materials[part.material]
    point = operating_point or ("typed-in bearing stiffness" if not operating else "operating point")
    return ShaftLine(which=which, part=name, node_x_mm=x, outer_diameter_mm=sections[:, 0],
                     inner_diameter_mm=sections[:, 1], material=part.material,
                     density_kg_per_m3=material.density_kg_per_m3, youngs_modulus_Pa=material.youngs_modulus_MPa * 1e6,
                     poisson_ratio=material.poisson_ratio, supports=tuple(sorted(supports, key=lambda s: s.x_mm)),
                     hubs=tuple(hubs), operating_point=point)


def operating_supports(sweep, index: int) -> dict:
    """Bearing name → (k_y, k_z) (N/m): each nonlinear bearing's operating tangent radial stiffness in case ``index``
    of ``sweep`` (a ball bearing's ∂F/∂Δ at that case's solution; a gapped bearing's, open or closed); empty for a
    rig whose bearings are linear (their typed-in stiffness is the operating one in every case).

    Parameters
    ----------
    sweep : Sweep
        A solved sweep (:func:`rvcoax.run_sweep`).
    index : int
        The load case (0-based).

    Returns
    -------
    dict
        Bearing name → (vertical, horizontal) radial stiffness in N/m.
    """
    bearings = sweep.nonlinear_bearings
    if bearings is None:
        return {}
    u = sweep.case_displacements[:, index] + (sweep.rest_displacement if sweep.rig.paths.measured_from ==
                                              "aligned_at_rest" else 0.0)
    _, tangent = bearings.laws(bearings.operator @ u)
    out = {}
    for spring, components, rows in bearings.spring_rows():
        block = tangent[rows, rows]
        y, z = components.index(1), components.index(2)
        out[spring.name] = (float(block[y, y]), float(block[z, z]))
    return out


def ross_identifier(text: str) -> str:
    """``text`` as a ROSS tag or material name: letters, digits and ``_`` only (anything else becomes ``_``).

    Parameters
    ----------
    text : str
        A name from the rig file.

    Returns
    -------
    str
        The identifier.
    """
    return re.sub(r"[^A-Za-z0-9_]", "_", text)


def build_rotor(line: ShaftLine, ross=None):
    """A ``ross.Rotor`` of ``line``: Timoshenko shaft elements, bearings at the supports, hubs as disks."""
    rs = ross if ross is not None else import_ross()
    # ROSS keeps a material by its name (an identifier in its files): a rig's material key may hold any text
    material = rs.Material(name=ross_identifier(f"rvcoax_{line.material}"), rho=line.density_kg_per_m3,
                           E=line.youngs_modulus_Pa, Poisson=line.poisson_ratio)
    lengths = np.diff(line.node_x_mm) * MM
    shaft = [rs.ShaftElement(L=float(length), idl=float(inner * MM), odl=float(outer * MM), material=material, n=i,
                             shear_method_calc="cowper")
             for i, (length, outer, inner) in enumerate(zip(lengths, line.outer_diameter_mm, line.inner_diameter_mm))]
    disks = [rs.DiskElement(n=line.node_at(h.x_mm), m=h.mass_kg, Id=h.polar_inertia_kg_m2 / 2.0,
                            Ip=h.polar_inertia_kg_m2, tag=ross_identifier(f"hub_{h.coupling}")) for h in line.hubs]
    # ROSS's x is rvcoax's −z (horizontal), its y rvcoax's y (vertical)
    bearings = [rs.BearingElement(n=line.node_at(s.x_mm), kxx=s.stiffness_z_N_per_m,
                                  kyy=s.radial_stiffness_N_per_m, cxx=0.0,
                                  tag=ross_identifier(f"{s.spring.kind}_{s.spring.name}"))
                for s in line.supports]
    case = "".join(c if c.isalnum() or c in "._-=" else "_" for c in line.operating_point)
    return rs.Rotor(shaft, disks, bearings, tag=f"rvcoax_{line.which}_shaft__{case}")


def ross_gravity_sag(rotor) -> np.ndarray:
    """ROSS's static deflection in y (m) at every node: gravity on rigid bearings (``run_static``)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # ROSS's rigid supports (k = 1e20) make an ill-conditioned dense solve
        return np.asarray(rotor.run_static().deformation, dtype=float)


def rvcoax_gravity_sag(rig: Rig, line: ShaftLine, acceleration_m_per_s2: float = ROSS_GRAVITY_M_PER_S2) -> np.ndarray:
    """The same shaft in rvcoax: its beam elements and hubs under gravity, supports rigid in y and z (m).

    The elements, hubs and material are those of the rig's beam model; the shaft is cut free from
    every other part, and u_x and the twist are held at the first support (they carry no load).
    """
    support_nodes = [line.node_at(s.x_mm) for s in line.supports]
    fixed = [DOFS_PER_NODE * n + c for n in support_nodes for c in (1, 2)]
    fixed += [DOFS_PER_NODE * support_nodes[0] + c for c in (0, 3)]
    model = dataclasses.replace(_line_model(rig, line, "none"), fixed_dofs=np.array(sorted(fixed)))
    system = assemble_frame(model, [0.0, -acceleration_m_per_s2, 0.0])
    u = factorize(system.stiffness, system.elimination).solve(system.loads["gravity"])
    return u[1::DOFS_PER_NODE]


@dataclass(frozen=True)
class StaticComparison:
    """ROSS's and rvcoax's gravity deflection of one shaft line on rigid supports (m)."""

    line: ShaftLine
    ross_uy_m: np.ndarray
    rvcoax_uy_m: np.ndarray

    @property
    def largest_sag_m(self) -> float:
        return float(np.abs(self.rvcoax_uy_m).max())

    @property
    def largest_difference_m(self) -> float:
        return float(np.abs(self.ross_uy_m - self.rvcoax_uy_m).max())

    @property
    def relative_difference(self) -> float:
        """Largest difference over the largest rvcoax sag."""
        return self.largest_difference_m / self.largest_sag_m


def compare_static(rig: Rig, which: str, ross=None, line: ShaftLine | None = None) -> tuple[object, StaticComparison]:
    """Build the ROSS rotor of the measured shaft ``which`` and compare its static analysis with rvcoax.

    Parameters
    ----------
    rig : Rig
        A validated rig.
    which : str
        ``"input"`` or ``"output"``.
    ross : module, optional
        The ``ross`` package (imported when not given).
    line : ShaftLine, optional
        The shaft line to build (an operating point's, :func:`shaft_line`); default the typed-in stiffness.

    Returns
    -------
    (ross.Rotor, StaticComparison)
        The rotor, and both codes' gravity sag of the shaft on rigid supports with their difference.

    Raises
    ------
    RossUnavailableError
        ROSS is not installed.
    """
    line = shaft_line(rig, which) if line is None else line
    rotor = build_rotor(line, ross)
    return rotor, StaticComparison(line, ross_gravity_sag(rotor), rvcoax_gravity_sag(rig, line))


def _line_model(rig: Rig, line: ShaftLine, supports: str):
    """The shaft line cut out of the rig's beam model, its beams and hubs; ``supports`` ``"springs"``: its supports as
    radial springs to the ground, ``"none"``: no springs (the caller holds DOFs)."""
    frame = build_rig_model(rig)
    structure = frame.structure
    nodes = np.flatnonzero(frame.node_part == line.part)
    nodes = nodes[np.argsort(frame.node_x_mm[nodes])]
    renumber = -np.ones(structure.n_nodes, dtype=int)
    renumber[nodes] = np.arange(nodes.size)
    beams = structure.beams
    keep = np.all(renumber[beams.connectivity] >= 0, axis=1)
    local = BeamElements(connectivity=renumber[beams.connectivity[keep]], area_m2=beams.area_m2[keep],
                         second_moment_m4=beams.second_moment_m4[keep], polar_moment_m4=beams.polar_moment_m4[keep],
                         shear_coefficient=beams.shear_coefficient[keep],
                         youngs_modulus_Pa=beams.youngs_modulus_Pa[keep], shear_modulus_Pa=beams.shear_modulus_Pa[keep],
                         density_kg_per_m3=beams.density_kg_per_m3[keep], reference_vector=beams.reference_vector[keep])
    masses = structure.point_masses
    on_shaft = renumber[masses.node] >= 0
    hubs = PointMasses(renumber[masses.node[on_shaft]], masses.mass_kg[on_shaft], masses.rotary_inertia_kg_m2[on_shaft])
    springs = Bushings(np.zeros(0, int), np.zeros(0, int), np.zeros((0, 3)), np.zeros((0, 6)))
    if supports == "springs":
        coordinates = structure.coordinates[nodes]
        stiffness = np.zeros((len(line.supports), 6))
        stiffness[:, 1] = [s.radial_stiffness_N_per_m for s in line.supports]
        stiffness[:, 2] = [s.stiffness_z_N_per_m for s in line.supports]
        at = np.array([line.node_at(s.x_mm) for s in line.supports], dtype=int)
        springs = Bushings(np.full(at.size, -1), at, coordinates[at], stiffness)
    return StructuralModel(structure.coordinates[nodes], local, springs, point_masses=hubs)


def rvcoax_line_modes(rig: Rig, line: ShaftLine, count: int):
    """The shaft line's lowest ``count`` modes in rvcoax: consistent Timoshenko mass and stiffness of its beam
    elements and hubs, on its supports as radial springs (no tilt, axial or torsional stiffness, as in ROSS).

    Parameters
    ----------
    rig : Rig
    line : ShaftLine
    count : int

    Returns
    -------
    rvcoax.fem.modal.Modes
        Its frequencies (rigid-body axial and torsional modes at 0 Hz included).
    """
    from rvcoax.fem.modal import natural_modes
    from rvcoax.fem.pieces import assemble, frame_contributions, frame_mass_contributions

    model = _line_model(rig, line, "springs")
    system = assemble(model.n_dofs, frame_contributions(model, [0.0, -1.0, 0.0]) + frame_mass_contributions(model))
    # free axially and in torsion: K is singular, the shift-invert factorises K + M (σ = −1 rad²/s²)
    return natural_modes(system.stiffness, system.mass, system.elimination, count, shift=-1.0)


def ross_modal_frequencies(rotor, count: int) -> np.ndarray:
    """ROSS's undamped natural frequencies (Hz) at zero speed: ``rotor.run_modal(0).wn``, the lowest ``count``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        modal = rotor.run_modal(speed=0.0, num_modes=max(2 * count, 12))
    return np.sort(np.asarray(modal.wn, dtype=float))[:count] / (2.0 * np.pi)


@dataclass(frozen=True)
class ModalComparison:
    """ROSS's and rvcoax's lowest natural frequencies (Hz) of one shaft line on the same supports, zero speed."""

    line: ShaftLine
    ross_hz: np.ndarray
    rvcoax_hz: np.ndarray

    @property
    def relative_difference(self) -> np.ndarray:
        return np.abs(self.ross_hz / self.rvcoax_hz - 1.0)


def compare_modal(rig: Rig, which: str, ross=None, count: int = 4, line: ShaftLine | None = None
                  ) -> tuple[object, ModalComparison]:
    """ROSS's ``run_modal`` at zero speed against rvcoax's modes of the same shaft line, lowest ``count`` above
    :data:`RIGID_BODY_HZ`.

    Parameters
    ----------
    rig : Rig
    which : str
        ``"input"`` or ``"output"``.
    ross : module, optional
    count : int
        How many of the lowest nonzero frequencies (lateral pairs count twice, as ROSS lists them).
    line : ShaftLine, optional
        An operating point's line (:func:`shaft_line`); default the typed-in stiffness.

    Returns
    -------
    (ross.Rotor, ModalComparison)
    """
    line = shaft_line(rig, which) if line is None else line
    rotor = build_rotor(line, ross)
    ours = rvcoax_line_modes(rig, line, count + 6).frequencies_hz
    theirs = ross_modal_frequencies(rotor, count + 6)
    # the line is free axially and in torsion: its rigid-body modes (0 Hz, ~0.01 Hz after the shift) are left out
    ours = ours[ours > RIGID_BODY_HZ][:count]
    theirs = theirs[theirs > RIGID_BODY_HZ][:count]
    return rotor, ModalComparison(line, theirs, ours)


def fault_element(line: ShaftLine, hub: Hub) -> int:
    """ROSS shaft element that models the coupling: the one next to the hub, on the shaft's free-end side."""
    node = line.node_at(hub.x_mm)
    middle = 0.5 * (line.node_x_mm[0] + line.node_x_mm[-1])
    element = node - 1 if hub.x_mm < middle else node
    return int(np.clip(element, 0, line.node_x_mm.size - 2))


def misalignment_parameters(export: DynamicsExport, line: ShaftLine) -> list[dict]:
    """Per case and coupling hub of ``line``: the parameters of ``ross.MisalignmentFlex`` (SI).

    ``mis_distance_x_m``/``mis_distance_y_m`` are the coupling's parallel offset in ROSS's axes
    (x = −z of rvcoax, y = y) and ``mis_angle_rad`` its angular misalignment, from the state Y and
    β are measured from; ``radial_stiffness_N_per_m`` and ``bending_stiffness_Nm_per_rad`` are the
    rig's coupling stiffnesses; ``input_torque_Nm``/``load_torque_Nm`` the torque the coupling
    carries; ``n`` the shaft element of :func:`fault_element`. :func:`fault_arguments` turns a row
    into ROSS's keyword arguments.

    Parameters
    ----------
    export : DynamicsExport
        From :func:`rvcoax.results.export.dynamics_export`.
    line : ShaftLine
        From :func:`shaft_line`.

    Returns
    -------
    list of dict
        One row per case and hub, keys with SI units.
    """
    rig = export.sweep.rig
    couplings = {c.name: c for c in rig.couplings}
    rows = []
    for hub in line.hubs:
        coupling = couplings[hub.coupling]
        index = export.measured.index("coupling", hub.coupling)
        for i, case in enumerate(export.sweep.cases):
            delta = export.measured.deformation[i, index]
            torque = float(export.measured.force_on_b[i, index, 3])
            rows.append({
                "T1_input_Nm": case.case.input_torque_Nm, "T2_output_Nm": case.case.output_torque_Nm,
                "shaft": line.which, "coupling": hub.coupling, "n": fault_element(line, hub), "mis_type": "combined",
                "mis_distance_x_m": float(-delta[2]) + 0.0, "mis_distance_y_m": float(delta[1]) + 0.0,
                "mis_angle_rad": math.hypot(delta[4], delta[5]),
                "radial_stiffness_N_per_m": coupling.radial_stiffness_N_per_mm * 1e3,
                "bending_stiffness_Nm_per_rad": coupling.angular_stiffness_Nm_per_rad,
                "input_torque_Nm": torque, "load_torque_Nm": torque,
            })
    return rows


FAULT_ARGUMENTS = {"n": "n", "mis_type": "mis_type", "mis_distance_x": "mis_distance_x_m",
                   "mis_distance_y": "mis_distance_y_m", "mis_angle": "mis_angle_rad",
                   "radial_stiffness": "radial_stiffness_N_per_m", "bending_stiffness": "bending_stiffness_Nm_per_rad",
                   "input_torque": "input_torque_Nm", "load_torque": "load_torque_Nm"}
"""``ross.MisalignmentFlex`` keyword → column of :func:`misalignment_parameters` (SI, units in the names)."""


def fault_arguments(parameters: dict) -> dict:
    """The keyword arguments of ``ross.MisalignmentFlex`` (and of ``rotor.run_misalignment``) from one row."""
    return {keyword: parameters[column] for keyword, column in FAULT_ARGUMENTS.items()}


def misalignment_fault(rotor, parameters: dict, ross=None):
    """``ross.MisalignmentFlex`` on ``rotor`` from one row of :func:`misalignment_parameters`.

    Parameters
    ----------
    rotor : ross.Rotor
        From :func:`build_rotor`.
    parameters : dict
        One row of :func:`misalignment_parameters`.
    ross : module, optional
        The ``ross`` package (imported when not given).

    Returns
    -------
    ross.MisalignmentFlex
        The fault, ready for ROSS's time response.
    """
    rs = ross if ross is not None else import_ross()
    return rs.MisalignmentFlex(rotor, **fault_arguments(parameters))


def save_rotor(rotor, path: str | Path, header: str = "") -> Path:
    """``rotor.save`` through a temporary file in the same folder (ROSS picks the format by suffix), with ``header``
    as TOML comment lines on top (ROSS's loader skips comments)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.stem}.partial{path.suffix}")
    try:
        rotor.save(temporary)
        if header:
            lines = "".join(f"# {line}\n" for line in header.splitlines())
            temporary.write_text(lines + temporary.read_text(encoding="utf-8"), encoding="utf-8")
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path


@dataclass(frozen=True)
class RossFiles:
    """What :func:`write_ross` wrote, the static comparison of each measured shaft (in file order) and the modal one
    of each shaft and operating point."""

    paths: tuple[Path, ...]
    comparisons: tuple[StaticComparison, ...]
    modal: tuple[ModalComparison, ...] = ()


def write_ross(export: DynamicsExport, folder: str | Path, ross=None) -> RossFiles:
    """The ROSS files of ``export`` in ``folder``: ``ross_<shaft>_rotor.toml`` per measured shaft (the rotor with
    its misalignment faults checked by ROSS; with nonlinear bearings one rotor per load case,
    ``ross_<shaft>_rotor_caseNN.toml``, at that case's operating bearing stiffness, named on the file's first lines),
    ``ross_misalignment.csv`` (the fault parameters per case), ``ross_static.csv`` (ROSS's and rvcoax's gravity sag
    of each shaft on rigid supports) and ``ross_modal.csv`` (ROSS's and rvcoax's lowest natural frequencies).

    Raises
    ------
    RossUnavailableError
        ROSS is not installed.
    """
    ross = import_ross() if ross is None else ross
    folder = Path(folder)
    sweep = export.sweep
    rig = sweep.rig
    if sweep.nonlinear_bearings is None:  # linear bearings: the typed-in stiffness is the operating one in every case
        points = [(None, "every load case (linear bearings)", "")]
    else:
        points = [(i, c.case.label, f"_case{i + 1:02d}") for i, c in enumerate(sweep.cases)]
    written, faults, static, comparisons, modal, modal_rows = [], [], [], [], [], []
    for shaft in MEASURED_SHAFTS:
        for index, label, suffix in points:
            line = shaft_line(rig, shaft, {} if index is None else operating_supports(sweep, index), label)
            rotor, comparison = compare_static(rig, shaft, ross, line)
            _, frequencies = compare_modal(rig, shaft, ross, 4, line)
            if not index:  # once per shaft: the faults and the static check do not depend on the bearings' stiffness
                parameters = misalignment_parameters(export, line)
                for row in parameters:
                    misalignment_fault(rotor, row, ross)  # ROSS accepts every set of parameters
                faults += parameters
                static += [{"shaft": shaft, "x_mm": float(x), "uy_ross_um": float(a * 1e6),
                            "uy_rvcoax_um": float(b * 1e6)}
                           for x, a, b in zip(line.node_x_mm, comparison.ross_uy_m, comparison.rvcoax_uy_m)]
                comparisons.append(comparison)
            modal.append(frequencies)
            modal_rows += [{"shaft": shaft, "load_case": label, "mode": k + 1, "frequency_ross_Hz": float(a),
                            "frequency_rvcoax_Hz": float(b)}
                           for k, (a, b) in enumerate(zip(frequencies.ross_hz, frequencies.rvcoax_hz))]
            stiffness = ", ".join(f"{s.spring}: k_y {s.radial_stiffness_N_per_m * 1e-6:.6g} N/µm, k_z "
                                  f"{s.stiffness_z_N_per_m * 1e-6:.6g} N/µm" for s in line.supports)
            header = (f"rvcoax {shaft} shaft ({line.part}) of {rig.rig.name}\nbearing stiffness of load case: {label}"
                      f"\n{stiffness}\nrotor tag: {rotor.tag}")
            written.append(save_rotor(rotor, folder / f"ross_{shaft}_rotor{suffix}.toml", header))
    written.append(write_csv_atomic(folder / "ross_misalignment.csv", faults))
    written.append(write_csv_atomic(folder / "ross_static.csv", static))
    written.append(write_csv_atomic(folder / "ross_modal.csv", modal_rows))
    return RossFiles(tuple(written), tuple(comparisons), tuple(modal))
