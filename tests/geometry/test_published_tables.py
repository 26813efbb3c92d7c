"""The standards' tables the bearing models carry, against makers' published copies of them (issue 25 item 2:
the values first written from memory, checked here against what makers print; the source is named beside
each test)."""

from __future__ import annotations

import pytest

from rvcoax.fem import bearing_life as bl
from rvcoax.geometry.ball_bearings import CLEARANCE_CLASSES, clearance_range_um

# ISO 5753-1 radial internal clearance of deep-groove ball bearings (µm), bore over … incl → C2, CN, C3, C4 (min,
# max), as Cixi Yongchang Bearings prints it (bmzbearings.com, "Radial Internal Clearance Chart"); KTAI
# (ktaiballbearing.com, "radial internal clearance of standard deep groove ball bearings") prints the same rows but
# 0–9 for C2 at 10–18 mm (bmz: 0–8) and 13–25 for C3 at 18–24 mm (bmz: 13–28): the table keeps 0–9 and 13–28.
BALL_PUBLISHED = {
    (6, 10): ((0, 7), (2, 13), (8, 23), (14, 29)),  # KTAI (bmz: C2 0–8)
    (10, 18): ((0, 9), (3, 18), (11, 25), (18, 33)),  # KTAI (bmz: C2 0–8)
    (18, 24): ((0, 10), (5, 20), (13, 28), (20, 36)),  # bmz (KTAI: C3 13–25)
    (24, 30): ((1, 11), (5, 20), (13, 28), (23, 41)),
    (30, 40): ((1, 11), (6, 20), (15, 33), (28, 46)),
    (40, 50): ((1, 11), (6, 23), (18, 36), (30, 51)),
    (50, 65): ((1, 15), (8, 28), (23, 43), (38, 61)),
}
# ISO 5753-1 cylindrical roller bearings, cylindrical bore (µm), as AHR International prints it
# (ahrinternational.com, "bearing clearance": bore up to 24, 24–30, 30–40, 40–50, 50–65 mm)
CYLINDRICAL_PUBLISHED = {
    (10, 24): ((0, 25), (20, 45), (35, 60), (50, 75)),
    (24, 30): ((0, 25), (20, 45), (35, 60), (50, 75)),
    (30, 40): ((5, 30), (25, 50), (45, 70), (60, 85)),
    (40, 50): ((5, 35), (30, 60), (50, 80), (70, 100)),
    (50, 65): ((10, 40), (40, 70), (60, 90), (80, 110)),
}


@pytest.mark.parametrize(("kind", "published"), [("ball", BALL_PUBLISHED),
                                                 ("cylindrical_roller", CYLINDRICAL_PUBLISHED)])
def test_iso5753_clearances_against_makers_tables(kind, published):
    for (low, high), ranges in published.items():
        for bore in (low + 0.5, high):
            for name, expected in zip(CLEARANCE_CLASSES, ranges):
                assert clearance_range_um(bore, name, kind) == expected, (kind, bore, name)


def test_deep_groove_xy_table_against_a_makers_copy():
    """ISO 281 table 3 for deep-groove ball bearings as JTEKT (Koyo) prints it (koyousa.com catalogue, "Calculation
    of equivalent radial / axial load"): f0 F_a/C0 0.172 … 6.89, e 0.19 … 0.44, Y 2.30 … 1.00 (X = 0.56)."""
    key = (0.172, 0.345, 0.689, 1.03, 1.38, 2.07, 3.45, 5.17, 6.89)
    e = (0.19, 0.22, 0.26, 0.28, 0.30, 0.34, 0.38, 0.42, 0.44)
    y = (2.30, 1.99, 1.71, 1.55, 1.45, 1.31, 1.15, 1.04, 1.00)
    assert tuple(bl.XY_TABLE[0]) == key and tuple(bl.XY_TABLE[1]) == e and tuple(bl.XY_TABLE[2]) == y


def test_angular_contact_15_degree_rows_against_makers_copies():
    """ISO 281 table 3, α = 15°: JTEKT (Koyo) prints it by i f0 F_a/C0 (0.178 … 5.35), a maker's transcription
    (LYC, lycbearing.com "Equivalent Dynamic Load-Angular Contact Ball Bearings", table 3) by F_a/C0 (0.015 …
    0.58): e 0.38 … 0.56, Y 1.47 … 1.00, Y1 1.65 … 1.12, Y2 2.39 … 1.63; and 25°: e 0.68, 0.41 F_r + 0.87 F_a,
    pair F_r + 0.92 F_a / 0.67 F_r + 1.41 F_a."""
    key, e, y, y1, y2 = (tuple(float(v) for v in column) for column in bl.ANGULAR_XY_15)
    assert key == (0.015, 0.029, 0.058, 0.087, 0.12, 0.17, 0.29, 0.44, 0.58)
    assert e == (0.38, 0.40, 0.43, 0.46, 0.47, 0.50, 0.55, 0.56, 0.56)
    assert y == (1.47, 1.40, 1.30, 1.23, 1.19, 1.12, 1.02, 1.00, 1.00)
    assert y1 == (1.65, 1.57, 1.46, 1.38, 1.34, 1.26, 1.14, 1.12, 1.12)
    assert y2 == (2.39, 2.28, 2.11, 2.00, 1.93, 1.82, 1.66, 1.63, 1.63)
    assert bl.ANGULAR_XY[25.0] == (0.68, 0.41, 0.87, 0.92, 0.67, 1.41)
    assert bl.ANGULAR_XY[30.0] == (0.80, 0.39, 0.76, 0.78, 0.63, 1.24)
    assert bl.ANGULAR_XY[40.0] == (1.14, 0.35, 0.57, 0.55, 0.57, 0.93)
