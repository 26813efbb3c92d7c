"""The study report: its tables say what the model computed (closed-form checks), and the HTML file opens in
headless Chromium with every section, no console error and no network access, and is not blank."""

from __future__ import annotations

import base64
import io
import re
import subprocess

import numpy as np
import pytest
from PIL import Image

from rvcoax.geometry.rigfile import load_rig, reference_rig_text
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.reports import report_tables
from rvcoax.results.reports.report import REPORT_SECTIONS, ReportError, read_discrepancy, write_report
from rvcoax.results.reports.report_pdf import find_browser, headless_command
from rvcoax.results.sweep import run_sweep


@pytest.fixture(scope="module")
def sweep():
    return run_sweep(load_rig(), paper_cases()[::9])


def test_provenance_tags_are_read_per_entry_and_key():
    tags = report_tables.provenance_tags(reference_rig_text())
    assert tags[("parts", "motor_housing")] == {"material": "[P]", "mass_kg": "[R]", "segments": "[S][A]"}
    assert tags[("bearings", "input_B1")]["radial_stiffness_N_per_um"] == "[S]"
    assert tags[("materials", "HT200")] == {"youngs_modulus_MPa": "[P]", "poisson_ratio": "[P]",
                                            "density_kg_per_m3": "[P]"}
    text = '[[bearings]]\n# [A] both from the drawing\nname = "b"\nx_mm = 3 # [D] 1 + 2\n'
    assert report_tables.provenance_tags(text) == {("bearings", "b"): {"": "[A]", "x_mm": "[D]"}}


def test_support_reactions_carry_the_rig_weight(sweep):
    """From the unloaded geometry the vertical support forces sum to the weight of the rig as modelled."""
    table = report_tables.reaction_table(sweep)
    fy = table.columns.index("F_y [N]")
    sums = {row[0]: row for row in table.rows[-2:]}
    weight = sum(sweep.frame.part_mass_kg.values()) * sweep.rig.gravity.acceleration_m_per_s2
    assert float(sums["sum of the reactions"][fy]) == pytest.approx(weight, rel=2e-3)  # 4 significant digits
    assert float(sums["− (weight and applied loads)"][fy]) == pytest.approx(weight, rel=2e-3)
    assert "case 1: T1\u00a0=\u00a01.43, T2\u00a0=\u00a0200" in table.caption


def test_verdicts_grade_value_against_allowable():
    assert report_tables.verdict_of(None) == "no allowable given"
    assert report_tables.verdict_of(0.3).startswith("fine")
    assert report_tables.verdict_of(0.9) == "within allowable"
    assert report_tables.verdict_of(1.2) == "EXCEEDS allowable"


def test_a_file_that_is_not_a_discrepancy_result_is_named(tmp_path):
    bad = tmp_path / "d.json"
    bad.write_text("{\"rms\": 1}")
    with pytest.raises(ReportError, match=r"d\.json: has no 'verdict' key"):
        read_discrepancy(bad)
    bad.write_text("not json")
    with pytest.raises(ReportError, match="not a JSON file"):
        read_discrepancy(bad)


def _decoded_images(text: str) -> list[Image.Image]:
    return [Image.open(io.BytesIO(base64.b64decode(data)))
            for data in re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)]


@pytest.mark.slow
@pytest.mark.subprocess
def test_report_opens_in_headless_chromium(sweep, tmp_path):
    browser = find_browser()
    if browser is None:
        pytest.skip("no headless Chromium on the PATH (chromium, chromium-browser, google-chrome): `make test` "
                    "installs the Debian package chromium when run as root")
    measured = tmp_path / "measured.csv"
    rows = ["T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm"]
    rows += [f"{c.case.input_torque_Nm},{c.case.output_torque_Nm},{c.paths['input'].y_max_mm / 1.05:.6g},"
             f"{c.paths['output'].y_max_mm / 0.97:.6g}" for c in sweep.cases]
    measured.write_text("\n".join(rows) + "\n")
    discrepancy = tmp_path / "discrepancy.json"
    discrepancy.write_text('{"rvcoax_version": "test", "verdict": "explained", '
                           '"rms_before_mm": {"input": 0.0021, "output": 0.0009}, "rms_after_mm": {"input": 0.0001}, '
                           '"rms": {"held_out": {"rms_before_um": {"output": 2.25}, "rms_after_um": {"output": 0.125}, '
                           '"rms_tilt_before_urad": {"output": 14.5}, "rms_tilt_after_urad": {"output": 0.75}}}, '
                           '"selected": [{"effect": "output_block_height", "parameters": {"offset_um": 2.2}, '
                           '"group": []}]}')
    page = write_report(sweep, tmp_path / "report.html", rig_source="built-in reference_rig.toml",
                        rig_text=reference_rig_text(), measured=measured, discrepancy=discrepancy,
                        deformed_view=False)
    text = page.read_text(encoding="utf-8")
    # self-contained: nothing to fetch from a network or another file
    assert not re.search(r"""(src|href)=["'](?!data:|#)|url\(|@import""", text)
    images = _decoded_images(text)
    assert len(images) == 3 and all(min(image.size) > 300 for image in images)
    # the model is 5 % above and 3 % below the measured values written into the file
    assert "+5.0 %" in text and "-3.0 %" in text and "output_block_height" in text
    assert "input shaft 2.1 µm, output shaft 0.9 µm" in text
    assert re.search(r"<td>held out</td><td>output</td><td class=\"num\">2.25</td><td class=\"num\">0.125</td>", text)

    shot = tmp_path / "shot.png"
    with_log = headless_command(browser, tmp_path / "profile", "--enable-logging=stderr", "--v=0",
                                "--window-size=1280,1800", f"--screenshot={shot}", page.as_uri())
    done = subprocess.run(with_log, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    console = [line for line in done.stderr.splitlines()
               if "CONSOLE" in line or "Uncaught" in line or "Failed to load resource" in line or "net::ERR" in line]
    assert console == []
    pixels = np.asarray(Image.open(shot).convert("RGB"), dtype=float)
    assert pixels.shape == (1800, 1280, 3)
    drawn = (pixels < 200).any(axis=2)
    assert pixels.std() > 20 and 0.03 < drawn.mean() < 0.6  # text, tables and a picture: neither blank nor black

    dom = subprocess.run(headless_command(browser, tmp_path / "profile", "--dump-dom", page.as_uri()),
                         capture_output=True, text=True, timeout=120)
    assert dom.returncode == 0, dom.stderr[-2000:]
    for key, heading in REPORT_SECTIONS.items():
        assert re.search(rf'<section id="{key}"><h2>{re.escape(heading)}</h2>', dom.stdout), key
    assert dom.stdout.count("<img ") == 3
    assert "beam_max_element_length_mm = 5.0" in dom.stdout  # the provenance names the mesh


@pytest.mark.slow
def test_report_command_on_a_rig_of_another_layout_and_a_bad_discrepancy_file(tmp_path):
    from tutorial_rig import rig_text
    from typer.testing import CliRunner

    from rvcoax.results.cli.app import app

    rig_file = tmp_path / "rv40e.toml"  # the tutorial's RV-40E bench: a rig of another layout
    rig_file.write_text(rig_text(), encoding="utf-8")
    done = CliRunner().invoke(app, ["report", "--rig", str(rig_file), "--t1", "0.801,4.006", "--t2", "82.4,412",
                                    "--no-deformed", "--out", str(tmp_path / "out")])
    assert done.exit_code == 0, (done.output, done.exception)
    text = (tmp_path / "out" / "report.html").read_text(encoding="utf-8")
    assert all(f'<section id="{key}">' in text for key in REPORT_SECTIONS)
    assert "No measured data given" in text and "wrote" in done.output
    assert "<td>output_bearing_block</td>" in text and "rv40e.toml" in text
    (tmp_path / "d.json").write_text("[]")
    failed = CliRunner().invoke(app, ["report", "--t1", "1", "--t2", "100", "--no-deformed", "--out",
                                      str(tmp_path / "out2"), "--discrepancy", str(tmp_path / "d.json")])
    assert failed.exit_code == 2
    assert "d.json: has no 'verdict' key" in " ".join(failed.output.split())


@pytest.mark.slow
def test_the_report_prints_to_pdf(tmp_path):
    from rvcoax.results.reports.report_pdf import print_pdf

    if find_browser() is None:
        pytest.skip("no headless Chromium on the PATH: `make test` installs the Debian package chromium when root")
    page = tmp_path / "r.html"
    page.write_text("<!DOCTYPE html><html><body><h1>rvcoax</h1><p>report</p></body></html>", encoding="utf-8")
    pdf = print_pdf(page, tmp_path / "out" / "r.pdf")
    data = pdf.read_bytes()
    assert data.startswith(b"%PDF-") and b"/Type /Page" in data.replace(b"/Type/Page", b"/Type /Page")
    assert sorted(p.name for p in pdf.parent.iterdir()) == ["r.pdf"]  # no temporary left behind


def test_the_discrepancy_section_reads_the_workflow_document():
    """The keys `rvcoax discrepancy` writes: summary lines, meanings, parameters with units, sentinel, folds."""
    from rvcoax.results.reports.report import _discrepancy_html

    document = {
        "rvcoax_version": "test", "verdict": "unexplained", "confident": False,
        "summary": ["output shaft: measured − model is 2.43 µm RMS before, 0.14 µm after",
                    "not explained: the gap left is beyond the noise"],
        "named": [{"effect": "torque_reaction@output_bearing_block",
                   "meaning": "a vertical force of +9.44 N per N·m of T2 acts on the housing output_bearing_block"}],
        "selected": [{"effect": "torque_reaction@output_bearing_block",
                      "parameters": {"force_per_torque_N_per_Nm": {"value": 9.4412, "unit": "N/(N·m)"}},
                      "group": ["torque_reaction@output_bearing_block", "torque_reaction@reducer"]}],
        "sentinel": {"description": "a vertical lateral load of about +2 N per N·m of T2 near x = 470 mm"},
        "cross_validation": {"vocabulary": {"folds": 3, "held_out_observations": 40, "reduction_of_chi2": 0.9717,
                                            "improves": True}},
        "observability": {"visible": ["torque_reaction@reducer"],
                          "invisible": {"coupling_offset@C3": {"revealed_by": {"x_mm": 160}},
                                        "bearing_stiffness@brake_b": {"revealed_by": None}}},
    }
    text = _discrepancy_html(document, "discrepancy.json")
    assert "unexplained (not a confident single name)" in text
    assert "0.14 µm after" in text and "not explained: the gap left" in text
    assert "+9.44 N per N·m of T2 acts on the housing output_bearing_block" in text
    assert "force_per_torque_N_per_Nm = 9.441 N/(N·m)" in text
    assert "not a fix" in text and "<td>torque_reaction@reducer</td>" in text
    assert "near x = 470 mm" in text and "reduced by 97.2 % over 3 folds" in text
    assert "1 of 3 effects: torque_reaction@reducer" in text and "2 effects, 1 of them with one more measurement" in text
