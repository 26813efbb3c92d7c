"""A mechanism of several parts (a shaft line free to turn about the axis) is named before solving, as
``rvcoax modes`` names a zero-frequency mode: its parts, its motion, and the rig key whose zero leaves it free."""

from __future__ import annotations

import numpy as np
import pytest
from rigdata import reference_data

from rvcoax.geometry.model import preflight
from rvcoax.geometry.rigfile import parse_rig
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.sweep import ModelError, run_sweep

INPUT_LINE = ("'motor_shaft'", "'input_sensor_shaft'", "'input_shaft'")


def free_in_torsion() -> dict:
    data = reference_data()
    data["joints"][0]["rotational_stiffness_Nm_per_rad"][0] = 0  # sun_gear_mesh: nothing holds the input line about x
    return data


def test_a_shaft_line_free_in_torsion_is_named_with_the_key_to_fix():
    message = preflight.support_problem(parse_rig(free_in_torsion(), "torsion.toml"))
    assert message is not None and message.startswith("the model is singular: part(s) ")
    assert all(part in message for part in INPUT_LINE)
    assert "torsional motion: rotation about x, the axis" in message
    assert "joints[0] ('sun_gear_mesh').rotational_stiffness_Nm_per_rad[0] = 0" in message
    for held in ("'reducer'", "'output_shaft'", "'brake_shaft'", "'motor_housing'"):
        assert held not in message.split("Bearings")[0]  # the rest of the rig is held, and not named as free
    with pytest.raises(ModelError, match=r"sun_gear_mesh'\)\.rotational_stiffness_Nm_per_rad\[0\]"):
        run_sweep(parse_rig(free_in_torsion(), "torsion.toml"), (LoadCase(1.43, 200.0),))


def test_a_held_rig_with_fine_beam_elements_is_no_mechanism():
    data = reference_data()
    data["mesh"]["max_element_length_mm"] = 1.0  # λ_min of the scaled stiffness falls as the elements shrink
    assert preflight.support_problem(parse_rig(data, "fine.toml")) is None


def test_free_body_names_the_parts_with_the_motion_s_energy_and_its_class():
    kinetic = np.array([0.0, 0.0, 0.0, 6.0, 0.0, 0.0,   0.0, 0.0, 0.0, 3.9, 0.0, 0.0,   0.0, 0.1, 0.0, 0.0, 0.0, 0.0])
    owner = np.repeat(np.array(["a", "b", "c"], dtype=object), 6)
    body = preflight.free_body(kinetic, owner, {"axial": 0.0, "lateral vertical": 0.01, "lateral horizontal": 0.0,
                                                "torsional": 0.99})
    assert body == preflight.FreeBody(("a", "b"), "torsional")  # 'c' holds 1 %, under FREE_BODY_SHARE
    assert preflight.motion_class({"axial": 0.5, "lateral vertical": 0.3, "lateral horizontal": 0.2,
                                   "torsional": 0.0}) == "mixed (axial 50 %, lateral vertical 30 %)"
