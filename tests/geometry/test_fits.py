"""Operating clearance from fits (rvcoax.geometry.fits): ISO 286 classes, ISO 492 ring tolerances, thick rings."""

from __future__ import annotations

import tomllib

import pytest

from rvcoax.geometry import fits
from rvcoax.geometry.ball_model import OperatingClearanceError, fit_clearance_of, operating_geometry
from rvcoax.geometry.catalogue import plausibility_warnings
from rvcoax.geometry.rigfile import RigFileError, parse_rig, reference_rig_text

STEEL = (208000.0, 0.3)


@pytest.mark.parametrize(("tolerance_class", "size", "zone"), [
    # ISO 286-2 limit deviations (µm), as in every maker's table of shaft and housing fits
    ("k5", 20.0, (2, 11)), ("j6", 40.0, (-5, 11)), ("m6", 40.0, (9, 25)), ("k6", 60.0, (2, 21)),
    ("js6", 30.0, (-6.5, 6.5)), ("H7", 47.0, (0, 25)), ("J7", 47.0, (-11, 14)), ("K7", 62.0, (-21, 9)),
    ("M7", 80.0, (-30, 0)), ("N7", 62.0, (-39, -9)), ("G6", 30.0, (7, 20)), ("h5", 25.0, (-9, 0)),
])
def test_iso286_limit_deviations(tolerance_class, size, zone):
    assert fits.tolerance_zone_um(tolerance_class, size) == pytest.approx(zone)


def test_unknown_classes_are_named():
    with pytest.raises(ValueError, match="not tabulated here.*k5, k6"):
        fits.tolerance_zone_um("r6", 30.0)
    with pytest.raises(ValueError, match="not an ISO 286 tolerance class"):
        fits.tolerance_zone_um("H", 30.0)


def test_interference_ranges_with_iso492_ring_tolerances():
    # 6204 (d = 20 mm, Δ_dmp = 0 … −10 µm) on k5 (+2 … +11 µm): 2 … 21 µm
    assert fits.shaft_interference_um("k5", 20.0) == pytest.approx((2.0, 21.0))
    # its outer ring (D = 47 mm, Δ_Dmp = 0 … −11 µm) in H7 (0 … +25 µm): −36 … 0 µm (a clearance fit)
    assert fits.housing_interference_um("H7", 47.0) == pytest.approx((-36.0, 0.0))


def test_thick_ring_expansion_against_the_hand_computation():
    """One shaft/ring pair by hand: a solid shaft of the ring's steel pressed into the inner ring. Lamé with equal
    materials: p [a/E ((b²+a²)/(b²−a²) + ν) + a/E (1 − ν)] = p a/E · 2b²/(b²−a²) = I/2, so
    p = E I (b²−a²)/(4 a b²) and Δd_1 = 4 p a² b / (E (b²−a²)) = I a/b = I d/d_1: the textbook rule. For the 6204
    (d = 20, d_1 = D_pw − D_w = 33.5 − 7.938 = 25.562 mm) and I = 21 µm: 21 · 20/25.562 = 16.43 µm."""
    growth = fits.inner_raceway_growth_um(21.0, 20.0, 25.562, 0.0, ring=STEEL, shaft=STEEL)
    assert growth == pytest.approx(21.0 * 20.0 / 25.562, rel=1e-12)
    assert growth == pytest.approx(16.43, abs=0.01)
    # the outer ring in a much larger housing of the same steel: ΔD_1 = I D_1/D
    assert fits.outer_raceway_shrinkage_um(10.0, 47.0, 41.438, None, ring=STEEL, housing=STEEL) == pytest.approx(
        10.0 * 41.438 / 47.0, rel=1e-12)
    # a hollow shaft and a thin housing wall give way: less of the interference reaches the raceway
    assert fits.inner_raceway_growth_um(21.0, 20.0, 25.562, 8.0, ring=STEEL, shaft=STEEL) < growth
    assert fits.outer_raceway_shrinkage_um(10.0, 47.0, 41.438, 60.0, ring=STEEL, housing=(157000.0, 0.27)) < 10.0 * 41.438 / 47.0
    assert fits.inner_raceway_growth_um(-5.0, 20.0, 25.562, 0.0, ring=STEEL, shaft=STEEL) == 0.0  # a clearance fit


def _ball_rig(shaft_fit: str, housing_fit: str, clearance_class: str = "CN", which: str = "mean"):
    data = tomllib.loads(reference_rig_text("ball_bearings"))
    for bearing in data["bearings"]:
        if bearing["name"] == "input_B1":
            bearing.update(shaft_fit=shaft_fit, housing_fit=housing_fit, clearance_class=clearance_class,
                           fit_clearance=which)
    return parse_rig(data, "fits")


def test_mounted_clearance_of_a_rig_bearing():
    rig = _ball_rig("k5", "J7")
    bearing = next(b for b in rig.bearings if b.name == "input_B1")
    result = fit_clearance_of(rig, bearing)
    assert result.unmounted_um == (5.0, 20.0)  # ISO 5753-1 CN, bore 18 … 24 mm
    assert result.shaft_interference_um == pytest.approx((2.0, 21.0))
    assert result.housing_interference_um == pytest.approx((-25.0, 11.0))  # ring 0 … −11 in J7 −11 … +14
    low, high = result.reduction_um
    assert 0.0 < low < high < 21.0 * 20.0 / 25.562 + 11.0 * 41.438 / 47.0  # the hollow Ø8 shaft and the block give way
    assert result.mounted_um == pytest.approx((5.0 - high, 20.0 - low))
    assert operating_geometry(rig, bearing).clearance_m * 1e6 == pytest.approx(result.chosen_um)
    loose_rig = _ball_rig("k5", "J7", which="max")
    loosest = fit_clearance_of(loose_rig, next(b for b in loose_rig.bearings if b.name == "input_B1"))
    assert loosest.chosen_um == pytest.approx(result.mounted_um[1])
    # the tightest combination leaves a negative clearance: warned about, solved with the mean
    assert any("input_B1" in w and "k5" in w for w in plausibility_warnings(rig))


def test_a_fit_that_takes_all_the_clearance_is_refused():
    rig = _ball_rig("p6", "N7", clearance_class="C2")
    bearing = next(b for b in rig.bearings if b.name == "input_B1")
    with pytest.raises(OperatingClearanceError, match=r"bearings 'input_B1': shaft_fit = p6, housing_fit = N7.*leave -"):
        operating_geometry(rig, bearing)
    data = tomllib.loads(reference_rig_text("ball_bearings"))
    data["bearings"][4].update(shaft_fit="k5", clearance_um=10.0)
    with pytest.raises(RigFileError, match="clearance_um is the clearance as mounted"):
        parse_rig(data, "fits")
    data["bearings"][4].pop("clearance_um")
    data["bearings"][4]["shaft_fit"] = "K7"
    with pytest.raises(RigFileError, match="shaft_fit.*lower case"):
        parse_rig(data, "fits")
