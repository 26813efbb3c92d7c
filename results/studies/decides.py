"""What decides Y: the change of Y and tilt of each measured shaft when one assumed input is doubled or halved.

An *assumed* input is a numeric rig-file key tagged ``[A]`` (an assumption) in its comment
(:func:`rvcoax.results.reports.report_tables.assumed_inputs`). Each is scaled by 2 and by ½ on its own (a
list such as a mount's three stiffnesses as a whole) and the rig is solved again in one load case
(the report takes its case of the largest torque); the inputs are ranked by the largest change of
Y over both measured shafts and both factors. This is the one-at-a-time study of the tutorial
(docs/tutorial.md, "Which numbers matter"), computed for the user's own rig; ``rvcoax sensitivity``
does the global, tolerance-weighted version.

A condensed housing's dimensions are not varied (each change is a new solid model to mesh and
condense); its ``stiffness_factor`` is the key to vary by hand. A scaled value the rig file's rules
refuse (a doubled value beyond its bound) is reported as not varied, with the reason.
"""

from __future__ import annotations

from dataclasses import dataclass

from pydantic import ValidationError

from rvcoax.fem.errors import RvcoaxError
from rvcoax.geometry import MEASURED_SHAFTS
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.sweep import SweepSettings, run_sweep

__all__ = ["FACTORS", "Influence", "NOISE", "NOT_VARIED_SECTIONS", "WhatDecides", "scaled_rig", "what_decides_y"]

FACTORS = (0.5, 2.0)
NOT_VARIED_SECTIONS = ("housings",)


@dataclass(frozen=True)
class Influence:
    """One assumed input and what halving and doubling it does to the measured shafts.

    ``y_change_um[shaft]`` and ``tilt_change_urad[shaft]``: (change when halved, change when doubled) of
    Y_max (µm) and of the true tilt (µrad), against the rig as given.
    """

    section: str
    entry: str
    key: str
    value: object
    y_change_um: dict[str, tuple[float, float]]
    tilt_change_urad: dict[str, tuple[float, float]]

    @property
    def address(self) -> str:
        return f"{self.section}.{self.entry}.{self.key}"

    @property
    def largest_y_change_um(self) -> float:
        return max(abs(v) for pair in self.y_change_um.values() for v in pair)


@dataclass(frozen=True)
class WhatDecides:
    """The ranked influences (largest first), the case solved, Y and tilt of the rig as given, and the
    inputs not varied with the reason."""

    case: LoadCase
    y_um: dict[str, float]
    tilt_urad: dict[str, float]
    ranked: tuple[Influence, ...]
    not_varied: tuple[tuple[str, str], ...]


def scaled_rig(rig: Rig, section: str, entry: str, key: str, factor: float) -> Rig:
    """A copy of ``rig`` with ``section``'s entry ``entry``'s key ``key`` (a number or a list of numbers) times
    ``factor``, validated again (``pydantic.ValidationError`` when the scaled value breaks a rule)."""
    data = rig.model_dump(by_alias=True)
    target = next(e for e in data[section] if e.get("name") == entry)
    value = target[key]
    target[key] = [v * factor for v in value] if isinstance(value, list | tuple) else value * factor
    return Rig.model_validate(data)


NOISE = 1e-9
"""A change below this share of the value it changes is the solves' rounding (a linear solve holds ~1e-12, a
nonlinear bearing's Newton stop ~1e-10), written as 0 rather than as a 2e-15 µrad "effect"."""


def _change(new: float, base: float) -> float:
    change = new - base
    return 0.0 if abs(change) <= NOISE * max(abs(new), abs(base)) else change


def _shafts(sweep) -> tuple[dict[str, float], dict[str, float]]:
    paths = sweep.cases[0].paths
    return ({s: paths[s].y_max_mm * 1e3 for s in MEASURED_SHAFTS},
            {s: paths[s].fitted_tilt_urad for s in MEASURED_SHAFTS})


def what_decides_y(rig: Rig, assumed, case: LoadCase, settings: SweepSettings | None = None,
                   progress=None) -> WhatDecides:
    """Halve and double each assumed input of ``rig`` and solve ``case`` again.

    Parameters
    ----------
    rig : Rig
        The rig as given.
    assumed : iterable of (section, entry, key, value)
        The assumed inputs (:func:`rvcoax.results.reports.report_tables.assumed_inputs`).
    case : LoadCase
        The load case solved.
    settings : SweepSettings, optional
        The model (default: beam); the beam model is used for a solid or hybrid one (a full mesh per variation would take
        minutes each).
    progress : callable, optional
        ``progress(i, n)`` after each input.

    Returns
    -------
    WhatDecides
        The inputs ranked by the largest change of Y.
    """
    if settings is None or settings.model != "beam":
        settings = SweepSettings(model="beam")
    base_y, base_tilt = _shafts(run_sweep(rig, (case,), settings, engineering=False))
    assumed = list(assumed)
    ranked, not_varied = [], []
    for i, (section, entry, key, value) in enumerate(assumed):
        address = f"{section}.{entry}.{key}"
        if section in NOT_VARIED_SECTIONS:
            not_varied.append((address, "a housing dimension: each change is a new solid to condense (vary its "
                                        "stiffness_factor instead)"))
            continue
        changes = []
        try:
            for factor in FACTORS:
                changes.append(_shafts(run_sweep(scaled_rig(rig, section, entry, key, factor), (case,), settings,
                                                 engineering=False)))
        except ValidationError as error:
            problem = error.errors()[0]
            not_varied.append((address, f"×{factor:g} is refused by the rig file's rules ({problem['msg']})"))
            continue
        except RvcoaxError as error:
            not_varied.append((address, f"×{factor:g} does not solve ({error})"))
            continue
        ranked.append(Influence(
            section=section, entry=entry, key=key, value=value,
            y_change_um={s: tuple(_change(c[0][s], base_y[s]) for c in changes) for s in MEASURED_SHAFTS},
            tilt_change_urad={s: tuple(_change(c[1][s], base_tilt[s]) for c in changes) for s in MEASURED_SHAFTS}))
        if progress is not None:
            progress(i + 1, len(assumed))
    ranked.sort(key=lambda r: r.largest_y_change_um, reverse=True)
    return WhatDecides(case=case, y_um=base_y, tilt_urad=base_tilt, ranked=tuple(ranked), not_varied=tuple(not_varied))
