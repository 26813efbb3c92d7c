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

__all__ = ["EXAMPLE_RIG", "example_rig_text", "is_reference_rig", "load_example_rig"]

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
