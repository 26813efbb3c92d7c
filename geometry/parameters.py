"""Named physical parameters of a rig: read and replace a value by a dotted address.

An address is ``<group>.<item name>.<key>``, e.g. ``bearings.input_B1.radial_stiffness_N_per_um``
or ``torque_lateral_loads.sun_gear_load_sharing.imbalance``; a ``Triple`` component is
addressed with an index suffix, ``mounts.reducer_pedestal.translational_stiffness_N_per_um[1]``.
A top-level table's key is ``<table>.<key>``: ``gravity.acceleration_m_per_s2``, ``gravity.enabled``,
``force_table.scale``, ``force_table.apply``, ``beam.shear_deformation``. A temperature rise is
``thermal.temperature_rise_K.<part>`` (or ``thermal.support_temperature_rise_K.<mount>``): 0 when not
set, and setting it creates the entry. Keys are the rig file's
(``torque_lateral_loads.<name>.force_per_torque_N_per_Nm``); a true/false key reads as 1.0/0.0 and
is set from a number (non-zero is true). Replacing returns a new, re-validated rig: the original is
never changed.
"""

from __future__ import annotations

import re

from rvcoax.geometry.schema import Rig

__all__ = ["GROUPS", "TABLES", "get_parameter", "with_parameters"]

_ADDRESS = re.compile(r"^(?P<group>\w+)\.(?P<item>[A-Za-z0-9_.\-]+?)\.(?P<key>\w+)(\[(?P<index>\d)\])?$")
_TABLE_ADDRESS = re.compile(r"^(?P<group>\w+)\.(?P<key>\w+)$")
GROUPS = ("bearings", "mounts", "couplings", "joints", "torque_lateral_loads", "gear_meshes", "housings")
TABLES = ("gravity", "force_table", "beam")
DICT_KEYS = {"thermal": ("temperature_rise_K", "support_temperature_rise_K")}  # table → keys holding {name: value}


def _dict_address(address: str):
    """(table, key, name) of ``thermal.temperature_rise_K.<part>``-like addresses, else None."""
    match = _ADDRESS.match(address)
    if match and match["index"] is None and match["item"] in DICT_KEYS.get(match["group"], ()):
        return match["group"], match["item"], match["key"]
    return None


def _parse(address: str):
    """(group, item name or None for a table, key as in the file, index or None)."""
    table = _TABLE_ADDRESS.match(address)
    if table and table["group"] in TABLES:
        return table["group"], None, table["key"], None
    match = _ADDRESS.match(address)
    if not match or match["group"] not in GROUPS:
        raise KeyError(f"parameter address '{address}' is not <group>.<name>.<key> with group in {', '.join(GROUPS)}, "
                       f"nor <table>.<key> with table in {', '.join(TABLES)}")
    index = match["index"]
    return match["group"], match["item"], match["key"], None if index is None else int(index)


def _field_name(entry, key: str) -> str | None:
    """The attribute behind file key ``key`` (a field's alias or its name)."""
    for name, info in type(entry).model_fields.items():
        if key in (info.alias, name) and (info.alias is None or key == info.alias):
            return name
    return None


def _entry(rig: Rig, group: str, item: str | None):
    if item is None:
        return getattr(rig, group)
    for entry in getattr(rig, group):
        if entry.name == item:
            return entry
    raise KeyError(f"no {group[:-1]} named '{item}'")


def get_parameter(rig: Rig, address: str) -> float:
    """Current value of a named parameter."""
    keyed = _dict_address(address)
    if keyed is not None:
        table = getattr(rig, keyed[0])
        return float(getattr(table, keyed[1]).get(keyed[2], 0.0)) if table is not None else 0.0
    group, item, key, index = _parse(address)
    entry = _entry(rig, group, item)
    name = _field_name(entry, key)
    if name is None:
        raise KeyError(f"'{group if item is None else f'{group}.{item}'}' has no key '{key}'")
    value = getattr(entry, name)
    if index is not None:
        if not isinstance(value, (list, tuple)):
            raise KeyError(f"'{address}': the key holds one value, not a list to index")
        if index >= len(value):
            raise KeyError(f"'{address}': index {index} is beyond the {len(value)} values of the key (0 … {len(value) - 1})")
        value = value[index]
    if value is None:
        raise KeyError(f"'{address}' is not set in this rig")
    if isinstance(value, (list, tuple)) and index is None:
        raise KeyError(f"'{address}' holds {len(value)} values: name one with an index, e.g. {address}[0]")
    if not isinstance(value, (int, float)):
        raise KeyError(f"'{address}' is not a number (it holds {value!r}): only numeric keys can be varied")
    return float(value)


def with_parameters(rig: Rig, values: dict[str, float]) -> Rig:
    """A copy of ``rig`` with the given parameters replaced (and validated again)."""
    data = rig.model_dump(by_alias=True)
    for address, value in values.items():
        keyed = _dict_address(address)
        if keyed is not None:
            table = data[keyed[0]] if data.get(keyed[0]) is not None else {}
            table[keyed[1]] = {**table.get(keyed[1], {}), keyed[2]: float(value)}
            data[keyed[0]] = table
            continue
        group, item, key, index = _parse(address)
        entry = _entry(rig, group, item)
        if _field_name(entry, key) is None:
            get_parameter(rig, address)  # raises a clear KeyError for a bad address
        target = data[group] if item is None else next(e for e in data[group] if e["name"] == item)
        if isinstance(target.get(key), bool):
            target[key] = bool(value)
        elif index is None:
            target[key] = float(value)
        else:
            triple = list(target[key])
            triple[index] = float(value)
            target[key] = triple
    return Rig.model_validate(data)
