"""Named physical parameters of a rig: read and replace a value by a dotted address.

An address is ``<group>.<item name>.<key>``, e.g. ``bearings.input_B1.radial_stiffness_N_per_um``
or ``torque_lateral_loads.sun_gear_load_sharing.imbalance``; a ``Triple`` component is
addressed with an index suffix, ``mounts.reducer_pedestal.translational_stiffness_N_per_um[1]``.
Replacing returns a new, re-validated rig: the original is never changed.
"""

from __future__ import annotations

import re

from geometry.schema import Rig

_ADDRESS = re.compile(r"^(?P<group>\w+)\.(?P<item>[A-Za-z0-9_.\-]+?)\.(?P<key>\w+)(\[(?P<index>\d)\])?$")
GROUPS = ("bearings", "mounts", "couplings", "joints", "torque_lateral_loads")


def _parse(address: str):
    match = _ADDRESS.match(address)
    if not match or match["group"] not in GROUPS:
        raise KeyError(f"parameter address '{address}' is not <group>.<name>.<key> with group in {', '.join(GROUPS)}")
    index = match["index"]
    return match["group"], match["item"], match["key"], None if index is None else int(index)


def get_parameter(rig: Rig, address: str) -> float:
    """Current value of a named parameter."""
    group, item, key, index = _parse(address)
    for entry in getattr(rig, group):
        if entry.name == item:
            if key not in type(entry).model_fields:
                raise KeyError(f"'{group}.{item}' has no key '{key}'")
            value = getattr(entry, key)
            return float(value if index is None else value[index])
    raise KeyError(f"no {group[:-1]} named '{item}'")


def with_parameters(rig: Rig, values: dict[str, float]) -> Rig:
    """A copy of ``rig`` with the given parameters replaced (and validated again)."""
    data = rig.model_dump(by_alias=True)
    for address, value in values.items():
        get_parameter(rig, address)  # raises a clear KeyError for a bad address
        group, item, key, index = _parse(address)
        for entry in data[group]:
            if entry["name"] == item:
                if index is None:
                    entry[key] = float(value)
                else:
                    triple = list(entry[key])
                    triple[index] = float(value)
                    entry[key] = triple
    return Rig.model_validate(data)
