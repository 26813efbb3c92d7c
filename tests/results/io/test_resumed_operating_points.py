"""A resumed nonlinear sweep lists every case's bearing operating points in sweep.json's ``model``: the cases
solved now from the new solve, the reused ones from the journal's records (not only those solved in the last run)."""

from __future__ import annotations

import json

from typer.testing import CliRunner

from rvcoax.geometry.rigfile import reference_rig_text
from rvcoax.results.cli.app import app

T1 = "0.5,1,1.2,1.43,2"
T2 = "10,50,100,150,200"


def test_a_resumed_ball_bearing_sweep_lists_the_operating_points_of_every_case(tmp_path):
    rig = tmp_path / "ball.toml"
    rig.write_text(reference_rig_text("ball_bearings"), encoding="utf-8")
    sweep = ["sweep", "--rig", str(rig), "--t1", T1, "--t2", T2]
    for out in ("fresh", "out"):
        result = CliRunner().invoke(app, [*sweep, "--out", str(tmp_path / out)])
        assert result.exit_code == 0, result.output
    resumed = CliRunner().invoke(app, [*sweep, "--out", str(tmp_path / "out"), "--resume"])
    assert resumed.exit_code == 0, resumed.output
    # five reused cases, three of them solved again as a spot check: cases 2 and 4 come from the journal only
    assert "3 reused case(s) as a spot check" in " ".join(resumed.output.split())
    fresh = json.loads((tmp_path / "fresh" / "sweep.json").read_text(encoding="utf-8"))["model"]
    model = json.loads((tmp_path / "out" / "sweep.json").read_text(encoding="utf-8"))["model"]
    labels = ["at rest"] + [f"T1={t1:g} N·m, T2={t2:g} N·m" for t1, t2 in zip(map(float, T1.split(",")),
                                                                               map(float, T2.split(",")))]
    points = model["ball_bearing_operating_points"]
    assert set(points) == {"input_B1", "input_B2", "output_B1", "output_B2"}
    for name, listed in points.items():
        assert [p["case"] for p in listed] == [p["case"] for p in fresh["ball_bearing_operating_points"][name]]
        assert len(listed) == len(labels)
    assert model["ball_bearing_operating_points"] == fresh["ball_bearing_operating_points"]
    assert model == fresh  # the whole section, as an uninterrupted run writes it
