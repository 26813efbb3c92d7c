"""Answers that cover what the data cannot exclude (issue 28, item 1: at least 95 % honest on every class).

- A |Y_max| table folds each path's sign, so the χ² of one linear effect has several valleys: the fit must start in
  the deepest one (a scan of the effect's search range), not at zero. Checked on a closed form: paths whose sign
  changes along the shaft, shifted by a constant offset, observed as |Y_max| per case.
- An ``ambiguous`` answer names every pair of candidates that fits as well as the named selection; checked on the
  committed CalculiX pair paths file (data another code made from the rig's geometry) through the rule itself: every
  pair it adds fits within the ambiguity margin, and each member earns its parameter.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from discrepancy_data import identification_rig

import rvcoax
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.studies.discrepancy import workflow
from rvcoax.results.studies.discrepancy.identify import Problem
from rvcoax.results.studies.discrepancy.responses import EffectResponse
from rvcoax.results.sweep import SweepSettings


@dataclass(frozen=True)
class _Parameter:
    name: str = "offset_um"
    unit: str = "µm"
    lower: float = -100.0
    upper: float = 100.0
    typical: float = 20.0


@dataclass(frozen=True)
class _Offset:
    name: str = "offset"
    parameters: tuple = (_Parameter(),)


def _table_problem(true_offset: float):
    """Five cases of an 11-station path y(x) = T (sin 2πx + 0.3 sin πx) µm (a positive lobe and a smaller negative
    one), a constant offset as the effect, observed as |Y_max| of each case; data made by the offset ``true_offset``
    (µm; mm inside)."""
    x = np.linspace(0.0, 1.0, 11)
    torques = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    base = np.concatenate([1e-3 * t * (np.sin(2 * np.pi * x) + 0.3 * np.sin(np.pi * x)) for t in torques])

    def observe(paths):
        return np.abs(paths.reshape(torques.size, x.size)).max(axis=1)

    response = EffectResponse(_Offset(), "linear", columns=np.full((1, base.size), 1e-3))
    measured = observe(base + true_offset * response.columns[0])
    sigma = np.full(torques.size, 1e-6)
    return Problem(measured, sigma, base, observe, {"offset": response})


def test_a_linear_effect_on_a_table_is_fitted_in_its_deepest_valley():
    problem = _table_problem(-1.5)  # the offset lowers the positive lobe and deepens the negative one
    start_at_zero = problem.fit(("offset",), {"offset": np.zeros(1)})  # the old single start: a shallower valley
    fitted = problem.fit(("offset",))
    assert fitted.chi2 < 1e-6 and start_at_zero.chi2 > 1e3
    assert float(fitted.values[0][0]) == pytest.approx(-1.5, rel=1e-4)


FOLDER = Path(__file__).parent / "data" / "calculix"
SETS = {s["id"]: s for s in json.loads((FOLDER / "manifest.json").read_text())["sets"]}


@pytest.fixture(scope="module")
def ambiguous_paths():
    """The workflow's stages on the committed CalculiX stiffness paths file (1 % noise), which is ``ambiguous``."""
    rig = identification_rig()
    data = rvcoax.read_measured(FOLDER / SETS["bearing_stiffness_paths_1"]["file"])
    settings = workflow.DiscrepancySettings(confidence_draws=0)
    library = workflow.build_library(rig, paper_cases(), SweepSettings())
    seen = workflow._observe(rig, data, settings, library if library.cases == tuple(data.cases) else None, None)
    located = workflow._locate(seen, settings)
    named = workflow._name(seen, located, settings)
    return seen, named, settings, workflow._judge(seen, located, named, settings)


def test_an_ambiguous_answer_names_both_members_of_every_pair_that_fits_as_well(ambiguous_paths):
    seen, named, settings, result = ambiguous_paths
    assert result.verdict == "ambiguous"
    assert set(SETS["bearing_stiffness_paths_1"]["truth"]) <= {m for s in result.selected for m in s.group}
    problem = named.problem
    limit = workflow._bic(problem, named.fitted, named.after) + settings.ambiguity_margin
    named_members = {m for s in result.selected for m in s.group}
    pairs = [r for r in result.reasons if r.startswith("the pair ")]
    assert pairs  # the rule found pairs here, and each is a real alternative:
    for reason in pairs:
        a, b = reason.removeprefix("the pair ").split(" fits")[0].split(" + ")
        assert {a, b} <= named_members
        fit = problem.fit((a, b), {a: problem.fit((a,)).values[0]})
        assert fit.rejected is None and fit.bic < limit
        assert fit.bic < problem.fit((a,)).bic and fit.bic < problem.fit((b,)).bic
