"""Write a changed rig back into its own TOML text, keeping the user's layout and comments.

The original text is parsed with tomlkit (style preserving); every value that differs between the
original rig and the changed one is replaced in place, new array entries are appended, and each
change carries a comment saying where it came from. The result is read back and must validate to
exactly the changed rig.
"""

from __future__ import annotations

import tomllib

import tomlkit

from rvcoax.geometry.rigfile import parse_rig
from rvcoax.geometry.schema import Rig

__all__ = ["updated_rig_text"]


def _plain(value):
    """Rig dump value → TOML value (tuples as arrays)."""
    if isinstance(value, tuple | list):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if v is not None}
    return value


def _table_of(entry: dict):
    table = tomlkit.table()
    for key, value in entry.items():
        if value is None:
            continue
        if isinstance(value, dict):
            inline = tomlkit.inline_table()
            inline.update(_plain(value))
            table[key] = inline
        else:
            table[key] = _plain(value)
    return table


def _update(node, old: dict, new: dict, note: str, path: str, *, changed: list[str]) -> None:  # noqa: PLR0913
    for key, value in new.items():
        before = old.get(key)
        if before == value:
            continue
        where = f"{path}.{key}" if path else key
        if isinstance(value, dict) and isinstance(before, dict) and key in node:
            _update(node[key], before, value, note, where, changed=changed)
        elif (isinstance(value, list) and value and all(isinstance(v, dict) for v in value)
              and isinstance(before, list) and key in node):
            for i, entry in enumerate(value):
                if i < len(before):
                    _update(node[key][i], before[i], entry, note, f"{where}[{i}]", changed=changed)
                else:
                    table = _table_of(entry)
                    table.comment(note)
                    node[key].append(table)
                    changed.append(f"{where}[{i}] (new)")
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            array = tomlkit.aot()
            for entry in value:
                table = _table_of(entry)
                table.comment(note)
                array.append(table)
            node[key] = array
            changed.append(f"{where} (new)")
        elif value is None:
            if key in node:
                del node[key]
                changed.append(f"{where} (removed)")
        else:
            previous = node.get(key)
            previous_comment = previous.trivia.comment.lstrip("# ").strip() if hasattr(previous, "trivia") else ""
            node[key] = _plain(value)
            # an inline table ({ a = 1, b = 2 }: a temperature per part) cannot hold comments
            if hasattr(node[key], "comment") and not isinstance(node, tomlkit.items.InlineTable):
                was = f"; was {_plain(before)}" if before is not None else ""
                node[key].comment(note + was + (f" ({previous_comment})" if previous_comment else ""))
            changed.append(where)


def updated_rig_text(original_text: str, new_rig: Rig, note: str, header: list[str] = ()) -> tuple[str, list[str]]:
    """The original rig text with every difference to ``new_rig`` written in, and the changed keys.

    Parameters
    ----------
    original_text : str
        The rig file the changes start from.
    new_rig : Rig
        The changed rig.
    note : str
        A comment attached to every changed value (its provenance).
    header : list of str
        Comment lines put at the top of the file.

    Returns
    -------
    (str, list of str)
        The updated TOML text (comments and layout of ``original_text`` kept), and the changed keys.
    """
    old_rig = parse_rig(tomllib.loads(original_text), "original rig")
    document = tomlkit.parse(original_text)
    changed: list[str] = []
    _update(document, old_rig.model_dump(by_alias=True, mode="json"), new_rig.model_dump(by_alias=True, mode="json"),
            note, "", changed=changed)
    text = "".join(f"# {line}\n" for line in header) + tomlkit.dumps(document)
    written = parse_rig(tomllib.loads(text), "updated rig")
    if written.model_dump() != new_rig.model_dump():
        raise RuntimeError("the updated rig file does not read back as the changed rig")
    return text, changed
