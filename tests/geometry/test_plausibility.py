"""The catalogue of plausible ranges (geometry/catalogue.py): silent on the reference rig, and the
issue's cases (a stiffness in N/m in an ``_N_per_um`` key, a torque on a housing, a swapped bearing,
a load reacted on its own part) each named with the key and the range."""

from __future__ import annotations

import pytest
from rigdata import reference_data

from rvcoax.geometry.catalogue import CATALOGUE, plausibility_warnings, plausible_range
from rvcoax.geometry.rigfile import load_rig, parse_rig


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
    (lambda d: (d["torques"]["T1"].update(part="motor_housing"), d["torques"]["T1"].pop("reacted_on")),
     "torques.T1.part = 'motor_housing' is a housing"),
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


def test_palmgren_ball_bearing_stiffness_by_hand():
    """6204 (8 balls of 7.938 mm) at 1000 N: Q_max = 4.37·1000/8 = 546.25 N, δ = 4.36e-4·546.25^(2/3)/7.938^(1/3)
    = 0.014606 mm, k = 1.5 F/δ = 102.7 N/µm; and k grows as F^(1/3)."""
    from rvcoax.geometry.catalogue import ball_bearing_radial_stiffness_N_per_um as stiffness

    assert stiffness(8, 7.938, 1000.0) == pytest.approx(102.70, rel=1e-4)
    assert stiffness(8, 7.938, 8000.0) / stiffness(8, 7.938, 1000.0) == pytest.approx(2.0, rel=1e-12)


@pytest.mark.parametrize(("bore_mm", "balls", "ball_mm", "rating_N"), [
    (8, 7, 3.969, 3450), (20, 8, 7.938, 13500), (30, 9, 9.525, 20300), (50, 10, 12.7, 35100)])
def test_the_bore_band_holds_deep_groove_ball_bearings_from_light_to_heavy_load(bore_mm, balls, ball_mm, rating_N):
    """608, 6204, 6206, 6210 (catalogue ball sets and dynamic ratings) from 1 % to 50 % of C: inside
    0.5·d … 100·d N/µm with a factor ≥ 3 to spare on both sides."""
    from rvcoax.geometry.catalogue import RADIAL_STIFFNESS_PER_BORE
    from rvcoax.geometry.catalogue import ball_bearing_radial_stiffness_N_per_um as stiffness

    low, high = RADIAL_STIFFNESS_PER_BORE
    light, heavy = stiffness(balls, ball_mm, 0.01 * rating_N), stiffness(balls, ball_mm, 0.5 * rating_N)
    assert 3 * low * bore_mm < light < heavy < high * bore_mm / 3


def test_a_bearing_stiffness_implausible_for_its_bore_is_named():
    data = reference_data()
    data["bearings"][4]["radial_stiffness_N_per_um"] = 3000  # input_B1, a 6204 on the Ø20 journal
    data["bearings"][0]["radial_stiffness_N_per_um"] = 5  # motor_front on the Ø19 motor shaft
    found = warnings_of(data)
    assert found == [
        "bearings[0] ('motor_front').radial_stiffness_N_per_um = 5 N/µm is outside the plausible range of a rolling "
        "bearing of 19 mm bore (the shaft's Ø at x = -5 mm) (9.5 … 1900 N/µm)",
        "bearings[4] ('input_B1').radial_stiffness_N_per_um = 3000 N/µm is outside the plausible range of a rolling "
        "bearing of 20 mm bore (the shaft's Ø at x = 255 mm) (10 … 2000 N/µm)",
    ]


@pytest.mark.parametrize(("table", "index", "key", "value", "words"), [
    ("couplings", 0, "mass_kg", 245.0, "couplings[0] ('C1').mass_kg = 245 kg is outside the plausible range of a "
                                       "coupling (0.005 … 100 kg): written in g?"),
    ("couplings", 2, "hub_length_mm", 0.045, "hub_length_mm = 0.045 mm is outside the plausible range of a coupling "
                                             "(2 … 500 mm): written in m?"),
    ("bearings", 4, "width_mm", 0.014, "width_mm = 0.014 mm is outside the plausible range of a bearing "
                                       "(2 … 500 mm): written in m?"),
])
def test_masses_and_dimensions_in_another_unit_are_named(table, index, key, value, words):
    data = reference_data()
    data[table][index][key] = value
    (message,) = warnings_of(data)
    assert words in message


@pytest.mark.parametrize(("edit", "words"), [
    (lambda d: d["parts"][1]["segments"][0].update(outer_diameter_mm=0.019),
     "parts[1] ('motor_shaft').segments[0].outer_diameter_mm = 0.019 mm is outside the plausible range of a rig "
     "part's diameter (1 … 3000 mm): written in m?"),
    (lambda d: d["torque_lateral_loads"][0].update(mesh_stiffness_N_per_um=1.4e8),
     "torque_lateral_loads[0] ('sun_gear_load_sharing').mesh_stiffness_N_per_um = 1.4e+08 N/µm is outside the "
     "plausible range of a torque lateral load (10 … 10000 N/µm): written in N/m?"),
    (lambda d: d["torque_lateral_loads"][1].update(radius_mm=0.035), "radius_mm = 0.035 mm is outside"),
])
def test_diameters_and_lateral_load_keys_in_another_unit_are_named(edit, words):
    data = reference_data()
    edit(data)
    (message,) = warnings_of(data)
    assert words in message
