"""Housings, bearing blocks, pedestals and brackets condensed from a solid FE model to a superelement.

Three shapes, each in rig coordinates (mm; the rig's axis is y = z = 0):

* :class:`BlockGeometry` — a box along the axis, an optional bore on the axis, an optional wider foot
  plate on the bed; its feet are the whole bed face;
* :class:`PedestalGeometry` — a web pedestal: a base plate on the bed with four square bolt feet at its
  corners, a vertical web (any section: a thin plate across or along the axis, or a box column) and a
  bearing seat (a box with the bore) on top;
* :class:`BracketGeometry` — a wall bracket: a plate bolted to a wall parallel to the axis (plane
  z = −wall distance) by four square bolt feet, an arm of rectangular section reaching to the seat, and
  the bearing seat at its free end.

Each is meshed with gmsh into curved quadratic tetrahedra (:func:`rvcoax.geometry.meshing.mesh_part`,
cached by content hash); its feet are clamped or sit on an elastic bed (a Winkler foundation: normal and
shear stiffness per area; a spring per bolt foot is the same law with the foot's stiffness spread over its
area), and one 6-DOF reference node per attachment is tied to a face (a band of the bore, or the top
face). The supported model is then reduced to the reference nodes (:mod:`rvcoax.fem.condensation`): a
6k × 6k stiffness against the ground that enters the rig like a bushing. The condensed matrix is cached
too, keyed by everything it depends on.

This module is the geometric half (the shapes, their feet, the faces references are tied to); the
finite-element half (the supported solid model, its condensation and the cache) is
:mod:`rvcoax.geometry.model.condensed_housing`.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass

import numpy as np
import skfem

from rvcoax.geometry.meshing import MESHER_VERSION

__all__ = ["BlockGeometry", "BracketGeometry", "FootPatch", "HOUSING_VERSION", "HousingGeometry", "PedestalGeometry",
           "Reference", "foot_facets", "housing_faces"]

HOUSING_VERSION = 2
"""Bump whenever a change here changes a condensed matrix (invalidates its cache entries)."""
_TOL_MM = 1e-6


@dataclass(frozen=True)
class FootPatch:
    """A bolt foot (or a whole bed face): the rectangle of the plane ``coordinate[axis] = at_mm`` (mm) that rests on
    the bed or the wall, ``span_mm`` its extent along the two other axes in increasing order ((x, z) for a foot on
    the bed, axis 1; (x, y) for a foot on a wall, axis 2)."""

    axis: int
    at_mm: float
    span_mm: tuple[tuple[float, float], tuple[float, float]]

    @property
    def area_mm2(self) -> float:
        (a0, a1), (b0, b1) = self.span_mm
        return (a1 - a0) * (b1 - b0)


def _plate_boxes(occ, low, high, pad: float, axes: tuple[int, int]) -> list:
    """A plate (box from ``low`` to ``high``, mm) cut into 3 × 3 boxes along ``axes`` so that its four corner squares of
    side ``pad`` (the bolt feet) have faces of their own (one box when ``pad`` is 0)."""
    cuts = []
    for axis in axes:
        points = [low[axis], high[axis]]
        cuts.append(points if pad <= 0 else [low[axis], low[axis] + pad, high[axis] - pad, high[axis]])
    boxes = []
    for a0, a1 in zip(cuts[0][:-1], cuts[0][1:]):
        for b0, b1 in zip(cuts[1][:-1], cuts[1][1:]):
            lo, hi = list(low), list(high)
            lo[axes[0]], hi[axes[0]], lo[axes[1]], hi[axes[1]] = a0, a1, b0, b1
            boxes.append(_box(occ, lo, hi))
    return boxes


def _box(occ, low, high) -> tuple[int, int]:
    return (3, occ.addBox(*low, *(h - lo for h, lo in zip(high, low))))


def _corner_feet(axis: int, at_mm: float, span_mm, pad: float) -> tuple[FootPatch, ...]:
    """The four corner squares of side ``pad`` of the rectangle ``span_mm`` (the whole rectangle when ``pad`` is 0)."""
    (a0, a1), (b0, b1) = span_mm
    if pad <= 0:
        return (FootPatch(axis, at_mm, ((a0, a1), (b0, b1))),)
    return tuple(FootPatch(axis, at_mm, (a, b)) for a in ((a0, a0 + pad), (a1 - pad, a1))
                 for b in ((b0, b0 + pad), (b1 - pad, b1)))


def _check_feet_fit(where: str, pad: float, length: float, across: float, plate: str) -> None:
    if not 2 * pad < min(length, across):
        raise ValueError(f"{where}: two bolt feet of {pad:g} mm do not fit side by side on the {plate} plate "
                         f"({length:g} × {across:g} mm)")


def _fragment(occ, volumes: list) -> None:
    """Conforming volumes whose shared faces are split where they meet."""
    if len(volumes) > 1:
        occ.fragment(volumes[:1], volumes[1:])
    occ.synchronize()


@dataclass(frozen=True)
class BlockGeometry:
    """A block along x in rig coordinates (mm): the rig's axis is y = z = 0.

    Attributes
    ----------
    name : str
    x_mm : (x0, x1)
    width_mm : float
        Along z, centred on the axis.
    bottom_mm, top_mm : float
        y of the bed face (the feet's underside, < 0 when the axis is above the bed) and of the top face.
    bore_diameter_mm : float
        A through bore on the axis (0: none).
    foot_thickness_mm, foot_width_mm : float
        A foot plate (bolt flange) on the bed, wider than the block along z (thickness 0: none).
    split_x_mm : tuple
        Planes x = const where faces are split (edges of the bore bands the references are tied to).
    mesh_size_mm : float
    """

    name: str
    x_mm: tuple[float, float]
    width_mm: float
    bottom_mm: float
    top_mm: float
    bore_diameter_mm: float = 0.0
    foot_thickness_mm: float = 0.0
    foot_width_mm: float = 0.0
    split_x_mm: tuple[float, ...] = ()
    mesh_size_mm: float = 5.0

    def __post_init__(self) -> None:
        x0, x1 = self.x_mm
        where = f"housing '{self.name}'"
        if not x1 > x0:
            raise ValueError(f"{where}: x_mm must be increasing, got {list(self.x_mm)}")
        if not self.top_mm > self.bottom_mm:
            raise ValueError(f"{where}: the top (y = {self.top_mm} mm) must lie above the bed face (y = {self.bottom_mm} mm)")
        radius = 0.5 * self.bore_diameter_mm
        if radius > 0 and not (radius < self.top_mm and radius < -self.bottom_mm - self.foot_thickness_mm
                               and radius < 0.5 * self.width_mm):
            raise ValueError(f"{where}: the bore (Ø{self.bore_diameter_mm:g} mm) does not fit inside the block")
        if self.foot_thickness_mm > 0 and not (self.foot_width_mm >= self.width_mm
                                               and self.foot_thickness_mm < self.top_mm - self.bottom_mm):
            raise ValueError(f"{where}: the foot plate must be at least as wide as the block and thinner than it is tall")
        object.__setattr__(self, "split_x_mm", tuple(sorted(float(x) for x in self.split_x_mm if x0 < x < x1)))

    @property
    def breakpoints_mm(self) -> tuple[float, ...]:
        points = sorted({*self.x_mm, *self.split_x_mm})
        return tuple(points)

    @property
    def feet(self) -> tuple[FootPatch, ...]:
        """One foot: the whole bed face."""
        half = 0.5 * max(self.width_mm, self.foot_width_mm if self.foot_thickness_mm > 0 else 0.0)
        return (FootPatch(1, self.bottom_mm, (self.x_mm, (-half, half))),)

    @property
    def volume_mm3(self) -> float:
        length = self.x_mm[1] - self.x_mm[0]
        volume = self.width_mm * (self.top_mm - self.bottom_mm) * length
        volume += (self.foot_width_mm - self.width_mm) * self.foot_thickness_mm * length
        return volume - math.pi / 4 * self.bore_diameter_mm**2 * length

    def cache_key(self) -> str:
        """SHA-256 over the shape, the mesh size, gmsh's version and the mesher's version."""
        import gmsh

        payload = {"kind": "block", "x_mm": list(self.x_mm), "width_mm": self.width_mm, "bottom_mm": self.bottom_mm,
                   "top_mm": self.top_mm, "bore_diameter_mm": self.bore_diameter_mm,
                   "foot": [self.foot_thickness_mm, self.foot_width_mm], "split_x_mm": list(self.split_x_mm),
                   "mesh_size_mm": self.mesh_size_mm, "gmsh": gmsh.__version__, "mesher_version": MESHER_VERSION,
                   "housing_version": HOUSING_VERSION}
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()

    def build_occ_model(self, gmsh) -> None:
        """One slab per interval between breakpoints (box ∪ foot plate − bore), fragmented: conforming volumes
        whose faces are split at every breakpoint."""
        occ = gmsh.model.occ
        volumes = []
        points = self.breakpoints_mm
        for x0, x1 in zip(points[:-1], points[1:]):
            length = x1 - x0
            shape = [(3, occ.addBox(x0, self.bottom_mm, -0.5 * self.width_mm, length, self.top_mm - self.bottom_mm,
                                    self.width_mm))]
            if self.foot_thickness_mm > 0 and self.foot_width_mm > self.width_mm:
                foot = occ.addBox(x0, self.bottom_mm, -0.5 * self.foot_width_mm, length, self.foot_thickness_mm,
                                  self.foot_width_mm)
                shape, _ = occ.fuse(shape, [(3, foot)])
            if self.bore_diameter_mm > 0:
                bore = occ.addCylinder(x0, 0.0, 0.0, length, 0.0, 0.0, 0.5 * self.bore_diameter_mm)
                shape, _ = occ.cut(shape, [(3, bore)])
            volumes.extend(shape)
        _fragment(occ, volumes)


@dataclass(frozen=True, kw_only=True)
class _SeatGeometry:
    """The bearing seat of a pedestal or bracket: a box along x from ``seat_bottom_mm`` (y, below the axis) to
    ``top_mm``, ``width_mm`` across (z), with an optional bore on the axis; faces split at ``split_x_mm``."""

    name: str
    x_mm: tuple[float, float]
    width_mm: float
    top_mm: float
    seat_bottom_mm: float
    bore_diameter_mm: float = 0.0
    split_x_mm: tuple[float, ...] = ()
    mesh_size_mm: float = 5.0

    def _check_seat(self) -> str:
        x0, x1 = self.x_mm
        where = f"housing '{self.name}'"
        if not x1 > x0:
            raise ValueError(f"{where}: x_mm must be increasing, got {list(self.x_mm)}")
        if not self.top_mm > self.seat_bottom_mm:
            raise ValueError(f"{where}: the seat's top (y = {self.top_mm} mm) must lie above its underside "
                             f"(y = {self.seat_bottom_mm} mm)")
        radius = 0.5 * self.bore_diameter_mm
        if radius > 0 and not (radius < self.top_mm and radius < -self.seat_bottom_mm and radius < 0.5 * self.width_mm):
            raise ValueError(f"{where}: the bore (Ø{self.bore_diameter_mm:g} mm) does not fit inside the bearing seat")
        object.__setattr__(self, "split_x_mm", tuple(sorted(float(x) for x in self.split_x_mm if x0 < x < x1)))
        return where

    @property
    def centre_x_mm(self) -> float:
        return 0.5 * (self.x_mm[0] + self.x_mm[1])

    def _centred(self, length_mm: float, across_mm: float) -> tuple[tuple[float, float], tuple[float, float]]:
        """A plate's span, ``length_mm`` along x centred on the seat and ``across_mm`` centred on the axis."""
        c, a, b = self.centre_x_mm, 0.5 * length_mm, 0.5 * across_mm
        return (c - a, c + a), (-b, b)

    @property
    def _seat_volume_mm3(self) -> float:
        length = self.x_mm[1] - self.x_mm[0]
        return (self.width_mm * (self.top_mm - self.seat_bottom_mm) - math.pi / 4 * self.bore_diameter_mm**2) * length

    def _seat_payload(self) -> dict:
        import gmsh

        return {"x_mm": list(self.x_mm), "width_mm": self.width_mm, "top_mm": self.top_mm,
                "seat_bottom_mm": self.seat_bottom_mm, "bore_diameter_mm": self.bore_diameter_mm,
                "split_x_mm": list(self.split_x_mm), "mesh_size_mm": self.mesh_size_mm, "gmsh": gmsh.__version__,
                "mesher_version": MESHER_VERSION, "housing_version": HOUSING_VERSION}

    def _seat_volumes(self, occ) -> list:
        """One slab of the seat per interval between breakpoints (box − bore)."""
        points = sorted({*self.x_mm, *self.split_x_mm})
        volumes = []
        for x0, x1 in zip(points[:-1], points[1:]):
            shape = [_box(occ, (x0, self.seat_bottom_mm, -0.5 * self.width_mm), (x1, self.top_mm, 0.5 * self.width_mm))]
            if self.bore_diameter_mm > 0:
                bore = occ.addCylinder(x0, 0.0, 0.0, x1 - x0, 0.0, 0.0, 0.5 * self.bore_diameter_mm)
                shape, _ = occ.cut(shape, [(3, bore)])
            volumes.extend(shape)
        return volumes

    def cache_key(self) -> str:
        """SHA-256 over the shape, every dimension, the mesh size, gmsh's version and the mesher's version."""
        payload = {"kind": type(self).__name__, **self._seat_payload(), **self._own_payload()}
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()

    def _own_payload(self) -> dict:
        raise NotImplementedError


@dataclass(frozen=True, kw_only=True)
class PedestalGeometry(_SeatGeometry):
    """A web pedestal (rig coordinates, mm): a base plate on the bed, a vertical web, the bearing seat on top.

    Attributes
    ----------
    bottom_mm : float
        y of the bed face (the base plate's underside; < 0: the axis is above the bed).
    web_length_mm, web_width_mm : float
        The web's section along x and z, centred under the seat (a thin plate across the axis: a short
        ``web_length_mm``; along it: a narrow ``web_width_mm``; a box column: both large).
    base_length_mm, base_width_mm, base_thickness_mm : float
        The base plate (along x, along z, along y), centred under the seat.
    foot_pad_mm : float
        Side of the four square bolt feet at the base plate's corners (0: the whole underside is the foot).
    """

    bottom_mm: float
    web_length_mm: float
    web_width_mm: float
    base_length_mm: float
    base_width_mm: float
    base_thickness_mm: float
    foot_pad_mm: float = 0.0

    def __post_init__(self) -> None:
        where = self._check_seat()
        if not self.bottom_mm + self.base_thickness_mm < self.seat_bottom_mm:
            raise ValueError(f"{where}: the base plate (top at y = {self.bottom_mm + self.base_thickness_mm:g} mm) must "
                             f"lie below the seat's underside (y = {self.seat_bottom_mm:g} mm): no room for the web")
        if not (self.web_length_mm <= self.base_length_mm and self.web_width_mm <= self.base_width_mm):
            raise ValueError(f"{where}: the web ({self.web_length_mm:g} × {self.web_width_mm:g} mm) must stand on the "
                             f"base plate ({self.base_length_mm:g} × {self.base_width_mm:g} mm)")
        if not (self.web_length_mm <= self.x_mm[1] - self.x_mm[0] and self.web_width_mm <= self.width_mm):
            raise ValueError(f"{where}: the web ({self.web_length_mm:g} × {self.web_width_mm:g} mm) must fit under the "
                             f"seat ({self.x_mm[1] - self.x_mm[0]:g} × {self.width_mm:g} mm)")
        _check_feet_fit(where, self.foot_pad_mm, self.base_length_mm, self.base_width_mm, "base")

    def _own_payload(self) -> dict:
        return {"bottom_mm": self.bottom_mm, "web_mm": [self.web_length_mm, self.web_width_mm],
                "base_mm": [self.base_length_mm, self.base_width_mm, self.base_thickness_mm],
                "foot_pad_mm": self.foot_pad_mm}

    @property
    def feet(self) -> tuple[FootPatch, ...]:
        return _corner_feet(1, self.bottom_mm, self._centred(self.base_length_mm, self.base_width_mm), self.foot_pad_mm)

    @property
    def volume_mm3(self) -> float:
        web = self.web_length_mm * self.web_width_mm * (self.seat_bottom_mm - self.bottom_mm - self.base_thickness_mm)
        return self._seat_volume_mm3 + web + self.base_length_mm * self.base_width_mm * self.base_thickness_mm

    def build_occ_model(self, gmsh) -> None:
        occ = gmsh.model.occ
        c, top_of_base = self.centre_x_mm, self.bottom_mm + self.base_thickness_mm
        volumes = self._seat_volumes(occ)
        volumes.append(_box(occ, (c - 0.5 * self.web_length_mm, top_of_base, -0.5 * self.web_width_mm),
                            (c + 0.5 * self.web_length_mm, self.seat_bottom_mm, 0.5 * self.web_width_mm)))
        volumes += _plate_boxes(occ, (c - 0.5 * self.base_length_mm, self.bottom_mm, -0.5 * self.base_width_mm),
                                (c + 0.5 * self.base_length_mm, top_of_base, 0.5 * self.base_width_mm),
                                self.foot_pad_mm, (0, 2))
        _fragment(occ, volumes)


@dataclass(frozen=True, kw_only=True)
class BracketGeometry(_SeatGeometry):
    """A wall bracket (rig coordinates, mm): a plate bolted to a wall parallel to the axis, an arm, the bearing seat.

    Attributes
    ----------
    wall_z_mm : float
        z of the wall face (the plate's back, < −width/2: the wall is on the −z side of the axis).
    arm_length_mm, arm_height_mm : float
        The arm's section along x and y, centred on the seat's centre and on the axis height; it runs along z
        from the plate to the seat's side face.
    plate_length_mm, plate_height_mm, plate_thickness_mm : float
        The wall plate (along x, y, z), centred like the arm.
    foot_pad_mm : float
        Side of the four square bolt feet at the plate's corners (0: the whole back of the plate is the foot).
    """

    wall_z_mm: float
    arm_length_mm: float
    arm_height_mm: float
    plate_length_mm: float
    plate_height_mm: float
    plate_thickness_mm: float
    foot_pad_mm: float = 0.0

    def __post_init__(self) -> None:
        where = self._check_seat()
        if not self.wall_z_mm + self.plate_thickness_mm < -0.5 * self.width_mm:
            raise ValueError(f"{where}: the wall plate (front at z = {self.wall_z_mm + self.plate_thickness_mm:g} mm) "
                             f"must lie beside the seat (its side at z = {-0.5 * self.width_mm:g} mm): no room for the arm")
        if not (self.arm_length_mm <= self.x_mm[1] - self.x_mm[0]
                and 0.5 * self.arm_height_mm <= min(self.top_mm, -self.seat_bottom_mm)):
            raise ValueError(f"{where}: the arm ({self.arm_length_mm:g} × {self.arm_height_mm:g} mm) must meet the "
                             "seat's side face (no longer than the seat, no higher than its top or lower than its underside)")
        if not (self.arm_length_mm <= self.plate_length_mm and self.arm_height_mm <= self.plate_height_mm):
            raise ValueError(f"{where}: the arm ({self.arm_length_mm:g} × {self.arm_height_mm:g} mm) must meet the wall "
                             f"plate ({self.plate_length_mm:g} × {self.plate_height_mm:g} mm)")
        _check_feet_fit(where, self.foot_pad_mm, self.plate_length_mm, self.plate_height_mm, "wall")

    def _own_payload(self) -> dict:
        return {"wall_z_mm": self.wall_z_mm, "arm_mm": [self.arm_length_mm, self.arm_height_mm],
                "plate_mm": [self.plate_length_mm, self.plate_height_mm, self.plate_thickness_mm],
                "foot_pad_mm": self.foot_pad_mm}

    @property
    def feet(self) -> tuple[FootPatch, ...]:
        return _corner_feet(2, self.wall_z_mm, self._centred(self.plate_length_mm, self.plate_height_mm),
                            self.foot_pad_mm)

    @property
    def volume_mm3(self) -> float:
        arm = self.arm_length_mm * self.arm_height_mm * (-0.5 * self.width_mm - self.wall_z_mm - self.plate_thickness_mm)
        return self._seat_volume_mm3 + arm + self.plate_length_mm * self.plate_height_mm * self.plate_thickness_mm

    def build_occ_model(self, gmsh) -> None:
        occ = gmsh.model.occ
        c, front = self.centre_x_mm, self.wall_z_mm + self.plate_thickness_mm
        volumes = self._seat_volumes(occ)
        volumes.append(_box(occ, (c - 0.5 * self.arm_length_mm, -0.5 * self.arm_height_mm, front),
                            (c + 0.5 * self.arm_length_mm, 0.5 * self.arm_height_mm, -0.5 * self.width_mm)))
        volumes += _plate_boxes(occ, (c - 0.5 * self.plate_length_mm, -0.5 * self.plate_height_mm, self.wall_z_mm),
                                (c + 0.5 * self.plate_length_mm, 0.5 * self.plate_height_mm, front),
                                self.foot_pad_mm, (0, 1))
        _fragment(occ, volumes)


HousingGeometry = BlockGeometry | PedestalGeometry | BracketGeometry
"""A housing's shape: everything :func:`rvcoax.geometry.model.condensed_housing.build_housing_model` needs (``feet``, ``top_mm``, ``bore_diameter_mm``,
``cache_key``, ``build_occ_model``)."""


@dataclass(frozen=True)
class Reference:
    """A reference node at ``point_mm`` tied to a face: ``("bore", x0, x1)`` (a band of the bore), ``("top", x0, x1)``
    (the part of the top face between x0 and x1) — ``tie`` ``"distributing"`` or ``"rigid"``."""

    point_mm: tuple[float, float, float]
    face: tuple[str, float, float]
    tie: str = "distributing"


def _boundary_facets_where(mesh: skfem.MeshTet2, test) -> np.ndarray:
    facets = mesh.boundary_facets()
    corners = mesh.p[:, mesh.facets[:, facets]] / 1e-3  # (3, 3 corners, n), mm
    keep = np.all(test(corners[0], corners[1], corners[2]), axis=0)
    return facets[keep]


def _tolerance_mm(mesh: skfem.MeshTet2) -> float:
    return 1e-4 * float(np.ptp(mesh.p, axis=1).max()) / 1e-3


def housing_faces(mesh: skfem.MeshTet2, geometry: HousingGeometry, face: tuple[str, float, float]) -> np.ndarray:
    """Boundary facets of ``face``: ``("bore" | "top" | "bottom", x0, x1)``, every corner within [x0, x1]
    (``bottom``: the feet, :func:`foot_facets`)."""
    kind, x0, x1 = face
    tol = _tolerance_mm(mesh)

    def along(x):
        return (x >= x0 - _TOL_MM) & (x <= x1 + _TOL_MM)

    if kind == "bore":
        radius = 0.5 * geometry.bore_diameter_mm
        facets = _boundary_facets_where(mesh, lambda x, y, z: along(x) & (np.abs(np.hypot(y, z) - radius) < tol))
    elif kind == "top":
        facets = _boundary_facets_where(mesh, lambda x, y, z: along(x) & (np.abs(y - geometry.top_mm) < tol))
    elif kind == "bottom":
        facets = np.concatenate(foot_facets(mesh, geometry))
        centres = mesh.p[0, mesh.facets[:, facets]].mean(axis=0) / 1e-3
        facets = facets[along(centres)]
    else:
        raise ValueError(f"unknown housing face kind {kind!r} (bore, top, bottom)")
    if facets.size == 0:
        raise ValueError(f"housing '{geometry.name}': no mesh facets on its {kind} face between x = {x0:g} and {x1:g} mm")
    return facets


def foot_facets(mesh: skfem.MeshTet2, geometry: HousingGeometry) -> list[np.ndarray]:
    """The boundary facets of each of ``geometry.feet`` (one array per foot, in their order)."""
    tol = _tolerance_mm(mesh)
    found = []
    for foot in geometry.feet:
        others = [axis for axis in range(3) if axis != foot.axis]
        (a0, a1), (b0, b1) = foot.span_mm

        def on_foot(*xyz, foot=foot, others=others, a=(a0, a1), b=(b0, b1)):
            u, v = xyz[others[0]], xyz[others[1]]
            return ((np.abs(xyz[foot.axis] - foot.at_mm) < tol) & (u >= a[0] - tol) & (u <= a[1] + tol)
                    & (v >= b[0] - tol) & (v <= b[1] + tol))

        facets = _boundary_facets_where(mesh, on_foot)
        if facets.size == 0:
            raise ValueError(f"housing '{geometry.name}': no mesh facets on a foot at {'xyz'[foot.axis]} = {foot.at_mm:g} mm")
        found.append(facets)
    return found
