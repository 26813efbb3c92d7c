"""The rig files shipped with rvcoax, and how the reference rig is recognised.

``reference_rig.toml`` is paper 000's RV-20E bench, the rig the paper's published table belongs to;
``rv40e_example_rig.toml`` is an example of another layout (an RV-40E bench with one torque sensor,
a 260 mm output shaft and a hysteresis brake) with its own load cases.

A rig *is* the reference rig when its validated content equals the built-in reference rig's,
key for key and value for value (:func:`is_reference_rig`): comments, layout and key order do not
matter, any changed number, name or added key does. Paper 000's load cases and published table
are used by default for that rig only, never because a rig's name or a copied comment says so.
"""

from __future__ import annotations

from functools import lru_cache
from importlib import resources

from rvcoax.geometry.rigfile import REFERENCE_RIG, parse_rig_text
from rvcoax.geometry.schema import Rig

__all__ = ["EXAMPLE_RIG", "example_rig_text", "is_reference_rig", "load_example_rig", "reference_differences"]

EXAMPLE_RIG = "rv40e_example_rig.toml"


def example_rig_text() -> str:
    """The built-in example rig (RV-40E bench), as text (to copy and edit).

    Returns
    -------
    str
        The TOML text of the example rig file.
    """
    return resources.files("rvcoax.geometry").joinpath("data", EXAMPLE_RIG).read_text(encoding="utf-8")


def load_example_rig() -> Rig:
    """The built-in example rig (RV-40E bench), validated.

    Returns
    -------
    Rig
        The example rig.
    """
    return parse_rig_text(example_rig_text(), f"<built-in {EXAMPLE_RIG}>")


@lru_cache(maxsize=1)
def _reference() -> Rig:
    text = resources.files("rvcoax.geometry").joinpath("data", REFERENCE_RIG).read_text(encoding="utf-8")
    return parse_rig_text(text, f"<built-in {REFERENCE_RIG}>")


def is_reference_rig(rig: Rig) -> bool:
    """True when ``rig`` is the built-in reference rig (paper 000's bench), value for value.

    Parameters
    ----------
    rig : Rig
        The rig to compare.

    Returns
    -------
    bool
        Whether every value equals the reference rig's.
    """
    return rig == _reference()


def reference_differences(rig: Rig, limit: int = 3) -> list[str]:
    """Where ``rig`` differs from the built-in reference rig: up to ``limit`` items such as
    ``parts[0].mass_kg = 2.6 (the reference has 2.5)``, in the order of the rig file's keys.

    Used to tell the user of a copy of the reference rig why it is no longer treated as the
    reference (paper 000's load cases and table belong to the reference only).

    Parameters
    ----------
    rig : Rig
        The rig to compare.
    limit : int
        At most this many differences are listed.

    Returns
    -------
    list of str
        Empty when ``rig`` is the reference rig.
    """
    found: list[str] = []

    def walk(where: str, mine, theirs) -> None:
        if len(found) >= limit or mine == theirs:
            return
        if isinstance(mine, dict) and isinstance(theirs, dict):
            for key in list(mine) + [k for k in theirs if k not in mine]:
                walk(f"{where}.{key}" if where else str(key), mine.get(key), theirs.get(key))
        elif isinstance(mine, list) and isinstance(theirs, list) and len(mine) == len(theirs):
            for i, (a, b) in enumerate(zip(mine, theirs)):
                walk(f"{where}[{i}]", a, b)
        elif isinstance(mine, list) and isinstance(theirs, list):
            found.append(f"{where} has {len(mine)} entries (the reference has {len(theirs)})")
        else:
            found.append(f"{where} = {_shown(mine)} (the reference has {_shown(theirs)})")

    walk("", rig.model_dump(by_alias=True), _reference().model_dump(by_alias=True))
    return found


def _shown(value) -> str:
    if value is None:
        return "no such key"
    text = repr(value) if isinstance(value, str) else f"{value:g}" if isinstance(value, float) else str(value)
    return text if len(text) <= 60 else text[:57] + "…"
