"""ROSS adapter: the measured shafts as ``ross.Rotor`` models, their misalignment faults, ROSS's static analysis.

ROSS (the open-source rotordynamics package ``ross-rotordynamics``) is an optional dependency:
``pip install "rvcoax[ross]"``. It is imported only here, lazily, and its absence is reported
with that instruction (:class:`RossUnavailableError`).

For each measured shaft (``input``, ``output``) the adapter builds

- a :class:`ShaftLine` from the rig: the shaft's beam elements exactly as the rvcoax beam model
  has them (node positions, outer and inner diameters, material), its supports (bearings, and joints
  with lateral stiffness to a housing, such as the reducer's output flange) with their radial
  stiffness, and the coupling hubs it carries (half the coupling mass each, no rotary inertia, as
  in the rvcoax model);
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
"""

from __future__ import annotations

import contextlib
import math
import os
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

__all__ = ["FAULT_ARGUMENTS", "Hub", "INSTALL_HINT", "ROSS_GRAVITY_M_PER_S2", "RossUnavailableError",
           "ShaftLine", "StaticComparison", "Support", "build_rotor", "compare_static", "fault_arguments",
           "fault_element", "import_ross", "misalignment_fault", "misalignment_parameters", "ross_gravity_sag",
           "RossFiles", "operating_radial_stiffness", "rvcoax_gravity_sag", "save_rotor", "shaft_line", "write_ross"]

ROSS_GRAVITY_M_PER_S2 = 9.8065
"""The gravity ``ross.Rotor.run_static`` applies (fixed inside ROSS)."""
INSTALL_HINT = 'pip install "rvcoax[ross]"  (the package ross-rotordynamics)'


class RossUnavailableError(RvcoaxError, RuntimeError):
    """ROSS is not installed (or cannot be imported); the message says how to install it."""


@contextlib.contextmanager
def _quiet_output():
    """Silence stdout/stderr at the file-descriptor level (ROSS's dependencies print on import)."""
    saved = [os.dup(1), os.dup(2)]
    with open(os.devnull, "w") as null:
        try:
            os.dup2(null.fileno(), 1)
            os.dup2(null.fileno(), 2)
            yield
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)


def import_ross():
    """The ``ross`` module, or :class:`RossUnavailableError` with the install instruction.

    Returns
    -------
    module
        ``ross``, imported with its start-up output and warnings silenced.

    Raises
    ------
    RossUnavailableError
        ROSS is not installed (the message says how to install it).
    """
    try:
        with _quiet_output(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import ross
    except ImportError as error:
        raise RossUnavailableError(f"the ROSS export needs ROSS: {INSTALL_HINT} ({error})") from None
    return ross


@dataclass(frozen=True)
class Support:
    """A lateral support of a shaft line: a bearing or a joint to a housing (radial stiffness in N/m)."""

    spring: SpringId
    x_mm: float
    radial_stiffness_N_per_m: float


@dataclass(frozen=True)
class Hub:
    """A coupling hub carried by the shaft line (mass in kg)."""

    coupling: str
    x_mm: float
    mass_kg: float


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


def shaft_line(rig: Rig, which: str, operating_N_per_m: dict[str, float] | None = None) -> ShaftLine:
    """The measured shaft ``which`` with its beam-model nodes, supports and coupling hubs.

    ``operating_N_per_m``: the radial operating stiffness of the bearings with a clearance or from ball
    geometry (:func:`operating_radial_stiffness`); their typed-in or filled-in linear reference spring is
    not their stiffness, so such a bearing without one is refused (``ValueError`` naming it).
    """
    name = getattr(rig.paths, which).part
    part = rig.part(name)
    frame = build_rig_model(rig)
    x = np.sort(frame.node_x_mm[frame.node_part == name])
    sections = np.array([_section_at(part, 0.5 * (a + b)) for a, b in zip(x[:-1], x[1:])])
    operating = operating_N_per_m or {}
    nonlinear = [b.name for b in rig.bearings if b.shaft == name and (b.model != "linear" or b.radial_clearance_um > 0)
                 and b.name not in operating]
    if nonlinear:
        raise ValueError(f"bearing(s) {', '.join(nonlinear)} of the {which} shaft are nonlinear (ball geometry or "
                         "clearance): give their operating stiffness from a sweep (operating_radial_stiffness)")
    supports = [Support(SpringId("bearing", b.name), b.x_mm, operating.get(b.name, b.radial_stiffness_N_per_um * 1e6))
                for b in rig.bearings if b.shaft == name]
    for j in rig.joints:
        lateral = min(j.translational_stiffness_N_per_um[1:]) * 1e6
        ends = {j.from_.part: j.from_.x_mm, j.to.part: j.to.x_mm}
        if name in ends and lateral > 0 and len(ends) == 2:
            supports.append(Support(SpringId("joint", j.name), ends[name], lateral))
    hubs = [Hub(c.name, end.x_mm, c.mass_kg / 2.0) for c in rig.couplings for end in (c.from_, c.to)
            if end.part == name]
    material = rig.materials[part.material]
    return ShaftLine(which=which, part=name, node_x_mm=x, outer_diameter_mm=sections[:, 0],
                     inner_diameter_mm=sections[:, 1], material=part.material,
                     density_kg_per_m3=material.density_kg_per_m3, youngs_modulus_Pa=material.youngs_modulus_MPa * 1e6,
                     poisson_ratio=material.poisson_ratio, supports=tuple(sorted(supports, key=lambda s: s.x_mm)),
                     hubs=tuple(hubs))


def build_rotor(line: ShaftLine, ross=None):
    """A ``ross.Rotor`` of ``line``: Timoshenko shaft elements, bearings at the supports, hubs as disks."""
    rs = ross if ross is not None else import_ross()
    material = rs.Material(name=f"rvcoax_{line.material}".replace(" ", "_"), rho=line.density_kg_per_m3,
                           E=line.youngs_modulus_Pa, Poisson=line.poisson_ratio)
    lengths = np.diff(line.node_x_mm) * MM
    shaft = [rs.ShaftElement(L=float(length), idl=float(inner * MM), odl=float(outer * MM), material=material, n=i,
                             shear_method_calc="cowper")
             for i, (length, outer, inner) in enumerate(zip(lengths, line.outer_diameter_mm, line.inner_diameter_mm))]
    disks = [rs.DiskElement(n=line.node_at(h.x_mm), m=h.mass_kg, Id=0.0, Ip=0.0, tag=f"hub_{h.coupling}")
             for h in line.hubs]
    bearings = [rs.BearingElement(n=line.node_at(s.x_mm), kxx=s.radial_stiffness_N_per_m,
                                  kyy=s.radial_stiffness_N_per_m, cxx=0.0, tag=f"{s.spring.kind}_{s.spring.name}")
                for s in line.supports]
    return rs.Rotor(shaft, disks, bearings, tag=f"rvcoax_{line.which}_shaft")


def ross_gravity_sag(rotor) -> np.ndarray:
    """ROSS's static deflection in y (m) at every node: gravity on rigid bearings (``run_static``)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # ROSS's rigid supports (k = 1e20) make an ill-conditioned dense solve
        return np.asarray(rotor.run_static().deformation, dtype=float)


def rvcoax_gravity_sag(rig: Rig, line: ShaftLine, gravity_m_per_s2: float = ROSS_GRAVITY_M_PER_S2) -> np.ndarray:
    """The same shaft in rvcoax: its beam elements and hubs under gravity, supports rigid in y and z (m).

    The elements, hubs and material are those of the rig's beam model; the shaft is cut free from
    every other part, and u_x and the twist are held at the first support (they carry no load).
    """
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
    hubs = PointMasses(renumber[masses.node[on_shaft]], masses.mass_kg[on_shaft],
                       masses.rotary_inertia_kg_m2[on_shaft])
    support_nodes = [line.node_at(s.x_mm) for s in line.supports]
    fixed = [DOFS_PER_NODE * n + c for n in support_nodes for c in (1, 2)]
    fixed += [DOFS_PER_NODE * support_nodes[0] + c for c in (0, 3)]
    no_springs = Bushings(np.zeros(0, int), np.zeros(0, int), np.zeros((0, 3)), np.zeros((0, 6)))
    model = StructuralModel(structure.coordinates[nodes], local, no_springs, point_masses=hubs,
                            fixed_dofs=np.array(sorted(fixed)))
    system = assemble_frame(model, [0.0, -gravity_m_per_s2, 0.0])
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


def operating_radial_stiffness(export: DynamicsExport) -> dict[str, float]:
    """The radial operating stiffness of the nonlinear bearings, for the ROSS rotors.

    Parameters
    ----------
    export : DynamicsExport
        :func:`rvcoax.results.export.dynamics_export` of a sweep.

    Returns
    -------
    dict of str to float
        Per bearing with a clearance or from ball geometry: the tangent of its force law (N/m, mean of y
        and z) in the sweep's case of the largest torque (|T2|, then |T1|); empty for a linear sweep.
    """
    sweep = export.sweep
    if sweep.nonlinear_bearings is None:
        return {}
    case = max(range(len(sweep.cases)), key=lambda i: (abs(sweep.cases[i].case.output_torque_Nm),
                                                       abs(sweep.cases[i].case.input_torque_Nm)))
    states = export.measured
    out = {}
    for b in sweep.rig.bearings:
        if b.model != "linear" or b.radial_clearance_um > 0:
            k = states.stiffness[case, states.index("bearing", b.name)]
            out[b.name] = float(0.5 * (k[1] + k[2]))
    return out


def compare_static(rig: Rig, which: str, ross=None, operating_N_per_m: dict[str, float] | None = None
                   ) -> tuple[object, StaticComparison]:
    """Build the ROSS rotor of the measured shaft ``which`` and compare its static analysis with rvcoax.

    Parameters
    ----------
    rig : Rig
        A validated rig.
    which : str
        ``"input"`` or ``"output"``.
    ross : module, optional
        The ``ross`` package (imported when not given).
    operating_N_per_m : dict, optional
        The nonlinear bearings' radial operating stiffness (:func:`operating_radial_stiffness`).

    Returns
    -------
    (ross.Rotor, StaticComparison)
        The rotor, and both codes' gravity sag of the shaft on rigid supports with their difference.

    Raises
    ------
    RossUnavailableError
        ROSS is not installed.
    """
    line = shaft_line(rig, which, operating_N_per_m)
    rotor = build_rotor(line, ross)
    return rotor, StaticComparison(line, ross_gravity_sag(rotor), rvcoax_gravity_sag(rig, line))


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


def save_rotor(rotor, path: str | Path) -> Path:
    """``rotor.save`` through a temporary file in the same folder (ROSS picks the format by suffix)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.stem}.partial{path.suffix}")
    try:
        rotor.save(temporary)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path


@dataclass(frozen=True)
class RossFiles:
    """What :func:`write_ross` wrote, and the static comparison of each measured shaft (in file order)."""

    paths: tuple[Path, ...]
    comparisons: tuple[StaticComparison, ...]


def write_ross(export: DynamicsExport, folder: str | Path, ross=None) -> RossFiles:
    """The ROSS files of ``export`` in ``folder``: ``ross_<shaft>_rotor.toml`` per measured shaft (the rotor with
    its misalignment faults checked by ROSS), ``ross_misalignment.csv`` (the fault parameters per case) and
    ``ross_static.csv`` (ROSS's and rvcoax's gravity sag of each shaft on rigid supports).

    Raises
    ------
    RossUnavailableError
        ROSS is not installed.
    """
    ross = import_ross() if ross is None else ross
    folder = Path(folder)
    written, faults, static, comparisons = [], [], [], []
    for shaft in MEASURED_SHAFTS:
        rotor, comparison = compare_static(export.sweep.rig, shaft, ross, operating_radial_stiffness(export))
        line = comparison.line
        parameters = misalignment_parameters(export, line)
        for row in parameters:
            misalignment_fault(rotor, row, ross)  # ROSS accepts every set of parameters
        faults += parameters
        static += [{"shaft": shaft, "x_mm": float(x), "uy_ross_um": float(a * 1e6), "uy_rvcoax_um": float(b * 1e6)}
                   for x, a, b in zip(line.node_x_mm, comparison.ross_uy_m, comparison.rvcoax_uy_m)]
        written.append(save_rotor(rotor, folder / f"ross_{shaft}_rotor.toml"))
        comparisons.append(comparison)
    written.append(write_csv_atomic(folder / "ross_misalignment.csv", faults))
    written.append(write_csv_atomic(folder / "ross_static.csv", static))
    return RossFiles(tuple(written), tuple(comparisons))
