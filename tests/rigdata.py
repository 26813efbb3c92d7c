"""The reference rig as mutable TOML data, and a small TOML writer to save an edited copy.

Shared by the tests that make bad or changed rig files (rig-file errors, plausibility, effects,
reliability, the bad-input corpus of the command line).
"""

from __future__ import annotations

import json
import math
import re
import tomllib

from rvcoax.geometry.rigfile import reference_rig_text

__all__ = ["assert_input_b1_refused", "dump_toml", "reference_data", "with_bearing_keys"]


def reference_data() -> dict:
    """A fresh, mutable copy of the reference rig as parsed TOML."""
    return tomllib.loads(reference_rig_text())


def with_bearing_keys(variant: str, header: str, keys: str) -> str:
    """The text of the reference rig's ``variant`` with the keys after ``header`` (a bearing entry's first lines,
    name to x_mm) up to the next ``[[bearings]]`` replaced by ``keys``."""
    text = reference_rig_text(variant)
    start = text.index(header) + len(header)
    end = text.index("[[bearings]]", start)
    return text[:start] + keys + "\n" + text[end:]


def assert_input_b1_refused(text_of, cases: dict[str, str]) -> None:
    """Each rig text ``text_of(keys)`` of ``cases`` (keys → reason) is refused naming the file, the bearing
    ``bearings[4] ('input_B1')`` and the reason."""
    import pytest

    from rvcoax.geometry.rigfile import RigFileError, parse_rig_text

    for keys, reason in cases.items():
        with pytest.raises(RigFileError) as error:
            parse_rig_text(text_of(keys), "rig.toml")
        message = str(error.value)
        assert "rig.toml" in message and "bearings[4] ('input_B1')" in message and reason in message, message


def _toml_key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # JSON escapes are valid TOML basic-string escapes
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"cannot write {value!r} as TOML")


def _is_table_array(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def dump_toml(data: dict) -> str:
    """Write a parsed rig back as TOML (tables, arrays of tables, inline tables below that)."""
    lines = [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in data.items()
             if not isinstance(v, dict) and not _is_table_array(v)]
    for key, value in data.items():
        if isinstance(value, dict):
            lines.append(f"[{_toml_key(key)}]")
            lines += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items()]
        elif _is_table_array(value):
            for item in value:
                lines.append(f"[[{_toml_key(key)}]]")
                lines += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in item.items()]
    return "\n".join(lines) + "\n"
