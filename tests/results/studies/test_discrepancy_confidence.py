"""The verdict's calibrated confidence (issue 28 item 6): a Monte Carlo of the workflow's own decisions.

Checked on CalculiX data (``data/calculix``, made by another code from the rig's geometry; see
``test_discrepancy_calculix.py``): the replay of the decisions used for the draws reproduces the sentinel's scan and
the workflow's verdict on the files themselves; the estimate is seeded (the same file, the same probability), lies in
its Wilson interval, and is reported in the summary and the JSON. Whether the probability is calibrated is measured
on the blind benchmark (``benchmarks/bench_discrepancy_blind.py``, reliability table in ``benchmarks/RESULTS.md``),
not here.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from discrepancy_data import identification_rig

import rvcoax
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.studies.discrepancy import confidence, workflow
from rvcoax.results.studies.discrepancy.report import discrepancy_document, engineering_summary
from rvcoax.results.studies.discrepancy.sentinel import fit_sentinel, sentinel_scan
from rvcoax.results.sweep import SweepSettings

FOLDER = Path(__file__).parent / "data" / "calculix"
SETS = {s["id"]: s for s in json.loads((FOLDER / "manifest.json").read_text())["sets"]}
DRAWS = 60  # fewer than the workflow's default: enough for the checks below, cheap
LENGTHS = {"input": 120.0, "output": 160.0}


@pytest.fixture(scope="module")
def library():
    rig = identification_rig()
    return rig, workflow.build_library(rig, paper_cases(), SweepSettings())


def document_probability(result, key):
    return discrepancy_document(result, LENGTHS, None, "test")["confidence"][key]


def _run(library, name, draws=DRAWS):
    rig, built = library
    data = rvcoax.read_measured(FOLDER / SETS[name]["file"])
    settings = workflow.DiscrepancySettings(confidence_draws=draws)
    library = built if built.cases == tuple(data.cases) else None
    return rig, data, settings, workflow.run_discrepancy(rig, data, settings, library=library)


def test_wilson_interval_matches_its_closed_form():
    """Wilson's 95 % score interval (Wilson 1927; e.g. Newcombe 1998, Stat. Med. 17, table I: 0/10 → 0–0.278,
    5/10 → 0.237–0.763, 10/10 → 0.722–1)."""
    assert confidence.wilson(0, 10) == pytest.approx((0.0, 0.2775), abs=5e-4)
    assert confidence.wilson(5, 10) == pytest.approx((0.2366, 0.7634), abs=5e-4)
    assert confidence.wilson(10, 10) == pytest.approx((0.7225, 1.0), abs=5e-4)
    assert confidence.wilson(0, 0) == (0.0, 1.0)


@pytest.mark.parametrize("name", ["oov_paths_1", "oov_table_1"])
def test_the_batched_sentinel_scan_is_the_sentinel_fit(library, name):
    """The draws' sentinel (every data set at once) finds the same best generic load as the workflow's own scan."""
    rig, built = library
    data = rvcoax.read_measured(FOLDER / SETS[name]["file"])
    settings = workflow.DiscrepancySettings(confidence_draws=0)
    observed = workflow._observe(rig, data, settings, built, None).observed
    fit = fit_sentinel(observed)
    scan = sentinel_scan(observed, np.vstack([observed.scaled_before, 2.0 * observed.scaled_before]))
    best = int(np.argmin(scan.bic[0]))
    assert scan.bic[0, best] == pytest.approx(fit.bic, rel=1e-9)
    assert (scan.site[best][0], scan.family[best]) == (fit.part, fit.family)  # (on a housing, sites may tie in x)
    assert np.min(scan.bic[1]) > np.min(scan.bic[0])  # a larger gap leaves more χ²


@pytest.mark.parametrize("name", ["position_error_paths_5", "oov_paths_1", "pair_table_5"])
def test_the_replay_gives_the_workflows_verdict_on_the_file_itself(library, name):
    """The draws are judged by a replay of the decision rules on the file's responses; on the file's own data it
    reaches the workflow's verdict (no gap, explained, unexplained for a load outside the vocabulary, ambiguous)."""
    _, _, _, result = _run(library, name)
    assert result.confidence is not None
    assert result.confidence.replay_verdict == result.verdict


def test_the_unexplained_bins_split_on_how_much_better_a_generic_load_fits():
    settings = workflow.DiscrepancySettings()
    margin = settings.bic_margin
    fits = {confidence._fit_class("unexplained", 5.0, gain, settings) for gain in (margin + 1, margin - 1)}
    assert len(fits) == 2  # the generic load's BIC advantage, not χ²/n, tells the two apart
    assert confidence._fit_class("explained", 0.5, margin + 1, settings) == confidence._quality_class(0.5)


def test_the_confidence_is_seeded_reported_and_within_its_interval(library):
    rig, data, settings, result = _run(library, "mesh_force_paths_5")
    c = result.confidence
    assert 0.0 <= c.low <= c.probability <= c.high <= 1.0
    assert DRAWS <= c.total_draws <= confidence.draw_limit(DRAWS) and 0 < c.draws <= c.total_draws and c.right <= c.draws
    assert sum(n for _, _, n in c.rates) == c.total_draws
    same = dict((v, n) for v, _, n in c.rates)[result.verdict]  # more drawn only while the verdict is rare
    assert same >= confidence.SAME_VERDICT or c.total_draws == confidence.draw_limit(DRAWS)
    assert c.total_draws == DRAWS or same - confidence.SAME_VERDICT < DRAWS // 2
    seen = workflow._observe(rig, data, settings, workflow.build_library(rig, data.cases, settings.sweep), None)
    again = confidence.verdict_confidence(seen, result, settings, DRAWS)
    assert (again.probability, again.draws, again.bin) == (c.probability, c.draws, c.bin)
    summary = engineering_summary(result, LENGTHS)
    assert summary[-1].startswith(f"confidence: the verdict '{result.verdict}' is right in")
    assert 0.0 <= document_probability(result, "logistic_probability") <= 1.0
    document = discrepancy_document(result, LENGTHS, None, "test")
    assert document["confidence"]["probability"] == pytest.approx(c.probability, abs=1e-4)
    assert document["confidence"]["draws"] == c.total_draws
    assert json.loads(json.dumps(document))["confidence"]["interval_95"][0] <= c.probability


def test_the_logistic_probability_model_recovers_a_known_rate_and_stays_cautious():
    """The probability model fitted on the draws: on data drawn from a known logistic law P = 1/(1 + e^-(1 + 2x)) it
    recovers the law's probabilities (to the sampling error of 2000 draws); a feature that never varies is ignored;
    draws that are all right give a high but not certain probability (the intercept's weak prior). The rate among the
    nearest draws follows the law too."""
    rng = np.random.default_rng(3)
    x = np.column_stack([rng.normal(size=2000), np.zeros(2000), rng.normal(size=2000)])
    truth = 1.0 / (1.0 + np.exp(-(1.0 + 2.0 * x[:, 0])))
    y = (rng.uniform(size=2000) < truth).astype(float)
    model = confidence._logistic(x, y)
    probe = np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    assert model(probe) == pytest.approx(1.0 / (1.0 + np.exp(-(1.0 + 2.0 * probe[:, 0]))), abs=0.04)
    assert np.isfinite(model(probe)).all()
    p = confidence._logistic(x[:40], np.ones(40))(probe[1:2])[0]
    assert 0.9 < p < 1.0
    near = confidence._nearest_rate(x, y, probe[2:3])  # the rate among the draws near x = 1: about the law's 0.95
    assert near == pytest.approx(1.0 / (1.0 + np.exp(-3.0)), abs=0.06)


def test_no_confidence_when_asked_for_none(library):
    _, _, _, result = _run(library, "none_paths_1", draws=0)
    assert result.confidence is None
    assert not any(line.startswith("confidence") for line in engineering_summary(result, LENGTHS))


@pytest.mark.parametrize("name", ["mesh_force_paths_5", "oov_paths_1"])
def test_the_draws_hide_what_the_files_own_fit_supports(library, name):
    """The draws hide the explanations the file's data do not exclude (BIC within the workflow's margin of the best):
    the effect the workflow names on a CalculiX mesh-force file, a generic load on a file with a load outside the
    vocabulary; the drawn truths are among them."""
    rig, data, settings, result = _run(library, name, draws=0)
    seen = workflow._observe(rig, data, settings, library[1] if library[1].cases == tuple(data.cases) else None, None)
    vocabulary = confidence._vocabulary(seen)
    replay = confidence._Replay(vocabulary, seen.observed, settings)
    scaled = ((data.value_mm - seen.observed.before) / seen.observed.sigma)[None, :]
    supported = confidence._supported(replay, scaled, settings)
    best = min(h.bic for h in supported)
    assert all(h.bic <= best + settings.bic_margin for h in supported)
    kinds = {h.kind for h in supported}
    named = {replay.names[c] for h in supported for c, _ in h.members}
    if SETS[name]["group"] == "out_of_vocabulary":
        assert result.verdict == "unexplained" and "outside" in kinds
    else:
        assert result.verdict == "explained" and result.selected[0].name in named and "none" not in kinds
    drawer = confidence._Drawer(seen, vocabulary, settings, np.random.default_rng(1), supported)
    for _ in range(20):
        _, truth = drawer.draw()
        assert truth.kind in kinds and set(truth.names) <= named
