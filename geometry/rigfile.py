"""Reading a rig file: TOML → validated :class:`rvcoax.geometry.schema.Rig`, with errors a user can act on."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from pydantic import ValidationError

from rvcoax.fem.errors import RvcoaxError
from rvcoax.geometry.inputfiles import InputFileError, parse_toml, read_input_text
from rvcoax.geometry.schema import Rig

__all__ = ["MAX_RIG_BYTES", "REFERENCE_RIG", "REFERENCE_VARIANTS", "RigFileError", "load_rig", "parse_rig", "parse_rig_text",
           "reference_rig_text"]

REFERENCE_RIG = "reference_rig.toml"
REFERENCE_VARIANTS = {"ball_bearings": "reference_rig_ball_bearings.toml",
                      "rolling_bearings": "reference_rig_rolling_bearings.toml"}
"""Variants of the reference rig: the input and output shaft bearings as ball bearings from geometry, or as
angular-contact, cylindrical and tapered roller bearings from geometry."""
MAX_RIG_BYTES = 4_000_000  # the reference rig is 20 kB; 200 times that is no hand-written rig


class RigFileError(RvcoaxError, ValueError):
    """A rig file that cannot be used; the message names the file, the keys and the reasons."""

    def __init__(self, source: str, problems: list[str]):
        self.source = source
        self.problems = problems
        listing = "\n".join(f"  - {p}" for p in problems)
        super().__init__(f"rig file {source}: {len(problems)} problem(s):\n{listing}")


def _key_path(location: tuple) -> str:
    out = ""
    for item in location:
        if isinstance(item, int):
            out += f"[{item}]"
        else:
            out += ("." if out else "") + str(item)
    return out or "(top level)"


def _describe(error: dict, data: dict) -> str:
    location = tuple(x for x in error["loc"] if x not in ("function-after[_check()]",))
    key = _key_path(location)
    # name the item, e.g. parts[3] ('input_shaft')
    if len(location) >= 2 and isinstance(location[1], int) and isinstance(data.get(location[0]), list):
        try:
            item = data[location[0]][location[1]]
            label = item.get("name") or item.get("label")
            if label:
                key = key.replace(f"{location[0]}[{location[1]}]", f"{location[0]}[{location[1]}] ('{label}')", 1)
        except (IndexError, AttributeError, TypeError):
            pass
    kind = error["type"]
    message = error["msg"].removeprefix("Value error, ")
    if kind == "missing":
        return f"{key}: required key is missing"
    if kind == "extra_forbidden":
        return f"{key}: unknown key (misspelled? it is not part of the rig schema)"
    value = error.get("input")
    shown = f" (got {value!r})" if not isinstance(value, (dict, list)) and kind != "value_error" else ""
    return f"{key}: {message}{shown}"


def parse_rig(data: dict, source: str) -> Rig:
    """Validate a parsed TOML document; raise :class:`RigFileError` naming every problem."""
    try:
        return Rig.model_validate(data)
    except ValidationError as error:
        problems = []
        for e in error.errors():
            text = _describe(e, data)
            if e["type"] == "value_error" and not e["loc"]:
                problems.extend(text.removeprefix("(top level): ").split("\n"))
            else:
                problems.append(text)
        raise RigFileError(source, problems) from None


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
    try:
        data = parse_toml(text)
    except InputFileError as error:
        raise RigFileError(source, [str(error)]) from None
    return parse_rig(data, source)


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
