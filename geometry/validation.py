"""Validating an input file: the strict schema base, the one formatter of validation errors, and the one
reader "TOML text → validated schema, or an error naming the file and every key".

Every TOML input of rvcoax is read this way: the rig file (:mod:`rvcoax.geometry.rigfile`), a tolerance file
(:mod:`rvcoax.results.studies.tolerances`), chain-error stage data (:mod:`rvcoax.results.studies.chain_error`)
and a DOE study file (:mod:`rvcoax.results.studies.doe.rig_study`). Their schemas derive from
:class:`StrictModel`, so an unknown (misspelled) key is an error, never ignored. A problem names its key as
the file writes it (``parts[3] ('input_shaft').x_mm``) and the reason, with the value given; the message's
form is :func:`rvcoax.errors.problems_text`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TypeVar

from pydantic import BaseModel, ConfigDict, ValidationError

from rvcoax.geometry.inputfiles import InputFileError, parse_toml

__all__ = ["LABEL_KEYS", "StrictModel", "key_path", "read_toml_model", "validation_problems"]

LABEL_KEYS = ("name", "label", "address")
"""Keys whose value names an entry of a list of tables in a message (``parts[3] ('input_shaft')``)."""

Schema = TypeVar("Schema", bound=BaseModel)


class StrictModel(BaseModel):
    """Base of every input-file schema: a key the schema does not know is an error; a validated value is frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)


def key_path(location: tuple, data: object = None) -> str:
    """A key as the file writes it, from a pydantic error location: ``bearings[4] ('input_B1').x_mm``.

    Parameters
    ----------
    location : tuple
        The error's ``loc`` (names and list indices), pydantic's own validator steps left out.
    data : object, optional
        The parsed file: an entry of a top-level list of tables is named by its first :data:`LABEL_KEYS` value.

    Returns
    -------
    str
        The key, or ``(top level)`` for the file as a whole.
    """
    text = ""
    for item in location:
        text += f"[{item}]" if isinstance(item, int) else ("." if text else "") + str(item)
    if len(location) >= 2 and isinstance(location[1], int) and isinstance(data, Mapping) \
            and isinstance(data.get(location[0]), list):
        try:
            entry = data[location[0]][location[1]]
            label = next((entry[k] for k in LABEL_KEYS if entry.get(k)), None)
        except (IndexError, AttributeError, TypeError):
            label = None
        if label:
            text = text.replace(f"{location[0]}[{location[1]}]", f"{location[0]}[{location[1]}] ('{label}')", 1)
    return text or "(top level)"


def validation_problems(error: ValidationError, data: object = None, unknown_key: str = "it is not part of the schema",
                        rename: Callable[[tuple, str, object], str] | None = None) -> list[str]:
    """One ``"<key>: <reason>"`` line per problem of a failed validation: the one formatter of input files.

    Parameters
    ----------
    error : pydantic.ValidationError
        What :meth:`pydantic.BaseModel.model_validate` raised.
    data : object, optional
        The parsed file (for the names of list entries, :func:`key_path`).
    unknown_key : str
        What to add to "unknown key (misspelled? …)".
    rename : callable, optional
        ``rename(location, key, data)`` → the key as the user wrote it, where the file's key differs from the schema's
        (a tolerance file's ``mean_um`` is the schema's ``mean``).

    Returns
    -------
    list of str
        The problems, in the schema's order; a check of the whole file that found several gives one line each.
    """
    problems = []
    for entry in error.errors():
        location = tuple(x for x in entry["loc"] if not str(x).startswith("function-"))
        key = key_path(location, data)
        if rename is not None:
            key = rename(location, key, data)
        kind = entry["type"]
        message = entry["msg"].removeprefix("Value error, ")
        if kind == "missing":
            problems.append(f"{key}: required key is missing")
        elif kind == "extra_forbidden":
            problems.append(f"{key}: unknown key (misspelled? {unknown_key})")
        elif kind == "value_error" and not location:
            problems.extend(message.split("\n"))
        else:
            value = entry.get("input")
            shown = f" (got {value!r})" if not isinstance(value, dict | list) and kind != "value_error" else ""
            problems.append(f"{key}: {message}{shown}")
    return problems


def read_toml_model(schema: type[Schema], text: str, fail: Callable[[list[str]], Exception],
                    prepare: Callable[[dict], dict] | None = None, **describe) -> Schema:
    """Parse TOML ``text`` and validate it as ``schema``, or raise ``fail(problems)`` naming every key.

    Parameters
    ----------
    schema : type of pydantic model
        The file's schema (a :class:`StrictModel`).
    text : str
        The file's text (:func:`rvcoax.geometry.inputfiles.read_input_text` read it).
    fail : callable
        Makes the file's error from its problems (the error names the file: ``lambda p: RigFileError(source, p)``).
    prepare : callable, optional
        Turns the parsed document into what the schema validates (a unit-suffixed key into the schema's key);
        it may raise ``fail``'s error itself.
    **describe
        ``unknown_key`` and ``rename`` of :func:`validation_problems`.

    Returns
    -------
    pydantic model
        The validated file.
    """
    try:
        data = parse_toml(text)
    except InputFileError as error:
        raise fail([str(error)]) from None
    try:
        return schema.model_validate(prepare(data) if prepare is not None else data)
    except ValidationError as error:
        raise fail(validation_problems(error, data, **describe)) from None
