"""The rig's modal study (rvcoax.modes / `rvcoax modes`): energy and mass bookkeeping, operating-point stiffness of
nonlinear bearings, the interference crossings, and clear errors for bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from rigdata import dump_toml, reference_data
from typer.testing import CliRunner

import rvcoax
from rvcoax.geometry.rigfile import load_rig, parse_rig_text
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.cli.app import app
from rvcoax.results.studies.modes import ModesError, ModeSettings, run_modes

DATA = Path(__file__).resolve().parents[2] / "geometry" / "data"


@pytest.fixture(scope="module")
def study():
    return rvcoax.modes(n_modes=20)


def test_reference_rig_modes_are_consistent(study):
    case = study.cases[0]
    f = np.array([m.frequency_hz for m in case.modes])
    assert np.all(np.diff(f) >= 0) and f[0] > 1.0
    phi = case.shapes
    k, mass = study.system.stiffness, study.mass
    assert np.allclose(phi.T @ mass @ phi, np.eye(20), atol=1e-8)
    assert np.allclose(np.diag(phi.T @ k @ phi), (2 * np.pi * f) ** 2, rtol=1e-8)
    for mode in case.modes:
        assert sum(mode.direction_share.values()) == pytest.approx(1.0, abs=1e-9)
        assert sum(mode.energy_share.values()) == pytest.approx(1.0, abs=1e-3)  # shares below 1e-4 are not listed
    # the lowest mode: the input line twisting on the sun gear's torsional spring (8.45 N·m/rad)
    assert case.modes[0].kind == "torsional" and case.modes[0].owner == "joint:sun_gear_mesh"
    # lateral modes come in vertical/horizontal pairs (the rig is axisymmetric but for gravity, which is a load)
    lateral = [m for m in case.modes if m.kind.startswith("lateral")]
    assert len(lateral) >= 8
    # the strain energies add up to ω²/2 for each mode (checked inside: shares are of the summed energy)
    assert study.part_mass_kg["brake_housing"] == pytest.approx(46.0, rel=1e-12)


def test_effective_masses_add_up_to_the_rig_mass(study):
    """With every mode (dense), Σ Γ² along y is the moving mass along y, rᵀ M r; the study's Γ² are the first ones."""
    from rvcoax.fem.modal import natural_modes

    system, mass = study.system, study.mass
    t = system.elimination
    n_mass = int(np.count_nonzero((t.T @ mass @ t).diagonal() > 0))
    every = natural_modes(system.stiffness, mass, t, n_mass)
    r = (system.dofs.component == 1).astype(float)
    r[np.asarray(t.sum(axis=1)).ravel() == 0] = 0.0  # held DOFs (the housings' bed side) do not move
    gamma = every.shapes.T @ (mass @ r)
    assert np.sum(gamma**2) == pytest.approx(float(r @ (mass @ r)), rel=1e-6)
    # the study's Γ² per group of equal frequencies (a y/z pair may turn within its plane: only the sum is fixed)
    modes = study.cases[0].modes
    f = np.array([m.frequency_hz for m in modes])
    groups = np.cumsum(np.r_[True, np.diff(f) > 1e-6 * f[1:]]) - 1
    last = groups[-1]
    every_f = every.frequencies_hz[:40]
    for g in range(last):  # the last group may be cut by the 20th mode
        members = groups == g
        mine = sum(m.effective_mass["y_kg"] for m, keep in zip(modes, members) if keep)
        same = np.abs(every_f - f[members][0]) <= 1e-6 * f[members][0]
        assert mine == pytest.approx(np.sum(gamma[:40][same] ** 2), rel=1e-5, abs=1e-9 * float(r @ (mass @ r)))


def test_ball_bearings_use_their_operating_tangent_stiffness():
    """Ball bearings stiffen with load: each case's lateral modes rise with the torque."""
    rig = load_rig(DATA / "reference_rig_ball_bearings.toml")
    cases = (LoadCase(0.07, 10.0), LoadCase(1.43, 200.0))
    result = run_modes(rig, cases, ModeSettings(n_modes=12))
    assert [c.label for c in result.cases] == [c.label for c in cases]
    low, high = (np.array([m.frequency_hz for m in c.modes]) for c in result.cases)
    assert not np.allclose(low, high, rtol=1e-6)
    owners = {m.owner for c in result.cases for m in c.modes}
    assert any(o.startswith("bearing:") for o in owners) or owners


def test_interference_crossings(study):
    rig = study.rig
    assert rig.speeds is not None
    for crossing in study.crossings:
        order = dict(study.orders)[crossing.order]
        assert crossing.crossing_rpm == pytest.approx(60 * crossing.frequency_hz / order)
        assert crossing.inside == (rig.speeds.motor_rpm[0] <= crossing.crossing_rpm <= rig.speeds.motor_rpm[1])
    torsion = study.cases[0].modes[0].frequency_hz
    once = [c for c in study.crossings if c.mode == 1 and c.order == "motor ×1"]
    assert once and once[0].crossing_rpm == pytest.approx(60 * torsion)
    assert study.gyroscopic_ratio_max < 0.02


def test_rv40e_example_runs():
    result = rvcoax.modes(rvcoax.load_example_rig(), n_modes=10)
    assert len(result.cases[0].modes) == 10 and result.crossings


def test_too_many_modes_is_a_clear_error():
    with pytest.raises(ModesError, match="degrees of freedom with mass"):
        rvcoax.modes(n_modes=100000)


def _rig_text(change) -> str:
    data = reference_data()
    change(data)
    return dump_toml(data)


def test_speed_range_without_speeds_is_refused():
    with pytest.raises(ValueError, match="speeds.motor_rpm"):
        parse_rig_text(_rig_text(lambda d: d["speeds"].pop("motor_rpm")))
    with pytest.raises(ValueError, match="no speed range"):
        parse_rig_text(_rig_text(lambda d: d["speeds"].update(motor_rpm=[3000, 3000])))


def test_cli_errors_without_traceback(tmp_path):
    free = tmp_path / "free.toml"

    def loose(data):  # the sun gear holds the whole input line in torsion: without it that line spins freely
        for joint in data["joints"]:
            if joint["name"] == "sun_gear_mesh":
                joint["rotational_stiffness_Nm_per_rad"] = [0, 0, 0]

    free.write_text(_rig_text(loose), encoding="utf-8")
    result = CliRunner().invoke(app, ["modes", "--rig", str(free), "--out", str(tmp_path / "a"), "--pictures", "0"])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "input_shaft" in result.output or "motor_shaft" in result.output
    nospeeds = tmp_path / "nospeeds.toml"
    nospeeds.write_text(_rig_text(lambda d: d.pop("speeds")), encoding="utf-8")
    result = CliRunner().invoke(app, ["modes", "--rig", str(nospeeds), "--interference", "--out", str(tmp_path / "b")])
    assert result.exit_code == 2 and "[speeds]" in result.output
    result = CliRunner().invoke(app, ["modes", "--modes", "99999", "--out", str(tmp_path / "c"), "--pictures", "0"])
    assert result.exit_code == 2 and "degrees of" in result.output and "ask for at most" in result.output


@pytest.mark.render
def test_cli_writes_the_table_diagram_and_pictures(tmp_path):
    result = CliRunner().invoke(app, ["modes", "--modes", "8", "--pictures", "2", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    for name in ("modes.csv", "modes.json", "modes_crossings.csv", "modes_interference.png", "modes/mode_01.png",
                 "modes/mode_02.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    header = (tmp_path / "modes.csv").read_text().splitlines()[0]
    assert "frequency_Hz" in header and "effective_mass_y_kg" in header


@pytest.mark.slow  # about 8 s CPU: a 27 k-DOF hybrid model (30 mm mesh) and its 20 modes
def test_hybrid_lateral_modes_agree_with_the_beam_model():
    """The lowest lateral modes of the hybrid rig against the beam model's (docs/modes.md, "Beam and hybrid").

    Each beam mode is matched to the hybrid mode of its class nearest in frequency. Where a mount or housing owns
    the mode, the shafts move as rigid bodies on it and both models carry the same springs: within 0.05 % (measured
    ≤ 0.02 % at this mesh, ≤ 0.03 % at the default one). Where a shaft or its bearings own it the solid shafts
    bend with 3D shear and their band ties spread the bearing over its width: the hybrid is softer, up to 0.5 %
    lower (measured 0.16 % at output_B2 here, 0.36 % at the default mesh), never stiffer beyond rounding."""
    rig = rvcoax.load_rig()
    beam = run_modes(rig, settings=ModeSettings(n_modes=20, model="beam")).cases[0].modes
    hybrid = run_modes(rig, settings=ModeSettings(n_modes=20, model="hybrid", mesh_size_mm=30.0)).cases[0].modes
    lateral = [m for m in beam if m.kind.startswith("lateral")]
    assert len(lateral) >= 10
    shaft_owned = 0
    for mode in lateral:
        twin = min((h for h in hybrid if h.kind == mode.kind), key=lambda h: abs(h.frequency_hz - mode.frequency_hz))
        change = twin.frequency_hz / mode.frequency_hz - 1.0
        if mode.owner.startswith(("mount:", "housing:")):
            assert abs(change) < 5e-4, (mode.number, mode.owner, change)
        else:
            shaft_owned += 1
            assert -5e-3 < change < 5e-4, (mode.number, mode.owner, change)
    assert shaft_owned >= 2  # the band covers both kinds


@pytest.mark.slow  # the housing's Craig–Bampton reduction (a 20 mm block mesh) and three beam-model solves
def test_housing_mass_guyan_or_craig_bampton():
    """The reference rig with its input bearing block from geometry (self_weight): for the lowest 20 modes (top
    923 Hz) the block's lowest fixed-interface mode (10.4 kHz) is far above 3 × the band, so ``auto`` keeps Guyan.
    Asked for over 60 modes, Craig–Bampton (a Ritz refinement) lowers no frequency below what it was by more than
    1e-6 in the lowest 20 and lowers the modes the block owns (near 2 kHz) by a fraction of a percent: its own
    inertia."""
    from rvcoax.geometry.rigfile import parse_rig

    data = reference_data()
    data["mounts"] = [m for m in data["mounts"] if m["name"] != "input_block_base"]
    data["housings"] = [{  # the reference rig's input bearing block from geometry (docs/rig-file.md)
        "name": "input_block", "part": "input_bearing_block", "material": "HT200", "x_mm": [248.0, 320.0],
        "width_mm": 90.0, "height_above_bed_mm": 100.0, "top_above_axis_mm": 45.0, "bore_diameter_mm": 47.0,
        "foot_thickness_mm": 15.0, "foot_width_mm": 150.0, "attachments_x_mm": [255.0, 315.0],
        "attachment_width_mm": 14.0, "mesh_size_mm": 20.0, "self_weight": True}]
    rig = parse_rig(data, "test")
    auto = rvcoax.modes(rig, n_modes=20)
    assert any("Guyan" in n and "fixed-interface mode, 10" in n for n in auto.notes)
    guyan = rvcoax.modes(rig, n_modes=60, housing_dynamics="guyan").cases[0].modes
    asked = rvcoax.modes(rig, n_modes=60, housing_dynamics="craig-bampton")
    assert any("Craig–Bampton with 2" in n for n in asked.notes)
    cb = asked.cases[0].modes
    low, refined = (np.array([m.frequency_hz for m in s]) for s in (guyan, cb))
    assert np.all(refined <= low * (1 + 1e-12))
    assert refined[:20] == pytest.approx(low[:20], rel=1e-6)
    owned = [(g, c) for g, c in zip(guyan, cb) if g.owner == "housing:input_block"]
    assert owned
    for g, c in owned:
        assert c.owner == "housing:input_block" and 0.98 * g.frequency_hz < c.frequency_hz < g.frequency_hz
