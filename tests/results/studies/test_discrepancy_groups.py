"""A named effect's group holds the members the data cannot tell from it in the final selection, whatever the screen
pruned on its way there.

On hybrid-model data (``data/blind_pair20``: set 112 of ``benchmarks/blind_data.py``'s full design, 20 of paper 000's
cases, a coupling angle at C3 and a thermal growth of the output bearing block hidden together, 1 % noise, Y from the
unloaded geometry), identified with the beam model: the screen first adds a thermal growth of the reducer and prunes
it two steps later. The coupling angle's step had grouped six couplings and housings whose signatures are parallel to
it; in the final selection each of them, in its place, fits worse by more than the ambiguity margin and differs from
it by more than the gap test detects, so none is a look-alike, and the pair is ``explained``. (Kept whole because its
step was pruned since, the group made the answer ``ambiguous`` — "six look-alikes" that the data tell apart.)
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from discrepancy_data import discrepancy_rig

import rvcoax
from rvcoax.geometry.schema import Rig
from rvcoax.results.studies.discrepancy.identify import Problem
from rvcoax.results.studies.discrepancy.judge import AMBIGUOUS_GROUP
from rvcoax.results.studies.discrepancy.locate import detection_norm
from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings, _observe, build_library

FOLDER = Path(__file__).parent / "data" / "blind_pair20"
(ENTRY,) = json.loads((FOLDER / "manifest.json").read_text())["sets"]
SETTINGS = DiscrepancySettings(confidence_draws=0)


@pytest.fixture(scope="module")
def pruned():
    rig = discrepancy_rig().model_dump(by_alias=True)
    rig["paths"]["measured_from"] = ENTRY["datum"]
    rig["beam"]["shear_deformation"] = True  # the identification rig of the benchmark (blind_data.identification_rig)
    rig = Rig.model_validate(rig)
    data = rvcoax.read_measured(FOLDER / ENTRY["file"])
    library = build_library(rig, data.cases, SETTINGS.sweep)
    seen = _observe(rig, data, SETTINGS, library, None)  # the screen's problem: responses, σ, rows used to fit
    observed = seen.observed
    problem = Problem(observed.data.value_mm, observed.sigma, observed.base_paths, observed.observe, seen.responses,
                      rows=observed.rows)
    return rvcoax.run_discrepancy(rig, data, SETTINGS, library=library), problem


@pytest.mark.slow  # one workflow run on 20 cases: a few s of CPU
def test_a_pruned_step_s_look_alikes_are_judged_again_in_the_final_selection(pruned):
    result, problem = pruned
    assert any(step.pruned for step in result.steps)  # what this data set exercises: a selection pruned on the way
    truth = set(ENTRY["truth"])
    assert result.verdict == "explained"
    assert all(any(t in s.group for s in result.selected) for t in truth)
    assert all(len(s.group) <= AMBIGUOUS_GROUP for s in result.selected)
    # the members its step had grouped and the final selection left out are told apart by the data: in place of the
    # named effect (the other one kept) each fits worse by more than the ambiguity margin, and their predictions
    # differ by more than the gap test detects on the rows used to fit
    gains = {step.added: step for step in result.steps}
    fitted = {s.name: np.atleast_1d(np.asarray(s.values)) for s in result.selected}
    assert any(m not in s.group for s in result.selected for m in gains[s.name].group)
    for s in result.selected:
        left_out = [m for m in gains[s.name].group if m not in s.group]
        if not left_out:
            continue
        others = tuple(n for n in fitted if n != s.name)
        current = problem.fit(others + (s.name,), fitted)
        for member in left_out:
            trial = problem.fit(others + (member,), fitted)
            assert trial.bic - current.bic >= SETTINGS.ambiguity_margin, member
            difference = (problem.observe(problem.paths(trial.names, trial.values))
                          - problem.observe(problem.paths(current.names, current.values)))[problem.rows]
            assert np.linalg.norm(difference / problem.sigma[problem.rows]) >= detection_norm(problem.rows.size,
                                                                                             SETTINGS.alpha), member

