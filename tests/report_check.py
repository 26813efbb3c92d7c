"""Reading a report's tables back, and recomputing them from ``sweep.json`` by a path of their own.

Used by tests/results/test_report_consistency.py. Nothing here imports the report's table code: the
worst cases, sums and labels are recomputed from the JSON document alone.
"""

from __future__ import annotations

import math
import re
from html.parser import HTMLParser

import pytest

CELL_RELATIVE = 6e-4  # a report cell has 4 significant digits (3 for a few): half a unit of the 4th is 5e-4


class Tables(HTMLParser):
    """Every ``<table>`` of an HTML document: ``{caption: (headings, rows)}``, cell texts stripped."""

    def __init__(self, text: str):
        super().__init__()
        self.tables: dict[str, tuple[list[str], list[list[str]]]] = {}
        self._caption = self._cell = None
        self._headings: list[str] = []
        self._rows: list[list[str]] = []
        self._in = ""
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self._caption, self._headings, self._rows = "", [], []
        elif tag in ("caption", "th", "td"):
            self._in, self._cell = tag, ""
        elif tag == "tr" and self._caption is not None:
            self._rows.append([])

    def handle_endtag(self, tag):
        if tag == "caption":
            self._caption, self._in = self._cell.strip(), ""
        elif tag == "th":
            self._headings.append(self._cell.strip())
            self._in = ""
        elif tag == "td":
            self._rows[-1].append(self._cell.strip())
            self._in = ""
        elif tag == "table":
            self.tables[self._caption] = (self._headings, [r for r in self._rows if r])
            self._caption = None

    def handle_data(self, data):
        if self._in:
            self._cell += data

    def find(self, start: str) -> tuple[list[str], list[dict[str, str]]]:
        """The table whose caption starts with ``start``: its headings and its rows as dicts."""
        matches = [c for c in self.tables if c.startswith(start)]
        assert len(matches) == 1, (start, list(self.tables))
        headings, rows = self.tables[matches[0]]
        return headings, [dict(zip(headings, row)) for row in rows]

    def caption(self, start: str) -> str:
        return next(c for c in self.tables if c.startswith(start))


def same(cell: str, value: float, digits_relative: float = CELL_RELATIVE, floor: float = 0.0) -> None:
    """A formatted report cell equals ``value`` to the digits it shows (``floor``: absolute allowance)."""
    if value is None:
        assert cell == "–", cell
        return
    shown = float(cell.replace("\u2212", "-"))
    assert shown == pytest.approx(value, rel=digits_relative, abs=max(floor, 1e-300)), (cell, value)


def case_text(number: int, case: dict) -> str:
    return f"{number}: T1\u00a0=\u00a0{case['T1_input_Nm']:g}, T2\u00a0=\u00a0{case['T2_output_Nm']:g}"


def expected_worst_rows(cases: list[dict], group: str, name: str, keys: tuple[str, ...]) -> dict[int, set[str]]:
    """Case index → the keys whose largest value over the sweep lies in that case (a tie goes to a case already
    holding an earlier key, else to the earliest case)."""
    found: dict[int, set[str]] = {}
    for key in keys:
        values = [next(q for q in c["engineering"][group] if q["name"] == name)[key] for c in cases]
        top = max(values)
        tied = [i for i, v in enumerate(values) if v == top]
        found.setdefault(next((i for i in tied if i in found), tied[0]), set()).add(key)
    return found


def check_report_against_sweep(html_text: str, document: dict) -> dict:
    """Compare every table of the report computed from the sweep with ``sweep.json`` (``document``), value by
    value; return a summary (counts of cells compared per table) so that a test can require coverage."""
    tables = Tables(html_text)
    cases = document["cases"]
    counts: dict[str, int] = {}

    _, rows = tables.find("Load cases")
    assert len(rows) == len(cases)
    for number, (row, case) in enumerate(zip(rows, cases), start=1):
        assert row["case"] == str(number)
        same(row["T1 input torque [N·m]"], case["T1_input_Nm"])
        same(row["T2 output torque [N·m]"], case["T2_output_Nm"])
    counts["load cases"] = 2 * len(rows)

    _, rows = tables.find("Measured shafts")
    assert len(rows) == 2 * len(cases)
    compared = 0
    for row in rows:
        shafts = cases[int(row["case"]) - 1]["engineering"]["shafts"][row["shaft"]]
        floor = 5e-4 * max(abs(shafts["Y_max_um"]), 1e-30)
        same(row["Y_max [µm]"], shafts["Y_max_um"])
        same(row["β paper 000 = arcsin(Y_max/L) [µrad]"], shafts["beta_paper_urad"])
        same(row["true tilt: slope of the least-squares line [µrad]"], shafts["tilt_urad"], floor=floor)
        same(row["slope at start [µrad]"], shafts["end_slopes_urad"][0], floor=floor)
        same(row["slope at end [µrad]"], shafts["end_slopes_urad"][1], floor=floor)
        compared += 5
    counts["shafts"] = compared

    def coupling_cells(row, q):
        for heading, key in (("offset [µm]", "offset_um"), ("angle [µrad]", "angle_urad"),
                             ("offset from unloaded geometry [µm]", "offset_from_unloaded_um"),
                             ("angle from unloaded geometry [µrad]", "angle_from_unloaded_urad")):
            same(row[heading], q[key])
        return 4

    def bearing_cells(row, q):
        assert row["model"] == q["model"]
        for heading, key in (("radial force [N]", "force_radial_N"),
                             ("radial force change under load [N]", "force_radial_change_N"),
                             ("tilt [µrad]", "tilt_urad"), ("tilt change under load [µrad]", "tilt_change_urad")):
            same(row[heading], q[key])
        same(row["radial stiffness, operating [N/µm]"], q["radial_stiffness_N_per_um"], 6e-3)
        same(row["tilt stiffness, operating [N·m/rad]"], q["tilt_stiffness_Nm_per_rad"], 6e-3)
        if "loaded rolling elements" in row:
            assert row["loaded rolling elements"] == ("–" if q["loaded_elements"] is None else str(q["loaded_elements"]))
            same(row["largest rolling-element load [N]"], q["max_element_load_N"])
        return 6

    for group, caption, column, labels, cells in (
            ("couplings", "Couplings: misalignment", "coupling", {"offset_um": "offset", "angle_urad": "angle"},
             coupling_cells),
            ("bearings", "Bearings: radial force", "bearing", {"force_radial_N": "radial force", "tilt_urad": "tilt"},
             bearing_cells)):
        names = [q["name"] for q in cases[0]["engineering"][group]]
        if not names:
            continue
        _, rows = tables.find(caption)
        compared = 0
        for name in names:
            expected = expected_worst_rows(cases, group, name, tuple(labels))
            mine = [r for r in rows if r[column] == name]
            assert {r["case"] for r in mine} == {case_text(i + 1, cases[i]) for i in expected}, (name, mine)
            for row in mine:
                index = int(row["case"].split(":")[0]) - 1
                assert set(row["largest"].split(" and ")) == {labels[k] for k in expected[index]}
                compared += cells(row, next(q for q in cases[index]["engineering"][group] if q["name"] == name))
        counts[group] = compared

    last = max(range(len(cases)), key=lambda i: (abs(cases[i]["T2_output_Nm"]), abs(cases[i]["T1_input_Nm"])))
    caption = tables.caption("Support reactions on the rig")
    assert case_text(last + 1, cases[last]) in caption, caption
    _, rows = tables.find("Support reactions on the rig")
    reactions = cases[last]["engineering"]["reactions"]
    by_name = {r["support"]: r for r in rows}
    scale = max(abs(v) for r in reactions for v in r["force_N"])
    for r in reactions:
        row = by_name[r["name"]]
        for axis, value in zip("xyz", r["force_N"]):
            same(row[f"F_{axis} [N]"], value, floor=1e-9 * scale)
        for axis, value in zip("xyz", r["moment_Nm"]):
            same(row[f"M_{axis} [N·m]"], value, floor=1e-9 * scale)
    total = [math.fsum(r["force_N"][k] for r in reactions) for k in range(3)]
    applied = cases[last]["engineering"]["applied_force_N"]
    for axis, t, a in zip("xyz", total, applied):
        same(by_name["sum of the reactions"][f"F_{axis} [N]"], t, floor=1e-9 * scale)
        same(by_name["− (weight and applied loads)"][f"F_{axis} [N]"], -a, floor=1e-9 * scale)
        assert t == pytest.approx(-a, rel=1e-7, abs=1e-7 * scale)  # equilibrium, in the JSON itself
    counts["reactions"] = 6 * len(reactions) + 6
    return {"counts": counts, "reaction_kinds": sorted({r["kind"] for r in reactions}), "tables": tables}


def signature(html_text: str) -> str:
    """The report's signature line (rig file, SHA-256, version, date), tags removed."""
    match = re.search(r'<p class="sign">(.*?)</p>', html_text, re.S)
    assert match, "the report has no signature line"
    return re.sub(r"<[^>]+>", "", match.group(1))
