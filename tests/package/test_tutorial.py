"""docs/tutorial.md: its TOML blocks, in order, are a rig file that solves without a warning, and the figures
the page quotes (mass, Y at 412 N·m, which springs matter) are what that rig gives."""

from __future__ import annotations

import copy
import re
import subprocess
import sys
import tomllib

import pytest
from tutorial_rig import CASES, page, rig_text

from rvcoax.geometry.catalogue import plausibility_warnings
from rvcoax.geometry.rigfile import parse_rig, parse_rig_text
from rvcoax.results.sweep import run_sweep


def _scale(entry: dict, keys: tuple[str, ...]) -> None:
    for key in keys:
        value = entry[key]
        entry[key] = [2 * v for v in value] if isinstance(value, list) else 2 * value


def _named(items: list[dict], names: tuple[str, ...]) -> list[dict]:
    return [item for item in items if item["name"] in names]


SIX = ("translational_stiffness_N_per_um", "rotational_stiffness_Nm_per_rad")
EDITS = {  # the rows of the page's table → the edit each describes
    "crankshaft load sharing: imbalance":
        lambda d: _scale(_named(d["torque_lateral_loads"], ("crankshaft_load_sharing",))[0], ("imbalance",)),
    "reducer output flange (main bearings): all six stiffnesses":
        lambda d: _scale(_named(d["joints"], ("reducer_output_flange",))[0], SIX),
    "output bearings output_B1, output_B2: radial stiffness":
        lambda d: [_scale(b, ("radial_stiffness_N_per_um",)) for b in _named(d["bearings"], ("output_B1", "output_B2"))],
    "output bearing block mounts: all six stiffnesses":
        lambda d: _scale(_named(d["mounts"], ("output_block_base",))[0], SIX),
    "couplings C2 and C3: radial and angular stiffness":
        lambda d: [_scale(c, ("radial_stiffness_N_per_mm", "angular_stiffness_Nm_per_rad"))
                   for c in _named(d["couplings"], ("C2", "C3"))],
}


@pytest.fixture(scope="module")
def solved():
    rig = parse_rig_text(rig_text(), "rv40e.toml")
    return rig, run_sweep(rig, CASES)


def test_the_tutorial_rig_is_plausible_and_weighs_what_the_page_says(solved):
    rig, sweep = solved
    assert plausibility_warnings(rig) == []
    assert sweep.frame.part_mass_kg["motor_housing"] == pytest.approx(6.3)
    assert "the whole rig 103 kg" in page()
    assert sum(sweep.frame.part_mass_kg.values()) == pytest.approx(103, abs=0.5)
    last = sweep.cases[-1].paths
    assert f"output shaft's Y is {last['output'].y_max_mm * 1e3:.3f} µm" in page()
    assert f"input shaft's {last['input'].y_max_mm * 1e3:.3f} µm" in page()


def test_the_table_of_what_matters_is_what_the_rig_gives(solved):
    _, sweep = solved
    base = sweep.cases[-1].paths["output"].y_max_mm
    rows = dict(re.findall(r"^\| ([^|]+?) \| ([+−-][\d.]+) % \|$", page(), re.M))
    assert set(rows) == set(EDITS)
    data = tomllib.loads(rig_text())
    for label, edit in EDITS.items():
        edited = copy.deepcopy(data)
        edit(edited)
        changed = run_sweep(parse_rig(edited, label), CASES).cases[-1].paths["output"].y_max_mm
        quoted = float(rows[label].replace("−", "-"))
        assert 100 * (changed / base - 1) == pytest.approx(quoted, abs=0.5), label


@pytest.mark.slow
@pytest.mark.subprocess
def test_the_python_block_runs(tmp_path):
    (tmp_path / "rv40e.toml").write_text(rig_text(), encoding="utf-8")
    (code,) = re.findall(r"```python\n(.*?)```", page(), re.S)
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().endswith("µm")
    assert "<section id=\"provenance\">" in (tmp_path / "report.html").read_text(encoding="utf-8")
