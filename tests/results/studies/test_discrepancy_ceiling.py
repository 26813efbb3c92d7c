"""The blind benchmark's oracle (``benchmarks/bench_discrepancy_ceiling.py``) on closed forms.

Forty observations with σ = 1 read the paths directly (a linear observation, as a paths file is), and effects whose
signatures are chosen: one exactly proportional to the truth's (no data can tell them apart: the smallest honest group
holds both), one orthogonal to it (the data exclude it by χ² = ‖truth‖²), and two that only together make the truth's
signature (a pair that earns both its parameters). The detection rule is the gap test's: a noise-free change is
detectable when ‖s‖² lifts the expected χ² (n) to the test's critical value; χ²₀.₉₉(40) = 63.691 (NIST/SEMATECH
e-Handbook of Statistical Methods, table 1.3.6.7.4, upper critical values of the chi-square distribution), so the
threshold on 40 rows at α = 0.01 is √23.691 = 4.867 σ.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from rvcoax.geometry.effects import Effect, EffectParameter
from rvcoax.results.studies.discrepancy.identify import Problem
from rvcoax.results.studies.discrepancy.responses import EffectResponse
from rvcoax.results.studies.discrepancy.workflow import DiscrepancySettings

SCRIPT = Path(__file__).resolve().parents[3] / "benchmarks" / "bench_discrepancy_ceiling.py"
N = 40
SETTINGS = DiscrepancySettings(confidence_draws=0)


@pytest.fixture(scope="module")
def ceiling():
    spec = importlib.util.spec_from_file_location("bench_discrepancy_ceiling", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


class DirectReading:
    """Observations that are the path values themselves (a linear observation operator, like a paths file's)."""

    def __init__(self, n: int):
        self.matrix = sp.identity(n, format="csr")

    def __call__(self, paths):
        return self.matrix @ paths

    def jacobian(self, paths):
        return self.matrix


def _response(name: str, column: np.ndarray) -> EffectResponse:
    effect = Effect(name, name, None, (EffectParameter("size", "1", -1.0, 1.0, 0.5),), True,
                    f"closed-form effect {name}")
    return EffectResponse(effect, "linear", columns=column[None, :])


@pytest.fixture(scope="module")
def problem():
    x = np.linspace(0.0, 1.0, N)
    a = np.sin(np.pi * x)
    a *= 20.0 / np.linalg.norm(a)  # ‖a‖ = 20 σ
    c = np.cos(np.pi * x) - (np.cos(np.pi * x) @ a) / (a @ a) * a  # orthogonal to a
    c *= 10.0 / np.linalg.norm(c)
    columns = {"truth": a, "proportional": 2.0 * a, "orthogonal": c, "left": a + c, "right": -c}
    base = np.full(N, 5.0)  # the base model's signal: 2 % of it (‖·‖ = 31.6) is 0.63 σ, below every difference here
    measured = base + 0.5 * a  # noise-free: the truth at half its bound
    return Problem(measured, np.ones(N), base, DirectReading(N), {n: _response(n, v) for n, v in columns.items()})


def test_the_detection_rule_is_the_gap_tests(ceiling):
    threshold = np.sqrt(63.691 - N)  # NIST table 1.3.6.7.4: χ²₀.₉₉(40) = 63.691
    unit = np.ones(N) / np.sqrt(N)
    seen, norm, rule = ceiling.detectable(1.02 * threshold * unit, SETTINGS.alpha)
    assert rule == pytest.approx(threshold, rel=1e-3)
    assert seen and norm == pytest.approx(1.02 * threshold)
    assert not ceiling.detectable(0.98 * threshold * unit, SETTINGS.alpha)[0]


def test_a_proportional_signature_cannot_be_excluded_an_orthogonal_one_can(ceiling, problem):
    fit = ceiling.truth_fit(problem, ("truth",), {"truth": 0.5})
    assert fit.chi2 == pytest.approx(0.0, abs=1e-9) and float(fit.values[0][0]) == pytest.approx(0.5)
    reference = (fit.bic, problem.observe(problem.paths(fit.names, fit.values)))
    found = ceiling.alternatives(problem, ("truth",), ["proportional", "orthogonal"], SETTINGS, reference=reference)
    assert [names for names, _ in found] == [("proportional",)]  # same χ² (0) at a quarter of its bound
    assert ceiling.groups_of(("truth",), found) == (("truth", "proportional"),)
    # the orthogonal one alone is excluded by χ² = ‖0.5 a‖² = 100 against the margin of 6
    alone = problem.fit(("orthogonal",))
    assert alone.chi2 == pytest.approx(100.0, rel=1e-9)


def test_a_pair_that_makes_the_truths_signature_joins_the_group_when_pairs_count(ceiling, problem):
    fit = ceiling.truth_fit(problem, ("truth",), {"truth": 0.5})
    reference = (fit.bic, problem.observe(problem.paths(fit.names, fit.values)))
    found = ceiling.alternatives(problem, ("truth",), ["orthogonal", "left", "right"], SETTINGS, reference=reference)
    # left + right at 0.5 each is 0.5 a exactly (BIC 2 ln 40 = 7.4 against the truth's 3.7: within 6); each alone
    # leaves χ² = 100 sin²θ = 20 (left) and 100 (right): the pair earns both its parameters. "orthogonal" is −right:
    # left + orthogonal is the same hypothesis on these data, and the group grows beyond three
    assert sorted(names for names, _ in found) == [("left", "orthogonal"), ("left", "right")]
    assert ceiling.groups_of(("truth",), found) == (("truth", "left", "orthogonal", "right"),)


def test_groups_of_a_true_pair(ceiling):
    truth = ("a", "b")
    # a swap of one member joins that member's group; a pair replacing both puts one effect in each group; a single
    # that replaces the whole pair says the data do not show two effects
    assert ceiling.groups_of(truth, [(("a", "x"), 0.0)]) == (("a",), ("b", "x"))
    assert ceiling.groups_of(truth, [(("a", "x"), 0.0), (("y", "x"), 0.0)]) == (("a", "y"), ("b", "x"))
    groups = ceiling.groups_of(truth, [(("z",), 0.0)])
    assert ceiling.NOTHING in groups[0] + groups[1]


def test_the_model_form_clause_groups_what_the_margin_separates(ceiling):
    """On a large signal (‖base‖ = 632 σ) a look-alike a + 2d (d ⟂ a, ‖a‖ = 20, ‖d‖ = 5) fitted to 0.5 a stops at
    0.4 and leaves 0.1 a − 0.8 d: χ² = 4 + 16 = 20, excluded by the BIC margin (6), but its predictions are √20 = 4.5 σ
    from the truth's, within the model-form clause (2 % of 632 σ = 12.6 σ)."""
    x = np.linspace(0.0, 1.0, N)
    a = np.sin(np.pi * x)
    a *= 20.0 / np.linalg.norm(a)
    d = np.cos(np.pi * x) - (np.cos(np.pi * x) @ a) / (a @ a) * a
    d *= 5.0 / np.linalg.norm(d)
    base = np.full(N, 100.0)
    columns = {"truth": a, "near": a + 2.0 * d}
    problem = Problem(base + 0.5 * a, np.ones(N), base, DirectReading(N), {n: _response(n, v) for n, v in columns.items()})
    fit = ceiling.truth_fit(problem, ("truth",), {"truth": 0.5})
    reference = (fit.bic, problem.observe(problem.paths(fit.names, fit.values)))
    near = problem.fit(("near",))
    assert near.chi2 == pytest.approx(20.0, rel=1e-9) and float(near.values[0][0]) == pytest.approx(0.4)
    assert ceiling.alternatives(problem, ("truth",), ["near"], SETTINGS, reference=reference) == []
    assert [n for n, _ in ceiling.alternatives(problem, ("truth",), ["near"], SETTINGS, reference=reference,
                                               model_form=True)] == [("near",)]
