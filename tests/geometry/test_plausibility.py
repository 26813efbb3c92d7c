"""The catalogue of plausible ranges (geometry/catalogue.py): silent on the reference rig, and the
issue's cases (a stiffness in N/m in an ``_N_per_um`` key, a torque on a housing, a swapped bearing,
a load reacted on its own part) each named with the key and the range."""

from __future__ import annotations

import pytest

from rvcoax.geometry.catalogue import CATALOGUE, plausibility_warnings, plausible_range
from rvcoax.geometry.rigfile import load_rig, parse_rig
from tests.geometry.test_rigfile_errors import reference_data


def warnings_of(data: dict) -> list[str]:
    return plausibility_warnings(parse_rig(data, "edited.toml"))


def test_the_reference_rig_is_plausible():
    assert plausibility_warnings(load_rig(None)) == []


def test_every_reference_value_lies_inside_its_range_with_room():
    """The ranges are wide: every reference stiffness may change by 3x either way without a warning."""
    rig = load_rig(None)
    for factor in (1 / 3, 3.0):
        data = reference_data()
        for bearing in data["bearings"]:
            bearing["radial_stiffness_N_per_um"] *= factor
        for coupling in data["couplings"]:
            for key in ("radial_stiffness_N_per_mm", "angular_stiffness_Nm_per_rad", "torsional_stiffness_Nm_per_rad"):
                coupling[key] *= factor
        assert warnings_of(data) == [], factor
    assert len(rig.bearings) == 12 and len({(r.kind, r.key) for r in CATALOGUE}) == len(CATALOGUE)


def test_a_bearing_stiffness_in_n_per_m_is_named_with_key_range_and_slip():
    data = reference_data()
    data["bearings"][4]["radial_stiffness_N_per_um"] = 8e7  # the case: 50 N/µm typed as 8e7 N/m
    (message,) = warnings_of(data)
    assert message == ("bearings[4] ('input_B1').radial_stiffness_N_per_um = 8e+07 N/µm is outside the plausible "
                       "range of a bearing (1 … 5000 N/µm): written in N/m?")


@pytest.mark.parametrize(("edit", "words"), [
    (lambda d: d["torques"]["T1"].update(part="motor_housing"), "torques.T1.part = 'motor_housing' is a housing"),
    (lambda d: d["bearings"][4].update(shaft="input_bearing_block", housing="input_shaft"), "swapped?"),
    (lambda d: d["torque_lateral_loads"][1]["reacted_on"].update(part="output_shaft", x_mm=420),
     "on.part and reacted_on.part are both 'output_shaft'"),
])
def test_suspicious_topology_is_named(edit, words):
    data = reference_data()
    edit(data)
    found = warnings_of(data)
    assert len(found) == 1 and words in found[0], found


def test_zero_stiffness_means_a_free_direction_and_is_not_warned_about():
    assert plausible_range("bearing", "axial_stiffness_N_per_um").zero_allowed
    assert not plausible_range("bearing", "radial_stiffness_N_per_um").zero_allowed
    data = reference_data()
    data["mounts"][0]["rotational_stiffness_Nm_per_rad"] = [5e5, 0.0, 2e5]
    assert warnings_of(data) == []
