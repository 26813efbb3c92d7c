"""Angular-contact, cylindrical and tapered roller bearings from geometry in a rig: the catalogue, the
rig-file keys and their errors, the reference-rig variant and its nonlinear sweep."""

from __future__ import annotations

import math

import numpy as np
import pytest
from rigdata import assert_input_b1_refused, with_bearing_keys

from rvcoax.fem.ball_bearing import BallBearingGeometry
from rvcoax.fem.rolling_bearing import rolling_element_loads
from rvcoax.geometry.rigfile import parse_rig_text, reference_rig_text
from rvcoax.geometry.rolling_catalogue import (
    BALL_FC,
    ROLLER_FC,
    ROLLING_BEARINGS,
    _fc,
    ball_dynamic_rating_N,
    ball_static_rating_N,
    nearest_designations,
)
from rvcoax.geometry.rolling_model import PRELOAD_CLASS_SHARE, rolling_bearing_of
from rvcoax.loadcases.cases import LoadCase
from rvcoax.results.io.records import model_section
from rvcoax.results.sweep import ModelError, SweepSettings, run_sweep

NAMES = ("input_B1", "input_B2", "output_B1", "output_B2")
CASES = (LoadCase(1.43, 200.0), LoadCase(0.07, 10.0))
INPUT_B1 = "x_mm = 255                          # rig_reference part 5\n"  # input_B1's last common line


def _variant():
    return parse_rig_text(reference_rig_text("rolling_bearings"), "variant")


def _with_input_b1(keys: str):
    """The variant with input_B1's model keys replaced by ``keys``."""
    return with_bearing_keys("rolling_bearings", INPUT_B1, keys)


def test_catalogue_entries_build_and_are_plausible():
    kinds = {e.kind for e in ROLLING_BEARINGS.values()}
    assert kinds == {"angular_contact", "cylindrical_roller", "tapered_roller"}
    assert {"7000C", "7210AC", "7306B", "NU204", "N310", "NJ206", "30204", "32010X", "32210"} <= set(ROLLING_BEARINGS)
    for name, entry in ROLLING_BEARINGS.items():
        assert entry.bore_mm < entry.pitch_diameter_mm < entry.outside_diameter_mm, name
        assert entry.element_count * entry.element_diameter_mm < math.pi * entry.pitch_diameter_mm, name
        assert 0 < entry.static_rating_N and 0 < entry.dynamic_rating_N < 2e5, name
        assert all(tag for tag in entry.sources.values()), name  # every number says where it comes from
        assert "ESTIMATED" in entry.sources["element_diameter_mm"] and "COMPUTED" in entry.sources["static_rating_N"]
    # larger series, larger ratings; a B (40°) bearing carries less radially than its 15° C sibling
    assert ROLLING_BEARINGS["7306B"].dynamic_rating_N > ROLLING_BEARINGS["7206B"].dynamic_rating_N
    assert ROLLING_BEARINGS["7206B"].dynamic_rating_N < ROLLING_BEARINGS["7206C"].dynamic_rating_N
    assert ROLLING_BEARINGS["NU206"].dynamic_rating_N > ROLLING_BEARINGS["7206C"].dynamic_rating_N  # line contact


def test_load_ratings_from_geometry_against_a_published_catalogue_bearing():
    # the 6204 (the ball bearing catalogue's geometry: Z = 8, D_w = 7.938 mm, d_m = 33.5 mm, f_i 0.52, f_o 0.53):
    # SKF's rolling bearings catalogue gives C = 13.5 kN, C0 = 6.55 kN (quoted as remembered: the catalogue page was
    # not at hand this session; the tolerances are wider than the doubt). ISO 281's C (b_m = 1.3) is a few per cent below SKF's (their
    # own, higher factors); C0 by ISO 76's definition (4 200 MPa at Q_max = 5 F_r / Z) on this model's Hertz contact
    geometry = BallBearingGeometry(8, 7.938e-3, 33.5e-3, 0.52, 0.53)
    assert ball_static_rating_N(geometry) == pytest.approx(6550.0, rel=0.05)
    assert ball_dynamic_rating_N(8, 7.938, 33.5, 0.0) == pytest.approx(13500.0, rel=0.10)
    # ISO 281's f_c of radial ball bearings peaks at γ = 0.18–0.20 (59.9); C ∝ Z^(2/3) at a fixed ball
    assert _fc(BALL_FC, 0.19) == pytest.approx(59.9) and _fc(ROLLER_FC, 0.05) == pytest.approx(74.1)
    assert ball_dynamic_rating_N(16, 7.938, 67.0, 0.0) == pytest.approx(
        ball_dynamic_rating_N(8, 7.938, 33.5, 0.0) * 2 ** (2 / 3) * _fc(BALL_FC, 7.938 / 67) / _fc(BALL_FC, 7.938 / 33.5))


def test_the_estimated_7206_b_against_a_makers_published_data():
    # a maker's data for a 40° single-row angular-contact bearing 30 × 62 × 16 mm (7206 B; as reproduced at
    # www.fgfa.com.cn/en/Angular_contact_ball_bearings/1164.html): pressure point a = 27.3 mm from the side face,
    # C = 22.5 kN, C0 = 14.3 kN. The load centre is not an input of the model: it is where a radial force on the
    # inner ring causes no tilt, x = K_yθz / K_yy from the 5-DOF stiffness (here lightly preloaded)
    entry = ROLLING_BEARINGS["7206B"]
    row = rolling_bearing_of(parse_rig_text(_with_input_b1(
        'model = "angular_contact"\ndesignation = "7206B"\naxial_offset_um = 1'), "x").bearings[4])
    stiffness = row.force(np.zeros(5))[1]
    centre = stiffness[1, 4] / stiffness[1, 1]  # m; < 0: the thrust row's pressure point lies behind it
    assert -centre * 1e3 + entry.width_mm / 2 == pytest.approx(27.3, rel=0.02)
    # the estimated ball set rates 10–20 % below the maker's (tagged ESTIMATED)
    assert 0.8 < entry.dynamic_rating_N / 22500.0 < 1.0 and 0.8 < entry.static_rating_N / 14300.0 < 1.0


def test_tapered_dimensions_and_estimated_ratings_against_a_makers_table():
    # a maker's metric tapered roller bearing table, bore 15–35 mm (as reproduced at zanotowane.pl/1106/3332): d, D,
    # T, cup width C (mm) and, for three of them, C_r and C_0r (N)
    published = {"32004X": (20, 42, 15, 12), "30204": (20, 47, 15.25, 12), "32204": (20, 47, 19.25, 15),
                 "32005X": (25, 47, 15, 11.5), "30205": (25, 52, 16.25, 13), "32205": (25, 52, 19.25, 15),
                 "32006X": (30, 55, 17, 13), "30206": (30, 62, 17.25, 14), "32206": (30, 62, 21.25, 17)}
    import csv
    import io
    from importlib import resources

    from rvcoax.geometry.rolling_catalogue import ROLLING_CATALOGUE_FILE

    rows = {r["designation"]: r for r in csv.DictReader(io.StringIO(
        resources.files("rvcoax.geometry").joinpath("data", ROLLING_CATALOGUE_FILE).read_text(encoding="utf-8")))}
    for name, (d, big_d, width, cup) in published.items():
        row = rows[name]
        assert (float(row["bore_mm"]), float(row["outside_diameter_mm"]), float(row["width_mm"]),
                float(row["cup_width_mm"])) == (d, big_d, width, cup), name
    for name, (rating, static) in {"32006X": (37500, 46500), "30206": (43500, 48000), "32206": (53000, 61500)}.items():
        entry = ROLLING_BEARINGS[name]  # the estimated roller set: within 10 % of the maker's ratings
        assert entry.dynamic_rating_N == pytest.approx(rating, rel=0.10), name
        assert entry.static_rating_N == pytest.approx(static, rel=0.10), name


def test_the_variant_solves_with_the_four_bearings_from_geometry():
    rig = _variant()
    bearings = {b.name: b for b in rig.bearings if b.name in NAMES}
    assert [bearings[n].model for n in NAMES] == ["angular_contact", "cylindrical_roller", "tapered_roller",
                                                   "tapered_roller"]
    assert bearings["input_B1"].width_mm == 28.0  # a DB pair of two 14 mm rows
    assert bearings["output_B1"].width_mm == 17.25  # T of the 30206
    assert all(20 < bearings[n].radial_stiffness_N_per_um < 2000 for n in NAMES)
    sweep = run_sweep(rig, CASES)
    report = sweep.solver_report
    assert report["rolling_bearings"] == list(NAMES) and "ball_bearings" not in report
    points = report["rolling_bearing_operating_points"]
    for name in NAMES:
        assert [p["case"] for p in points[name]] == ["at rest"] + [c.label for c in CASES]
    pair = points["input_B1"][0]
    z = ROLLING_BEARINGS["7204B"].element_count
    assert pair["loaded_elements"] == 2 * z  # the light preload loads every ball of both rows at rest
    assert 40.0 < pair["contact_angle_min_deg"] <= pair["contact_angle_max_deg"] < 41.0  # 40° grown by the preload
    assert pair["axial_stiffness_N_per_um"] > 50 and pair["model"] == "angular_contact"
    section = model_section(sweep)
    assert section["rolling_bearings"] == list(NAMES) and "rolling_bearing_operating_points" in section
    # the converged states feed the per-element loads (for life and static safety), at rest and per case
    for index, position in ((None, 0), (0, 1), (1, 2)):
        elements = sweep.rolling_element_loads(index)
        for name in NAMES:
            point = points[name][position]
            assert elements[name].max_load_n == pytest.approx(point["max_element_load_N"], rel=1e-6, abs=1e-9)
            assert elements[name].loaded_elements == point["loaded_elements"]
    motion = sweep.nonlinear_bearings.motions(sweep.nonlinear_bearings.operator @ sweep.rest_displacement)
    model = next(m for m in sweep.nonlinear_bearings.rolling if m.name == "input_B1")
    assert rolling_element_loads(model.bearing, motion["input_B1"]).max_load_n == pytest.approx(
        pair["max_element_load_N"], rel=1e-9)
    with pytest.raises(ModelError, match="the beam and hybrid models solve it"):
        run_sweep(rig, CASES[:1], SweepSettings(model="solid"))


def test_a_designation_whose_bore_is_not_the_shaft_is_a_plausibility_warning():
    from rvcoax.geometry.catalogue import plausibility_warnings

    assert plausibility_warnings(_variant()) == []  # 20 mm bores on the Ø20 input shaft, 30 mm on the Ø30 output
    rig = parse_rig_text(_with_input_b1('model = "angular_contact"\ndesignation = "7206B"'))
    assert plausibility_warnings(rig) == [
        "bearings[4] ('input_B1').designation = 7206B: its bore is 30 mm, but the shaft's Ø at x = 255 mm is 20 mm: "
        "another designation, or the shaft's segment?"]
    # a preload far beyond the heavy class: the rows carry most of their C at rest
    (message,) = plausibility_warnings(parse_rig_text(_with_input_b1(
        'model = "angular_contact"\ndesignation = "7204B"\narrangement = "DB"\npreload_N = 9000')))
    assert message.startswith("bearings[4] ('input_B1').preload_N: each row carries 9000 N at rest, 69 % of its C")


@pytest.mark.slow
def test_the_hybrid_model_solves_them_like_the_beam_model():
    # the same condensed Newton solve on the hybrid system (solid input and output shafts); ~70 s under load
    hybrid = run_sweep(_variant(), CASES[:1], SweepSettings(model="hybrid"))
    beam = run_sweep(_variant(), CASES[:1])
    assert hybrid.solver_report["rolling_bearings"] == list(NAMES)
    for shaft in ("input", "output"):  # measured: 2.2 % and 0.01 %
        assert hybrid.cases[0].paths[shaft].y_max_mm == pytest.approx(beam.cases[0].paths[shaft].y_max_mm, rel=0.04)


def test_preload_class_loads_each_row_with_its_share_of_c():
    rig = _variant()
    entry = ROLLING_BEARINGS["7204B"]
    pair = rolling_bearing_of(next(b for b in rig.bearings if b.name == "input_B1"))
    for row in pair.rows:
        carried = row.state(np.zeros(5)).force[0]
        assert carried == pytest.approx(PRELOAD_CLASS_SHARE["light"] * entry.dynamic_rating_N, rel=1e-9)
    assert not np.any(np.abs(pair.force(np.zeros(5))[0]) > 1e-6)
    heavier = parse_rig_text(_with_input_b1('model = "angular_contact"\ndesignation = "7204B"\narrangement = "DB"\n'
                                            'preload_class = "heavy"'))
    heavy = rolling_bearing_of(next(b for b in heavier.bearings if b.name == "input_B1"))
    assert heavy.force(np.zeros(5))[1][1, 1] > pair.force(np.zeros(5))[1][1, 1]


def test_a_warm_shaft_presses_an_angular_pair_together():
    rig = _variant()
    bearing = next(b for b in rig.bearings if b.name == "input_B1")
    from rvcoax.geometry.variants import reference_from_geometry

    thermal = reference_from_geometry(("thermal",)).thermal  # shafts 10 K above their blocks
    warm = rig.model_copy(update={"thermal": thermal})
    cold_load = rolling_bearing_of(bearing).rows[0].state(np.zeros(5)).force[0]
    warm_load = rolling_bearing_of(bearing, warm).rows[0].state(np.zeros(5)).force[0]
    assert warm_load > 1.5 * cold_load


def test_bad_keys_are_refused_with_the_key_and_the_reason():
    cases = {
        'model = "angular_contact"\ndesignation = "7207"': "nearest: 7207",
        'model = "angular_contact"\ndesignation = "NU204"': "it is a designation of model = \"cylindrical_roller\"",
        'model = "tapered_roller"\ndesignation = "30299"': "unknown tapered roller bearing '30299'; nearest: 302",
        'model = "angular_contact"\ndesignation = "7204B"\npreload_class = "light"':
            "preload_class = \"light\" needs a DB or DF pair (arrangement): a single bearing has no partner row",
        'model = "tapered_roller"\ndesignation = "30206"\narrangement = "DT"\npreload_class = "medium"':
            "a tandem (DT) pair has no partner row",
        'model = "angular_contact"\ndesignation = "7204B"\narrangement = "DB"\npreload_class = "light"\npreload_N = 50':
            "preload_class and preload_N: give one way",
        'model = "angular_contact"\ndesignation = "7204B"\nclearance_class = "C3"':
            "clearance_class: not a key of model = \"angular_contact\"",
        'model = "cylindrical_roller"\ndesignation = "NU204"\ncrowning = "circular"': "needs crown_drop_um",
        'model = "cylindrical_roller"\ndesignation = "NU204"\narrangement = "DB"': "arrangement: not a key",
        'model = "cylindrical_roller"\ndesignation = "NU204"\ncrown_drop_um = 5':
            "crown_drop_um applies to crowning = \"circular\"",
        'model = "angular_contact"\ndesignation = "7204B"\narrangement = "DB"\naxial_direction = -1':
            "axial_direction: a DB pair carries thrust both ways",
        'model = "angular_contact"\nball_count = 10\nball_diameter_mm = 8': "missing: pitch_diameter_mm",
        'radial_stiffness_N_per_um = 50\narrangement = "DB"': "arrangement only apply to model = \"angular_contact\"",
        'model = "tapered_roller"\ndesignation = "30206"\nradial_clearance_um = 5': "axial_offset_um < 0",
        'model = "angular_contact"\ndesignation = "7204B"\ncontact_angle_deg = 10':
            "contact angle must lie in 15° … 45°, the range of ISO 281's X/Y table",
        'model = "cylindrical_roller"\ndesignation = "NU204"\naxial_stiffness_N_per_um = 100':
            "an NU bearing (NU204) has ribs on its outer ring only, its rollers slide axially",
        'model = "cylindrical_roller"\ndesignation = "N204"\naxial_direction = -1':
            "axial_direction: an N bearing carries no thrust either way",
        'model = "cylindrical_roller"\ndesignation = "NUP204"\naxial_direction = -1':
            "an NUP bearing carries thrust both ways",
        'model = "cylindrical_roller"\ndesignation = "NU204"\nminimum_load_factor = 0.1':
            "also needs reference_speed_rpm",
        'model = "angular_contact"\ndesignation = "7204B"\nminimum_load_factor = 0.02':
            "also needs oil_viscosity_mm2_per_s",
        'model = "tapered_roller"\ndesignation = "30204"\nminimum_load_factor = 0.02':
            "a tapered roller bearing's minimum load is 0.02 C (SKF), no factor",
        'model = "angular_contact"\ndesignation = "7204B"\nreference_speed_rpm = 9000':
            "reference_speed_rpm: the maker's reference speed enters the minimum load of a cylindrical",
        'model = "angular_contact"\ndesignation = "7204B"\noil_viscosity_mm2_per_s = 20\nviscosity_ratio = 2':
            "oil_viscosity_mm2_per_s and viscosity_ratio both give κ",
        'radial_stiffness_N_per_um = 50\noil_viscosity_mm2_per_s = 20': "need the bearing's mean diameter",
    }
    assert_input_b1_refused(_with_input_b1, cases)
    assert nearest_designations("7207")[:3] == ["7207C", "7207B", "7207AC"]
    assert nearest_designations("32006 x", "tapered_roller")[0] == "32006X"


def test_explicit_geometry_and_designations_written_loosely():
    rig = parse_rig_text(_with_input_b1('model = "tapered_roller"\ndesignation = "32006 x"\naxial_offset_um = 3'))
    bearing = rolling_bearing_of(next(b for b in rig.bearings if b.name == "input_B1"))
    assert bearing.rows[0].law.roller_count == ROLLING_BEARINGS["32006X"].element_count
    explicit = parse_rig_text(_with_input_b1(
        'model = "angular_contact"\nball_count = 11\nball_diameter_mm = 8\npitch_diameter_mm = 33.5\n'
        'inner_conformity = 0.52\nouter_conformity = 0.53\ncontact_angle_deg = 30\npreload_N = 100'))
    law = rolling_bearing_of(next(b for b in explicit.bearings if b.name == "input_B1")).rows[0]
    assert law.law.ball_count == 11 and law.law.contact_angle_rad == pytest.approx(math.radians(30))
    assert law.state(np.zeros(5)).force[0] == pytest.approx(100.0, rel=1e-9)
    # arrangements: the rows' facings and positions (a bearing width apart); a DT pair shares a preload force
    for keys, facings in (('arrangement = "DF"\npreload_N = 200', (-1, 1)),
                          ('arrangement = "DT"\naxial_direction = -1\npreload_N = 200', (-1, -1))):
        rig = parse_rig_text(_with_input_b1(f'model = "angular_contact"\ndesignation = "7204C"\n{keys}'))
        entry = next(b for b in rig.bearings if b.name == "input_B1")
        pair = rolling_bearing_of(entry)
        assert tuple(r.facing for r in pair.rows) == facings and entry.width_mm == 28.0
        assert [r.axial_position_m for r in pair.rows] == pytest.approx([-7e-3, 7e-3])
        carried = [r.state(np.zeros(5)).force[0] for r in pair.rows]
        assert carried == pytest.approx([200.0, 200.0] if facings == (-1, 1) else [100.0, 100.0], rel=1e-9)


def test_the_discrepancy_vocabulary_has_the_clearance_and_setting_of_these_bearings():
    from rvcoax.geometry.effects import candidate_effects
    from rvcoax.geometry.rolling_model import clearance_um_of

    rig = _variant()
    names = {e.name: e for e in candidate_effects(rig)}
    assert not any(n.endswith("@input_B1") and n.startswith("bearing_") for n in names)  # set by a preload class
    assert "bearing_stiffness@input_B2" not in names  # the stiffness follows from geometry
    (c,) = names["bearing_clearance@input_B2"].parameters
    assert (c.name, c.unit, c.lower, c.upper) == ("clearance_um", "µm", -12.5, 75.0 - 12.5)  # 0 … C4 max (NU 204)
    (p,) = names["bearing_preload@output_B1"].parameters
    assert (p.name, p.unit, p.lower) == ("axial_offset_um", "µm", -25.0) and 5 < p.upper < 100
    assert not names["bearing_preload@output_B1"].linear
    closed = names["bearing_clearance@input_B2"].apply(rig, [-10.0])
    assert clearance_um_of(next(b for b in closed.bearings if b.name == "input_B2")) == 2.5
    pressed = names["bearing_preload@output_B1"].apply(rig, [8.0])
    assert next(b for b in pressed.bearings if b.name == "output_B1").axial_offset_um == 3.0
    # a pair preloaded by a force: the effect changes the force, up to the heavy class
    forced = parse_rig_text(_with_input_b1('model = "angular_contact"\ndesignation = "7204B"\narrangement = "DB"\n'
                                           'preload_N = 100'))
    (f,) = {e.name: e for e in candidate_effects(forced)}["bearing_preload@input_B1"].parameters
    assert (f.name, f.lower) == ("preload_N", -100.0)
    assert f.upper == pytest.approx(0.04 * ROLLING_BEARINGS["7204B"].dynamic_rating_N - 100.0, rel=1e-9)


def test_load_ratings_of_an_entry():
    from rvcoax.geometry.rolling_model import load_ratings_N

    rig = _variant()
    by_name = {b.name: b for b in rig.bearings}
    entry = ROLLING_BEARINGS["30206"]
    assert load_ratings_N(by_name["output_B1"]) == (entry.dynamic_rating_N, entry.static_rating_N)
    # a geometry override recomputes both (ISO 281, ISO 76's definition): more rollers, higher ratings
    more = parse_rig_text(_with_input_b1('model = "tapered_roller"\ndesignation = "30206"\nroller_count = 17'))
    c, c0 = load_ratings_N(next(b for b in more.bearings if b.name == "input_B1"))
    assert c == pytest.approx(entry.dynamic_rating_N * (17 / entry.element_count) ** 0.75, rel=1e-9)
    assert c0 == pytest.approx(entry.static_rating_N * 17 / entry.element_count, rel=1e-6)
    # a deep-groove ball bearing's, from its geometry (the 6204: about SKF's 13.5 / 6.55 kN)
    ball = parse_rig_text(reference_rig_text("ball_bearings"), "ball")
    c, c0 = load_ratings_N(next(b for b in ball.bearings if b.name == "input_B1"))
    assert c == pytest.approx(13500.0, rel=0.10) and c0 == pytest.approx(6550.0, rel=0.05)


@pytest.mark.subprocess  # a fresh interpreter, to see what an import loads
def test_catalogue_is_built_on_first_use_with_the_eagerly_built_values():
    import subprocess
    import sys

    from rvcoax.geometry import rolling_catalogue

    # importing the module (and a sweep's, which reaches it) builds nothing and leaves scipy.optimize to the
    # commands that need it (calibration, bearing preload)
    probe = ("import sys, rvcoax.geometry.rolling_catalogue as c, rvcoax.results.sweep; "
             "print('scipy.optimize' in sys.modules, c.rolling_bearings.cache_info().currsize)")
    assert subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          check=True).stdout.split() == ["False", "0"]
    assert ROLLING_BEARINGS is rolling_catalogue.rolling_bearings()  # one catalogue, however it is reached
    assert len(ROLLING_BEARINGS) == 176  # 14 NUP entries with the NJ rib change
    # bit for bit the values the catalogue had when it was built at import (recorded before the change)
    pinned = {"7206B": (12295.251746448308, 19754.767431054304, 12), "NU306": (53422.37394412075, 54175.597842449126, 10),
              "32006X": (43602.527005118754, 34675.35643878906, 17)}
    for name, (c0, c, count) in pinned.items():
        entry = ROLLING_BEARINGS[name]
        assert (entry.static_rating_N, entry.dynamic_rating_N, entry.element_count) == (c0, c, count), name


def test_cylindrical_ribs_by_designation():
    """An NJ bearing carries the shaft's thrust one way through its ribs (the roller ends against the outer ring's rib
    and the inner ring's one rib), NUP both ways, NU and N none (SKF Rolling bearings 17000 EN p. 509: NJ, NUP
    "locating bearings" P = 0.92 F_r + 0.6 F_a above e = 0.2; NU, N "non-locating" P = F_r)."""
    from rvcoax.geometry.bearing_ratings import equivalent_load, load_ratings
    from rvcoax.geometry.rolling_model import cylindrical_variant, rib_stiffness_N_per_um

    def entry(keys):
        rig = parse_rig_text(_with_input_b1('model = "cylindrical_roller"\n' + keys))
        return next(b for b in rig.bearings if b.name == "input_B1")

    nj, nj_minus, nup, nu = (entry('designation = "NJ204"'), entry('designation = "NJ204"\naxial_direction = -1'),
                             entry('designation = "NUP204"'), entry('designation = "NU204"'))
    assert [cylindrical_variant(b) for b in (nj, nup, nu)] == ["NJ", "NUP", "NU"]
    # the rib stiffness defaults to the radial reference stiffness (ESTIMATED), and is the linear reference's axial
    assert nj.axial_stiffness_N_per_um == pytest.approx(nj.radial_stiffness_N_per_um, rel=1e-9)
    assert nj.axial_stiffness_N_per_um == pytest.approx(rib_stiffness_N_per_um(nj))
    assert nu.axial_stiffness_N_per_um == 0.0
    step = 2e-6
    for bearing, pushed, pulled in ((nj, True, False), (nj_minus, False, True), (nup, True, True), (nu, False, False)):
        rows = rolling_bearing_of(bearing)
        for sign, carries in ((1.0, pushed), (-1.0, pulled)):
            force, stiffness = rows.force(np.array([sign * step, 0.0, 0.0, 0.0, 0.0]))
            expected = sign * step * bearing.axial_stiffness_N_per_um * 1e6 if carries else 0.0
            assert force[0] == pytest.approx(expected, abs=1e-9), (bearing.designation, sign)
            assert stiffness[0, 0] == pytest.approx(bearing.axial_stiffness_N_per_um * 1e6 if carries else 0.0)
    given = entry('designation = "NJ204"\naxial_stiffness_N_per_um = 40')
    assert rolling_bearing_of(given).force(np.array([step, 0, 0, 0, 0]))[0][0] == pytest.approx(40e6 * step)
    ratings = load_ratings(nj)
    law = rolling_bearing_of(nj).rows[0].law
    assert equivalent_load(nj, law, ratings, 1000.0, 500.0)[0] == pytest.approx(0.92 * 1000.0 + 0.6 * 500.0)
    assert equivalent_load(nu, law, ratings, 1000.0, 500.0)[0] == pytest.approx(1000.0)


def test_life_options_from_the_rig_keys():
    """κ from the oil's viscosity and the case's speed (ISO 281's ν1 at the pitch diameter), C_u from C0 and the
    pitch diameter (ISO 281 annex B), and SKF's minimum loads by type, from the rig keys; without k_r the rule of thumb
    (life_options gives None and life_from_forces takes 0.01 C / 0.02 C)."""
    from rvcoax.fem import bearing_life as bl
    from rvcoax.geometry.bearing_ratings import life_options, load_ratings

    def entry(keys):
        rig = parse_rig_text(_with_input_b1(keys))
        return next(b for b in rig.bearings if b.name == "input_B1")

    cylindrical = entry('model = "cylindrical_roller"\ndesignation = "NU205"\nminimum_load_factor = 0.1\n'
                        'reference_speed_rpm = 12000\noil_viscosity_mm2_per_s = 20\ncontamination_factor = 0.5')
    options = life_options(cylindrical, load_ratings(cylindrical), 3000.0)
    pitch = rolling_bearing_of(cylindrical).rows[0].law.pitch_diameter_m * 1e3
    assert options["minimum_load_N"] == pytest.approx(bl.cylindrical_minimum_load_N(0.1, 3000.0, 12000.0, 38.5))
    assert options["kappa"] == pytest.approx(20.0 / bl.reference_viscosity_mm2_s(3000.0, pitch))
    assert options["fatigue_limit_N"] == pytest.approx(load_ratings(cylindrical).static_N / 8.2)
    assert options["contamination"] == 0.5
    angular = entry('model = "angular_contact"\ndesignation = "7205B"\nminimum_load_factor = 0.02\n'
                    'oil_viscosity_mm2_per_s = 20')
    assert life_options(angular, load_ratings(angular), 3000.0)["minimum_load_N"] == pytest.approx(
        bl.ball_minimum_load_N(0.02, 20.0, 3000.0, 38.5))
    assert life_options(angular, load_ratings(angular), None)["minimum_load_N"] is None  # no speed: rule of thumb
    assert life_options(angular, load_ratings(angular), None)["kappa"] is None
    tapered = entry('model = "tapered_roller"\ndesignation = "30205"')
    assert life_options(tapered, load_ratings(tapered), None)["minimum_load_N"] == pytest.approx(
        0.02 * load_ratings(tapered).dynamic_N)


def test_rib_thrust_beyond_skfs_limit_is_named_per_case():
    """SKF (Rolling bearings 17000 EN p. 509): a locating cylindrical roller bearing's F_a must not exceed 0.5 F_r; an
    NJ whose ribs carry more in a case is named with the case; an NU (no ribs to carry it) is never."""
    from rvcoax.geometry.bearing_ratings import rib_thrust_warnings

    rig = parse_rig_text(_with_input_b1('model = "cylindrical_roller"\ndesignation = "NJ204"'))

    def entry(name, axial, radial):
        return {"name": name, "engineering": {"bearings": [{"name": "input_B1", "force_axial_N": axial,
                                                            "force_radial_N": radial},
                                                           {"name": "input_B2", "force_axial_N": 900.0,
                                                            "force_radial_N": 100.0}]}}

    entries = [entry("light", 40.0, 100.0), entry("heavy", -60.0, 100.0), entry("tiny", 0.8, 0.1)]
    said = rib_thrust_warnings(rig, entries, lambda e: e["name"])
    assert said == ["bearing input_B1 (NJ) carries more thrust on its ribs than 0.5 F_r, the limit for a locating "
                    "cylindrical roller bearing (SKF), in 1 case(s) (heavy)"]
