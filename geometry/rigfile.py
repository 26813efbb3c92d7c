"""Reading a rig file: TOML → validated :class:`rvcoax.geometry.schema.Rig`, with errors a user can act on."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from pydantic import ValidationError

from rvcoax.errors import InputFileProblems
from rvcoax.geometry.inputfiles import InputFileError, read_input_text
from rvcoax.geometry.schema import Rig
from rvcoax.geometry.validation import read_toml_model, validation_problems

__all__ = ["MAX_RIG_BYTES", "REFERENCE_RIG", "REFERENCE_VARIANTS", "RigFileError", "UNKNOWN_KEY", "load_rig", "parse_rig",
           "parse_rig_text", "reference_rig_text"]

REFERENCE_RIG = "reference_rig.toml"
REFERENCE_VARIANTS = {"ball_bearings": "reference_rig_ball_bearings.toml",
                      "rolling_bearings": "reference_rig_rolling_bearings.toml"}
"""Variants of the reference rig: the input and output shaft bearings as ball bearings from geometry, or as
angular-contact, cylindrical and tapered roller bearings from geometry."""
MAX_RIG_BYTES = 4_000_000  # the reference rig is 20 kB; 200 times that is no hand-written rig


class RigFileError(InputFileProblems):
    """A rig file that cannot be used; the message names the file, the keys and the reasons."""

    what = "rig file"


UNKNOWN_KEY = "it is not part of the rig schema"


def parse_rig(data: dict, source: str) -> Rig:
    """Validate a parsed TOML document; raise :class:`RigFileError` naming every problem."""
    try:
        return Rig.model_validate(data)
    except ValidationError as error:
        raise RigFileError(source, validation_problems(error, data, UNKNOWN_KEY)) from None


def load_rig(path: str | Path | None = None) -> Rig:
    """Load and validate a rig file.

    Parameters
    ----------
    path : str or Path, optional
        The rig's TOML file; ``None`` loads the built-in reference rig (paper 000's test rig).

    Returns
    -------
    Rig
        The validated rig: parts, couplings, bearings, loads, paths and mesh settings, in the file's units.

    Raises
    ------
    RigFileError
        The file cannot be read, is not TOML, or a key is missing, unknown or out of its physical range
        (the message names the file, the key and the reason).
    """
    if path is None:
        text = resources.files("rvcoax.geometry").joinpath("data", REFERENCE_RIG).read_text(encoding="utf-8")
        source = f"<built-in {REFERENCE_RIG}>"
    else:
        source = str(path)
        try:
            text = read_input_text(path, MAX_RIG_BYTES, "a rig file")
        except InputFileError as error:
            raise RigFileError(source, [str(error)]) from None
    return parse_rig_text(text, source)


def parse_rig_text(text: str, source: str = "<rig text>") -> Rig:
    """Parse and validate the text of a rig file.

    Parameters
    ----------
    text : str
        The TOML text.
    source : str
        What to call the text in error messages (a file name).

    Returns
    -------
    Rig
        The validated rig.

    Raises
    ------
    RigFileError
        The text is not TOML, or a key is missing, unknown or out of its physical range.
    """
    return read_toml_model(Rig, text, lambda problems: RigFileError(source, problems), unknown_key=UNKNOWN_KEY)


def reference_rig_text(variant: str | None = None) -> str:
    """The built-in reference rig file, as text (to copy and edit); ``variant`` names one of
    :data:`REFERENCE_VARIANTS` (``"ball_bearings"``).

    Parameters
    ----------
    variant : str, optional
        A variant of the reference rig; None for the rig itself.

    Returns
    -------
    str
        The TOML text.

    Raises
    ------
    RigFileError
        Unknown variant.
    """
    name = REFERENCE_RIG
    if variant is not None:
        if variant not in REFERENCE_VARIANTS:
            raise RigFileError(f"reference rig variant {variant!r}",
                               [f"unknown variant (known: {', '.join(REFERENCE_VARIANTS)})"])
        name = REFERENCE_VARIANTS[variant]
    return resources.files("rvcoax.geometry").joinpath("data", name).read_text(encoding="utf-8")
