"""The physical effects library: named, bounded augmentations of a rig model.

An :class:`Effect` is one physically meaningful change of the rig with one bounded parameter at
one location, named in a stable vocabulary (``coupling_offset@C3``, ``bearing_clearance@input_B1``,
``self_weight``, …). Parameters are **increments relative to the rig as given**: zero leaves the
rig's results unchanged, so every candidate is available on any rig and the base model is
"all parameters zero". :func:`candidate_effects` lists every candidate at every location of a rig.

Every kind is declared once, in :data:`EFFECT_KINDS`: its builder, how it changes the model (``response``: a load,
a spring, a clearance, or a rebuilt model; the discrepancy engine solves each accordingly) and what a fitted value
means in an engineer's words (``Effect.meaning``).

Each effect is expressed as rig-file changes: :meth:`Effect.rig_changes` gives parameter
addresses (:mod:`rvcoax.geometry.parameters`) and their new values, :meth:`Effect.new_items` the
entries it adds to a list (e.g. a new ``[[torque_lateral_loads]]`` of kind ``proportional``), and
:meth:`Effect.apply` the validated rig with both. ``rvcoax.geometry.rigwrite.updated_rig_text`` writes such
a rig into the user's file.

Vocabulary (parameter, unit, whether Y is affine in it):

=============================  ==================================  =====  ==========
effect                         parameter                           unit   linear
=============================  ==================================  =====  ==========
``self_weight``                ``extra_weight_factor``             –      yes
``force_pairs``                ``force_table_scale_added``         –      yes
``bearing_stiffness@B``        ``log2_stiffness_factor``           –      no
``bearing_clearance@B``        ``clearance_um``                    µm     no
``bearing_preload@B``          ``preload_N``                       N      no
``mount_compliance@P``         ``compliance_factor``               –      no
``coupling_offset@C``          ``offset_um``                       µm     yes
``coupling_angle@C``           ``angle_mrad``                      mrad   yes
``mesh_force@reducer_input``   ``force_per_torque_N_per_Nm``       N/N·m  yes
``torque_reaction@P``          ``force_per_torque_N_per_Nm``       N/N·m  yes
``shear_deformation``          ``shear_fraction``                  –      no
``thermal_growth@P``           ``lift_um``                         µm     yes
``mesh_position_error@L``      ``position_error_um``               µm     yes
``mesh_position_error@G``      ``position_error_um``               µm     yes
``temperature_rise@P``         ``temperature_rise_K``              °C     yes
``housing_stiffness@H``        ``log2_stiffness_factor``           –      no
=============================  ==================================  =====  ==========

"linear" means Y is exactly affine in the parameter; on a rig with a bearing clearance or a ball
bearing from geometry nothing is (the model is nonlinear), and every effect is then flagged ``linear = False``.

On a ball bearing (``model = "ball"``) ``bearing_clearance@B`` is its operating radial internal
clearance (diametral, ``clearance_um``, 0 … the top of ISO 5753-1's C4 range) and ``bearing_preload@B``
its axial preload (``preload_N``, 0 … 2 % of C0); ``bearing_stiffness@B`` is not offered there (the
stiffness follows from geometry). On a cylindrical roller bearing from geometry ``bearing_clearance@B`` is
its clearance the same way (ISO 5753-1's table for cylindrical roller bearings). On an angular-contact or
tapered roller bearing ``bearing_preload@B`` is its setting: ``preload_N`` when the entry gives a preload force
(0 … the heavy class), else ``axial_offset_um`` (an axial play of 30 µm … the heavy class's offset); an entry
set by ``preload_class`` has no bearing effect. On a linear bearing ``bearing_clearance@B`` is the radial gap
``radial_clearance_um`` (from the centred position) and ``bearing_preload@B`` does not exist.

With ``paths.measured_from = "aligned_at_rest"`` (the reference rig) Y is u − u_rest, so an effect
that does not depend on torque (self-weight, force table, offsets, thermal growth) leaves Y
unchanged on a linear rig: that is physics, not a bug. Such effects are observable when Y is
measured from the unloaded geometry (``measured_from = "unloaded"``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

from pydantic import ValidationError

from rvcoax.geometry.parameters import get_parameter, with_parameters
from rvcoax.geometry.schema import Rig

__all__ = ["EFFECT_KINDS", "Effect", "EffectKind", "EffectParameter", "KINDS", "RESPONSES", "RigChange", "STANDARD_GRAVITY",
           "candidate_effects", "effect_by_name", "effect_x_mm", "meaning"]

STANDARD_GRAVITY = 9.80665  # m/s²


@dataclass(frozen=True)
class EffectParameter:
    """One parameter of an effect.

    Attributes
    ----------
    name : str
        With its unit in the name (``offset_um``).
    unit : str
    lower, upper : float
        Physical bounds of the increment on this rig; a fit outside them is rejected.
    typical : float
        A realistic magnitude on the reference rig (scale for fitting and synthetic tests).
    """

    name: str
    unit: str
    lower: float
    upper: float
    typical: float


@dataclass(frozen=True)
class RigChange:
    """What an effect does to a rig file: new values at addresses, and new list entries."""

    values: dict = field(default_factory=dict)
    new_items: dict = field(default_factory=dict)  # group → list of entries (file keys)


@dataclass(frozen=True)
class Effect:
    """A named physical augmentation of a rig with bounded parameters (increments; zero = rig as given).

    Attributes
    ----------
    name : str
        Stable vocabulary, ``<kind>@<location>`` or ``<kind>`` for a global effect.
    kind : str
    location : str or None
    parameters : tuple of EffectParameter
    linear : bool
        Y is exactly affine in the parameters.
    description : str
        One physical sentence.
    """

    name: str
    kind: str
    location: str | None
    parameters: tuple[EffectParameter, ...]
    linear: bool
    description: str
    change: Callable[[Rig, tuple[float, ...]], RigChange] = field(repr=False, compare=False, default=None)

    def _values(self, values: Sequence[float]) -> tuple[float, ...]:
        values = tuple(float(v) for v in (values if isinstance(values, Sequence) else list(values)))
        if len(values) != len(self.parameters):
            raise ValueError(f"{self.name} takes {len(self.parameters)} value(s) "
                             f"({', '.join(p.name for p in self.parameters)}), got {len(values)}")
        bad = [p.name for p, v in zip(self.parameters, values) if not math.isfinite(v)]
        if bad:
            raise ValueError(f"{self.name}: {', '.join(bad)} must be finite")
        return values

    def rig_changes(self, rig: Rig, values: Sequence[float]) -> dict[str, float]:
        """Parameter addresses → new values (a true/false key as 1.0/0.0); new entries are in :meth:`new_items`."""
        return dict(self.change(rig, self._values(values)).values)

    def new_items(self, rig: Rig, values: Sequence[float]) -> dict[str, list[dict]]:
        """Entries the effect appends to lists of the rig file (group → entries), e.g. a new lateral load."""
        return {group: [dict(item) for item in items]
                for group, items in self.change(rig, self._values(values)).new_items.items()}

    def apply(self, rig: Rig, values: Sequence[float]) -> Rig:
        """A new, validated rig with the effect; ``values`` all zero gives the same results as ``rig``.

        Raises
        ------
        ValueError
            The values make an invalid rig (the reason names the key).
        """
        change = self.change(rig, self._values(values))
        try:
            changed = rig
            if change.new_items:
                data = rig.model_dump(by_alias=True)
                for group, items in change.new_items.items():
                    data[group] = list(data[group]) + [dict(item) for item in items]
                changed = Rig.model_validate(data)
            return with_parameters(changed, change.values) if change.values else changed
        except ValidationError as error:
            reasons = "; ".join(f"{'.'.join(str(x) for x in e['loc']) or 'rig'}: {e['msg']}" for e in error.errors())
            raise ValueError(f"{self.name} = {list(values)}: {reasons}") from None

    @property
    def response(self) -> str:
        """How the effect changes the model (:data:`RESPONSES`): ``load``, ``spring``, ``clearance`` or ``rebuild``."""
        return KINDS[self.kind].response

    @property
    def acts(self) -> str:
        """What the effect does to the rig, in engineering words, without its place or size."""
        return KINDS[self.kind].acts

    def meaning(self, values: Sequence[float]) -> str:
        """What the fitted ``values`` mean physically, in one engineering sentence."""
        (v, *_) = [float(x) for x in values]
        return KINDS[self.kind].says(self.location, v, self.parameters[0].unit)

    def out_of_bounds(self, values: Sequence[float]) -> list[str]:
        """One reason per value outside its physical bounds (empty when all are inside)."""
        return [f"{p.name} = {v:g} {p.unit} lies outside its physical bounds [{p.lower:g}, {p.upper:g}] {p.unit}"
                for p, v in zip(self.parameters, self._values(values)) if not p.lower <= v <= p.upper]


# ---- the effects ------------------------------------------------------------------------------------------

def _self_weight(rig: Rig) -> Effect:
    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        (p,) = v
        if r.gravity.enabled:
            return RigChange({"gravity.acceleration_m_per_s2": r.gravity.acceleration_m_per_s2 * (1.0 + p)})
        if p == 0.0:
            return RigChange()
        return RigChange({"gravity.enabled": 1.0, "gravity.acceleration_m_per_s2": STANDARD_GRAVITY * p})

    # 0…3: housing masses are [R]/[A] catalogue estimates (rig_reference.md); a factor 3 covers a
    # brake of 46 kg [A] that weighs 4× more, or fixtures forgotten in the model. With gravity off,
    # 1 is the full self-weight.
    off = "" if rig.gravity.enabled else " (gravity is off in this rig: 1 is the full self-weight)"
    return Effect(name="self_weight", kind="self_weight", location=None,
                  parameters=(EffectParameter("extra_weight_factor", "-", 0.0, 3.0, 0.5),), linear=True,
                  description="Every part weighs (1 + factor) times its modelled weight: masses of housings and fixtures "
                  f"underestimated{off}.", change=change)


def _force_pairs(rig: Rig) -> Effect:
    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        (p,) = v
        if r.force_table.apply:
            return RigChange({"force_table.scale": r.force_table.scale + p})
        if p == 0.0:
            return RigChange()
        return RigChange({"force_table.apply": 1.0, "force_table.scale": p})

    # ±2: paper 000 gives the pairs without saying where or in which direction they act
    # (rig_reference.md), so the sign is open; 1 is the table as published.
    return Effect(name="force_pairs", kind="force_pairs", location=None,
                  parameters=(EffectParameter("force_table_scale_added", "-", -2.0, 2.0, 1.0),), linear=True,
                  description="Paper 000's force table (F1 … F9, as interpreted in the rig file) added with this scale.", change=change)


def _doubles(address: str) -> Callable:
    """change() multiplying the value at ``address`` by 2 to the power of the effect's one parameter."""

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({address: get_parameter(r, address) * 2.0 ** v[0]})

    return change


def _bearing_stiffness(rig: Rig, name: str) -> Effect:
    change = _doubles(f"bearings.{name}.radial_stiffness_N_per_um")

    # 1/16 … 2: a ball bearing's radial stiffness depends on preload and clearance; the reference
    # 40–65 N/µm [S] holds for a preloaded 6204/6206 and drops by an order of magnitude near zero
    # load with internal clearance.
    return Effect(name=f"bearing_stiffness@{name}", kind="bearing_stiffness", location=name,
                  parameters=(EffectParameter("log2_stiffness_factor", "-", -4.0, 1.0, -1.0),), linear=False,
                  description=f"The radial stiffness of bearing {name} times 2^factor (preload, clearance, seat fit).", change=change)


def _bearing_clearance(rig: Rig, name: str) -> Effect:
    address = f"bearings.{name}.radial_clearance_um"
    current = get_parameter(rig, address)

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({address: get_parameter(r, address) + v[0]})

    # the gap c is measured from the centred position, half the radial internal clearance: CN group
    # 5–20 µm for 6204/6206 [S] (rig_reference.md) → c = 2.5–10 µm; C3 up to 28 µm → 14 µm. Total ≥ 0.
    return Effect(name=f"bearing_clearance@{name}", kind="bearing_clearance", location=name,
                  parameters=(EffectParameter("clearance_um", "µm", -current, 15.0 - current, 5.0),), linear=False,
                  description=f"Radial play of bearing {name}: no radial force until the shaft has moved the gap "
                  "(a dead band, nonlinear).", change=change)


# ---- ball bearings from geometry (model = "ball"): operating clearance and preload, in physical units ----

def _ball_clearance(rig: Rig, name: str) -> Effect:
    from rvcoax.geometry import ball_model, rolling_model

    address = f"bearings.{name}.clearance_um"
    bearing = next(b for b in rig.bearings if b.name == name)
    model = ball_model if bearing.model == "ball" else rolling_model  # ball or cylindrical_roller
    clearance_um_of, clearance_upper_um = model.clearance_um_of, model.clearance_upper_um
    current = clearance_um_of(bearing)
    what = "ball bearing" if bearing.model == "ball" else "cylindrical roller bearing"

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({address: clearance_um_of(next(b for b in r.bearings if b.name == name)) + v[0]})

    # 0 … the top of ISO 5753-1's C4 range for the bore: the operating clearance after fits and
    # temperatures lies between zero (a tight fit) and an unmounted C4 bearing.
    return Effect(name=f"bearing_clearance@{name}", kind="bearing_clearance", location=name,
                  parameters=(EffectParameter("clearance_um", "µm", -current, clearance_upper_um(bearing) - current, 5.0),),
                  linear=False, description=f"Operating radial internal clearance of {what} {name} (diametral, µm) changed by this "
                  "much: a dead band and a softer, load-dependent stiffness (nonlinear).", change=change)


def _ball_preload(rig: Rig, name: str) -> Effect:
    from rvcoax.geometry.ball_model import preload_upper_N

    address = f"bearings.{name}.preload_N"
    bearing = next(b for b in rig.bearings if b.name == name)

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({address: get_parameter(r, address) + v[0]})

    # 0 … 2 % of the static load rating C0 (ball_model.preload_upper_N): a wave-spring or nut preload
    return Effect(name=f"bearing_preload@{name}", kind="bearing_preload", location=name,
                  parameters=(EffectParameter("preload_N", "N", 0.0 - bearing.preload_N + 0.0, preload_upper_N(bearing) - bearing.preload_N,
                                   20.0),),
                  linear=False, description=f"Axial preload of ball bearing {name} (N) changed by this much: it takes up the clearance "
                  "and stiffens the bearing.", change=change)


def _rolling_preload(rig: Rig, name: str) -> Effect | None:
    """An angular-contact or tapered roller bearing's setting: its preload force (``preload_N`` given) or its
    axial offset (``axial_offset_um`` or nothing given); None for one set by a preload class."""
    from rvcoax.geometry.rolling_model import heavy_setting

    bearing = next(b for b in rig.bearings if b.name == name)
    if bearing.preload_class is not None:
        return None
    heavy_n, heavy_um = heavy_setting(bearing)  # up to the heavy class's preload, as a force and as an offset
    if bearing.preload_N:
        address = f"bearings.{name}.preload_N"

        def change(r: Rig, v: tuple[float, ...]) -> RigChange:
            return RigChange({address: get_parameter(r, address) + v[0]})

        return Effect(name=f"bearing_preload@{name}", kind="bearing_preload", location=name,
                      parameters=(EffectParameter("preload_N", "N", -bearing.preload_N, heavy_n - bearing.preload_N, 20.0),),
                      linear=False, description=f"Axial preload of bearing {name} (N) changed by this much: it stiffens the bearing.",
                      change=change)
    address = f"bearings.{name}.axial_offset_um"
    current = bearing.axial_offset_um or 0.0

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({address: (next(b for b in r.bearings if b.name == name).axial_offset_um or 0.0) + v[0]})

    # from an axial play of 30 µm (a loose adjustment) to the heavy class's preload (an over-tight one)
    return Effect(name=f"bearing_preload@{name}", kind="bearing_preload", location=name,
                  parameters=(EffectParameter("axial_offset_um", "µm", -30.0 - current, max(heavy_um - current, 0.0), 2.0),),
                  linear=False, description=f"Axial setting of bearing {name} (µm from first contact; > 0 a preload, < 0 a play) changed "
                  "by this much: play is a dead band, preload stiffens the bearing.", change=change)


def _mount_compliance(rig: Rig, part: str) -> Effect:
    addresses = [f"mounts.{m.name}.translational_stiffness_N_per_um[1]" for m in rig.mounts if m.part == part]

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({a: get_parameter(r, a) / (1.0 + v[0]) for a in addresses})

    # -0.5 … 20: the mounts are [A] 100–500 N/µm; a bolted pedestal or bracket on a bed can be an
    # order of magnitude softer (joint compliance), seldom much stiffer (×2 at most).
    return Effect(name=f"mount_compliance@{part}", kind="mount_compliance", location=part,
                  parameters=(EffectParameter("compliance_factor", "-", -0.5, 20.0, 1.0),), linear=False,
                  description=f"The vertical stiffness of the mounts of {part} divided by (1 + factor): a softer pedestal, "
                  "bracket or bolted joint.", change=change)


@dataclass(frozen=True)
class _Misalignment:
    """A coupling misalignment effect: its kind, the coupling key it adds to, its parameter and its name in words."""

    kind: str
    key: str
    parameter: EffectParameter
    what: str


# ±100 µm: allowed parallel offset of the C1/C3 bellows couplings 0.1 mm [S] (rig_reference.md);
# 20 µm is a good dial-indicator alignment.
_OFFSET = _Misalignment("coupling_offset", "parallel_offset_um", EffectParameter("offset_um", "µm", -100.0, 100.0, 20.0),
                        "Parallel misalignment")
# ±17.45 mrad: allowed angular misalignment 1° [S] (rig_reference.md); 0.5 mrad (0.05 mm per
# 100 mm) is a good alignment.
_ANGLE = _Misalignment("coupling_angle", "angular_misalignment_mrad",
                       EffectParameter("angle_mrad", "mrad", -17.45, 17.45, 0.5), "Angular misalignment")


def _coupling(rig: Rig, name: str, misalignment: _Misalignment) -> Effect:
    coupling = next(c for c in rig.couplings if c.name == name)
    plane = ("vertical" if math.isclose(math.cos(math.radians(coupling.misalignment_direction_deg)), 1.0)
             else f"at {coupling.misalignment_direction_deg:g}° from +Y")
    kind = misalignment.kind
    return Effect(name=f"{kind}@{name}", kind=kind, location=name, parameters=(misalignment.parameter,), linear=True,
                  description=f"{misalignment.what} of coupling {name} ({plane}, its misalignment_direction_deg), a "
                  "prestrain present at rest and in every case.",
                  change=_adds_to(f"couplings.{name}.{misalignment.key}"))


def _coupling_offset(rig: Rig, name: str) -> Effect:
    return _coupling(rig, name, _OFFSET)


def _coupling_angle(rig: Rig, name: str) -> Effect:
    return _coupling(rig, name, _ANGLE)


def _proportional(rig: Rig, item: str, torque: str, on: dict, reacted_on: dict | None) -> Callable:
    """change() adding p to the proportional lateral load ``item`` (created when the rig has none)."""
    address = f"torque_lateral_loads.{item}.force_per_torque_N_per_Nm"

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        if any(t.name == item for t in r.torque_lateral_loads):
            return RigChange({address: get_parameter(r, address) + v[0]})
        entry = {"name": item, "torque": torque, "kind": "proportional", "on": on, "direction_deg": 0.0,
                 "force_per_torque_N_per_Nm": v[0]}
        if reacted_on is not None:
            entry["reacted_on"] = reacted_on
        return RigChange(new_items={"torque_lateral_loads": [entry]})

    return change


def _location(location) -> dict:
    return location.model_dump(exclude_none=True)


def _mesh_force(rig: Rig) -> Effect | None:
    mesh = next((t for t in rig.torque_lateral_loads if t.kind == "gear_mesh_load_sharing" and t.torque == "T1"), None)
    if mesh is None:
        return None
    reacted = _location(mesh.reacted_on) if mesh.reacted_on is not None else None
    change = _proportional(rig, "mesh_force_reducer_input", "T1", _location(mesh.on), reacted)
    # ±100 N per N·m: the input gear's tangential force per N·m is 1/r = 100 N at r = 10 mm [A]; a
    # lateral mesh force cannot exceed it. 2 N per N·m is the reference imbalance 0.02 / r / cos 20°.
    return Effect(name="mesh_force@reducer_input", kind="mesh_force", location="reducer_input",
                  parameters=(EffectParameter("force_per_torque_N_per_Nm", "N/(N·m)", -100.0, 100.0, 2.0),), linear=True,
                  description=f"A vertical gear-mesh force proportional to T1 on {mesh.on.part} at x = {mesh.on.x_mm:g} mm "
                  "(where the input gear meshes), reacted on the reducer.", change=change)


def _torque_reaction(rig: Rig, part: str) -> Effect:
    body = rig.part(part)
    lo, hi = body.x_range_mm
    change = _proportional(rig, f"torque_reaction_{part}", "T2", {"part": part, "x_mm": 0.5 * (lo + hi)}, None)
    # ±20 N per N·m: a torque arm of ≥ 50 mm; 2 N per N·m is an arm of 0.5 m, or an asymmetric
    # pedestal turning a tenth of the torque into a vertical force at 50 mm.
    return Effect(name=f"torque_reaction@{part}", kind="torque_reaction", location=part,
                  parameters=(EffectParameter("force_per_torque_N_per_Nm", "N/(N·m)", -20.0, 20.0, 2.0),), linear=True,
                  description=f"A vertical reaction proportional to T2 on the housing {part} (torque arm, asymmetric pedestal), "
                  "carried to the ground by its mounts.", change=change)


def _shear(rig: Rig) -> Effect:
    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        if v[0] == 0.0:
            return RigChange()
        return RigChange({"beam.shear_deformation": 1.0, "beam.shear_flexibility_factor": v[0]})

    # 0…1: the shear flexibility Φ of the Timoshenko beam blended in, 1 = full Timoshenko (a
    # continuous parameter instead of a switch, so it can be fitted).
    return Effect(name="shear_deformation", kind="shear_deformation", location=None,
                  parameters=(EffectParameter("shear_fraction", "-", 0.0, 1.0, 1.0),), linear=False,
                  description="The beams' shear deformation (Timoshenko), blended in from the Euler–Bernoulli model.", change=change)


def _thermal_growth(rig: Rig, part: str) -> Effect:
    addresses = [f"mounts.{m.name}.vertical_offset_um" for m in rig.mounts if m.part == part]

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({a: get_parameter(r, a) + v[0] for a in addresses})

    # ±50 µm: a cast-iron housing (α ≈ 11e-6/K) with its axis ≈ 200 mm above the bed [A]
    # (rig_reference.md) grows 44 µm for 20 K; 10 µm is ≈ 5 K, or a shim.
    return Effect(name=f"thermal_growth@{part}", kind="thermal_growth", location=part,
                  parameters=(EffectParameter("lift_um", "µm", -50.0, 50.0, 10.0),), linear=True,
                  description=f"Every mount of {part} raised by the same height: thermal growth of the housing, or a shim.",
                  change=change)


def _adds_to(address: str) -> Callable:
    """change() adding the effect's one parameter to the value at ``address``."""

    def change(r: Rig, v: tuple[float, ...]) -> RigChange:
        return RigChange({address: get_parameter(r, address) + v[0]})

    return change


# ±10 µm: the IT3 band of the reference rig is ±2 µm (input) / ±3 µm (output) [P]; ISO grade 5–6 pitch and runout
# errors of gears (base pitch deviation f_pb, tooth-to-tooth; ISO 1328-1) reach 5–10 µm for modules of 1–2 mm.
_POSITION_ERROR = EffectParameter("position_error_um", "µm", -10.0, 10.0, 1.0)


def _mesh_position_error(rig: Rig, name: str) -> Effect:
    change = _adds_to(f"torque_lateral_loads.{name}.position_error_um")
    # The force k_eff·Δε acts while torque flows (bounds: _POSITION_ERROR).
    return Effect(name=f"mesh_position_error@{name}", kind="mesh_position_error", location=name,
                  parameters=(_POSITION_ERROR,), linear=True,
                  description=f"A position error of the two load-sharing meshes of {name}: a lateral force k_eff·Δε that "
                  "appears as soon as torque flows, whatever its size (a constant offset of the loaded rig).", change=change)


def _gear_mesh_position_error(rig: Rig, name: str) -> Effect:
    change = _adds_to(f"gear_meshes.{name}.planet_position_errors_um[0]")
    # ±10 µm, as for the typed-in load sharing (_POSITION_ERROR).
    return Effect(name=f"mesh_position_error@{name}", kind="mesh_position_error", location=name,
                  parameters=(_POSITION_ERROR,), linear=True,
                  description=f"The first planet mesh of gear mesh {name} engages this much later along its line of action "
                  "(a position error): the load sharing of its planets, and so the net force on the driving gear, "
                  "follow from the gear data.", change=change)


def _housing_stiffness(rig: Rig, name: str) -> Effect:
    change = _doubles(f"housings.{name}.stiffness_factor")

    # 1/8 … 2: the condensed block is the solid as drawn, bolted perfectly to a rigid bed; bolted
    # joints, a softer bed and fillets left out make real housings 2–8× softer, seldom stiffer.
    return Effect(name=f"housing_stiffness@{name}", kind="housing_stiffness", location=name,
                  parameters=(EffectParameter("log2_stiffness_factor", "-", -3.0, 1.0, -1.0),), linear=False,
                  description=f"The condensed stiffness of housing {name} times 2^factor (bolted joints, bed, details not drawn).",
                  change=change)


def _temperature_rise(rig: Rig, part: str) -> Effect:
    change = _adds_to(f"thermal.temperature_rise_K.{part}")

    # −10 … 40 °C: a running servo motor, brake or reducer runs 20–40 K above the room; a rig
    # aligned warm and measured cooler, −10 K.
    return Effect(name=f"temperature_rise@{part}", kind="temperature_rise", location=part,
                  parameters=(EffectParameter("temperature_rise_K", "°C", -10.0, 40.0, 10.0),), linear=True,
                  description=f"{part} (and its supports, unless given their own) this much warmer: it grows by α ΔT axially and "
                  "radially, and its supports lift it by α ΔT times their height above the bed.", change=change)


def _thermal_candidates(rig: Rig) -> list[Effect]:
    """``temperature_rise@P`` for the parts a temperature can be given to: with ``[thermal]``, a material with
    ``thermal_expansion_per_K`` and every mount with ``height_above_bed_mm``."""
    if rig.thermal is None:
        return []
    out = []
    for p in rig.parts:
        own = [m for m in rig.mounts if m.part == p.name]
        materials = [p.material] + [m.support_material for m in own if m.support_material]
        if all(rig.materials[name].thermal_expansion_per_K is not None for name in materials) and all(
                m.height_above_bed_mm is not None for m in own):
            out.append(_temperature_rise(rig, p.name))
    return out


def _with_linearity(effect: Effect, linear_rig: bool) -> Effect:
    return replace(effect, linear=False) if effect.linear and not linear_rig else effect


def _torque_reaction_parts(rig: Rig, mounted: list[str]) -> list[str]:
    """Mounted housings between the T1 and T2 application points (reducer, sensors, brake, blocks)."""
    x1, x2 = sorted((rig.torques.T1.x_mm, rig.torques.T2.x_mm))
    out = []
    for name in mounted:
        lo, hi = rig.part(name).x_range_mm
        if rig.part(name).role == "body" and hi > x1 and lo < x2:
            out.append(name)
    return out


def _mounted(rig: Rig) -> list[str]:
    return list(dict.fromkeys(m.part for m in rig.mounts))


# ---- the vocabulary, declared once ------------------------------------------------------------------------

RESPONSES = {
    "load": "changes only the loads: solved exactly on the base model's factorisation",
    "spring": "changes a few spring stiffnesses: solved exactly on the factorisation (Woodbury identity)",
    "clearance": "opens a gap in a bearing: nonlinear, an active-set iteration on the factorisation",
    "rebuild": "changes the model itself (its elements or geometry): solved by real sweeps of the changed rig",
}


@dataclass(frozen=True)
class EffectKind:
    """One kind of effect of the vocabulary, declared once: what it is, how it changes the model's response,
    what a fitted value means, and where it can act on a rig.

    Attributes
    ----------
    kind : str
        The stable name (the part of an effect's name before ``@``).
    response : str
        How it changes the model (a key of :data:`RESPONSES`): ``load``, ``spring``, ``clearance`` or ``rebuild``.
    build : callable
        ``build(rig)`` → every effect of this kind on ``rig``, in the rig's order.
    says : callable
        ``says(location, value, unit)`` → what the fitted value (in the parameter's unit) means, in one engineering
        sentence.
    acts : str
        What the effect does to the rig, in engineering words, without its place or size (``a vertical force
        proportional to T2``): what a group of look-alikes shares.
    per : str or None
        ``"bearing"`` or ``"coupling"``: the kind is listed with the other kinds at each bearing (coupling), in the
        rig's order of them; None: on its own.
    """

    kind: str
    response: str
    build: Callable[[Rig], list[Effect]] = field(repr=False)
    says: Callable[[str | None, float, str], str] = field(repr=False)
    acts: str = ""
    per: str | None = None


EFFECT_KINDS: tuple[EffectKind, ...] = (
    EffectKind("self_weight", "load", lambda rig: [_self_weight(rig)],
               lambda where, v, unit: f"the parts weigh {1.0 + v:.3g}× what is modelled (housings, fixtures)",
               acts="heavier parts (a vertical dead load, independent of torque)"),
    EffectKind("force_pairs", "load",
               lambda rig: [_force_pairs(rig)] if rig.force_table.pairs or rig.force_table.singles else [],
               lambda where, v, unit: f"paper 000's force table acts with {v:+.3g}× its published forces",
               acts="the force table's lateral loads scaled"),
    EffectKind("bearing_stiffness", "spring",  # a bearing from geometry: its stiffness follows from its data
               lambda rig: [_bearing_stiffness(rig, b.name) for b in rig.bearings if b.model == "linear"],
               lambda where, v, unit: f"bearing {where} is {2.0 ** v:.3g}× as stiff radially as modelled (preload, "
                                      "clearance or seat fit)", acts="a bearing stiffer or softer radially",
               per="bearing"),
    EffectKind("bearing_clearance", "clearance",  # ball and cylindrical roller bearings: their operating clearance
               lambda rig: [(_bearing_clearance if b.model == "linear" else _ball_clearance)(rig, b.name)
                            for b in rig.bearings if b.model in ("linear", "ball", "cylindrical_roller")],
               lambda where, v, unit: f"bearing {where} has {v:.3g} µm more radial play than modelled (a dead band)",
               acts="radial play in a bearing (a dead band)", per="bearing"),
    EffectKind("bearing_preload", "rebuild",  # ball: preload; angular-contact and tapered: their setting
               lambda rig: [e for b in rig.bearings for e in (
                   [_ball_preload(rig, b.name)] if b.model == "ball" else
                   [_rolling_preload(rig, b.name)] if b.model not in ("linear", "cylindrical_roller") else [])
                   if e is not None],
               lambda where, v, unit: f"bearing {where} is set {v:+.3g} {unit} "
                                      + ("tighter (more axial preload)" if unit == "N" else
                                         "further from first contact (> 0 a preload, < 0 a play)")
                                      + " than modelled",
               acts="a bearing's axial preload or setting changed", per="bearing"),
    EffectKind("mount_compliance", "spring", lambda rig: [_mount_compliance(rig, p) for p in _mounted(rig)],
               lambda where, v, unit: f"the mounts of the {where} are {1.0 + v:.3g}× as soft vertically as modelled",
               acts="a housing's mounts softer vertically"),
    EffectKind("coupling_offset", "load", lambda rig: [_coupling_offset(rig, c.name) for c in rig.couplings],
               lambda where, v, unit: f"the hubs of coupling {where} are offset {v:+.3g} µm vertically more than modelled",
               acts="a parallel offset of a coupling's hubs (a prestrain present at rest)",
               per="coupling"),
    EffectKind("coupling_angle", "load", lambda rig: [_coupling_angle(rig, c.name) for c in rig.couplings],
               lambda where, v, unit: f"the hubs of coupling {where} are tilted {v:+.3g} mrad ({v / 10:+.3g} mm per 100 mm) "
                                "more than modelled", acts="an angular misalignment of a coupling's hubs (a prestrain present at rest)",
               per="coupling"),
    EffectKind("mesh_force", "load", lambda rig: [e for e in (_mesh_force(rig),) if e is not None],
               lambda where, v, unit: f"a vertical gear-mesh force of {v:+.3g} N per N·m of T1 acts at the reducer input",
               acts="a vertical force proportional to T1"),
    EffectKind("mesh_position_error", "load",
               lambda rig: [_mesh_position_error(rig, t.name) for t in rig.torque_lateral_loads
                            if t.kind in ("gear_mesh_load_sharing", "crank_load_sharing")]
               + [_gear_mesh_position_error(rig, g.name) for g in rig.gear_meshes],
               lambda where, v, unit: f"the load-sharing meshes {where} have a position error of {v:+.3g} µm (a lateral "
                                "force while torque flows)",
               acts="a lateral force that appears as soon as torque flows"),
    EffectKind("torque_reaction", "load",
               lambda rig: [_torque_reaction(rig, p) for p in _torque_reaction_parts(rig, _mounted(rig))],
               lambda where, v, unit: f"a vertical force of {v:+.3g} N per N·m of T2 acts on the housing {where} (a torque "
                                "arm or an asymmetric pedestal)",
               acts="a vertical force proportional to T2"),
    EffectKind("shear_deformation", "rebuild", lambda rig: [] if rig.beam.shear_deformation else [_shear(rig)],
               lambda where, v, unit: f"the shafts shear as a Timoshenko beam to {100 * v:.3g} % of the full shear "
                                "flexibility",
               acts="shear flexibility of the shafts"),
    EffectKind("thermal_growth", "load", lambda rig: [_thermal_growth(rig, p) for p in _mounted(rig)],
               lambda where, v, unit: f"the {where} stands {abs(v):.3g} µm {'higher' if v > 0 else 'lower'} than modelled "
                                "(thermal growth or a shim)",
               acts="a housing standing higher or lower (thermal growth or a shim)"),
    EffectKind("temperature_rise", "rebuild", _thermal_candidates,
               lambda where, v, unit: f"the {where} runs {v:+.3g} °C warmer than modelled (it grows, and its supports lift "
                                "it)",
               acts="a part running warmer"),
    EffectKind("housing_stiffness", "rebuild", lambda rig: [_housing_stiffness(rig, h.name) for h in rig.housings],
               lambda where, v, unit: f"housing {where} is {2.0 ** v:.3g}× as stiff as its condensed model (bolted joints, "
                                "bed, details not drawn)",
               acts="a condensed housing stiffer or softer"),
)
"""Every kind of the vocabulary, in the order :func:`candidate_effects` lists them: adding a kind is one entry here
(with its builder above) plus its test and its line in docs/discrepancy.md."""

KINDS: dict[str, EffectKind] = {k.kind: k for k in EFFECT_KINDS}
_PLACES = {"bearing": lambda rig: [b.name for b in rig.bearings], "coupling": lambda rig: [c.name for c in rig.couplings]}


def candidate_effects(rig: Rig) -> tuple[Effect, ...]:
    """Every candidate effect at every location of ``rig``: each kind of :data:`EFFECT_KINDS` where it can act.

    Couplings: offset and angle; bearings: stiffness and clearance (a ball bearing: clearance and preload); parts
    with mounts: mount compliance and thermal growth; mounted housings between T1 and T2: torque reaction; the
    reducer input (the first ``gear_mesh_load_sharing`` on T1): mesh force; load-sharing meshes: position error;
    global: self-weight, force pairs (when the rig has a force table), shear deformation (when it is off); with
    ``[thermal]``, temperature rise; condensed housings: their stiffness.

    Parameters
    ----------
    rig : Rig
        The rig as modelled.

    Returns
    -------
    tuple of Effect
        Each with its name (``kind@location``), parameters with units and bounds, and how it changes the rig.
        The kinds at one bearing (coupling) are listed together, the bearings (couplings) in the rig's order.
    """
    linear_rig = not any(b.radial_clearance_um > 0 or b.model != "linear" for b in rig.bearings)
    first = {}
    for rank, k in enumerate(EFFECT_KINDS):
        first.setdefault(k.per or k.kind, rank)
    keyed = []
    for rank, k in enumerate(EFFECT_KINDS):
        places = _PLACES[k.per](rig) if k.per else None
        for i, effect in enumerate(k.build(rig)):
            key = (first[k.per], places.index(effect.location), rank) if k.per else (rank, i, 0)
            keyed.append((key, _with_linearity(effect, linear_rig)))
    return tuple(effect for _, effect in sorted(keyed, key=lambda item: item[0]))


def effect_x_mm(effect: Effect, rig: Rig) -> float | None:
    """Where along the rig's axis (x, mm) an effect acts: its bearing, its coupling's centre, the middle of its part,
    its load-sharing mesh; None for a global effect (self-weight, shear) or a place without one x."""
    where = effect.location
    if where is None:
        return None
    for b in rig.bearings:
        if b.name == where:
            return float(b.x_mm)
    for c in rig.couplings:
        if c.name == where:
            return float(c.centre_x_mm)
    for t in rig.torque_lateral_loads:
        if t.name == where:
            return float(t.on.x_mm)
    if where == "reducer_input":
        mesh = next((t for t in rig.torque_lateral_loads if t.kind == "gear_mesh_load_sharing"), None)
        return None if mesh is None else float(mesh.on.x_mm)
    part = next((p for p in rig.parts if p.name == where), None)
    return None if part is None else 0.5 * float(sum(part.x_range_mm))


def effect_by_name(rig: Rig, name: str) -> Effect:
    """The candidate effect ``name`` of ``rig``.

    Raises
    ------
    KeyError
        No such candidate on this rig (the message lists them).
    """
    effects = candidate_effects(rig)
    for effect in effects:
        if effect.name == name:
            return effect
    raise KeyError(f"no effect '{name}' on rig '{rig.rig.name}'; candidates: {', '.join(e.name for e in effects)}")


def meaning(effect: Effect, values: Sequence[float]) -> str:
    """What the fitted ``values`` of ``effect`` mean physically, in one engineering sentence."""
    return effect.meaning(values)
