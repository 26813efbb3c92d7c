"""Tolerance studies: tolerance files, sampling, Monte Carlo and sensitivity, run serially and through Dask.

A module-scoped :class:`distributed.LocalCluster` (2 worker processes on loopback) serves the
cluster tests; the test that kills a worker runs last on it.
"""

from __future__ import annotations

import json
import logging
import math
import os
import signal
import time
from pathlib import Path

import numpy as np
import pytest
from scipy import stats
from typer.testing import CliRunner

from rvcoax.geometry.rigfile import load_rig
from rvcoax.results.cli.app import app
from rvcoax.results.studies.distributed import ResumeError, future_outcome, run_samples, sample_path
from rvcoax.results.studies.montecarlo import (
    Study,
    classify_parameter,
    evaluate_sample,
    exceedance,
    plan_study,
    stack_records,
)
from rvcoax.results.studies.sampling import Distribution, sample_values, to_values, unit_design
from rvcoax.results.studies.sensitivity import morris_design, morris_indices, morris_values, sobol_design, sobol_indices
from rvcoax.results.studies.tolerances import ToleranceFileError, load_tolerances, parse_tolerances

# cost, for `make test-fast` (-m "not slow and not dask and not render")
pytestmark = [pytest.mark.dask, pytest.mark.slow, pytest.mark.xdist_group("dask-cluster")]  # one worker, one cluster, in order

EXAMPLE = Path(__file__).resolve().parents[3] / "loadcases" / "data" / "example_tolerances.toml"
RIG = load_rig()

CRANK_ERROR = "torque_lateral_loads.crankshaft_load_sharing.position_error_um"
LOAD_ONLY = f"""
schema_version = 1
[study]
name = "one normal load parameter"
measured_from = "aligned_at_rest"
[[cases]]
T1_input_Nm = 1.43
T2_output_Nm = 200
[[parameters]]
address = "{CRANK_ERROR}"
distribution = "normal"
mean_um = 0.0
std_um = 1.0
source = "test"
[[limits]]
shaft = "output"
Y_max_mm = 0.0005
"""


def parameter_block(address: str, body: str) -> str:
    return f'schema_version = 1\n[study]\nname = "t"\n[[parameters]]\naddress = "{address}"\n{body}\n'


@pytest.fixture(scope="module")
def example():
    return load_tolerances(EXAMPLE, RIG)


@pytest.fixture(scope="module")
def example_study(example):
    return plan_study(RIG, example)


@pytest.fixture(scope="module")
def cluster():
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, silence_logs=logging.ERROR) as local:
        yield local


# --- tolerance files -------------------------------------------------------------------------


def test_example_file_is_valid_and_tagged(example):
    assert example.measured_from == "unloaded"
    assert len(example.parameters) >= 10
    assert all(p.source.startswith("[") for p in example.parameters)  # every distribution is tagged
    keys = {p.address.rsplit(".", 1)[1] for p in example.parameters}
    assert {"parallel_offset_um", "angular_misalignment_mrad", "vertical_offset_um"} <= keys
    limits = {x.shaft: x for x in example.limits}
    assert limits["input"].beta_deg == pytest.approx(math.degrees(math.asin(0.002 / 120)), rel=1e-12)
    assert limits["output"].beta_deg == pytest.approx(math.degrees(math.asin(0.003 / 160)), rel=1e-12)
    assert [(c.input_torque_Nm, c.output_torque_Nm) for c in example.cases] == [(1.43, 200.0), (0.07, 10.0)]


@pytest.mark.parametrize("text, expected", [
    (parameter_block("bearings.input_B1.radial_stiffness_N_per_um",
                     'distribution = "normal"\nmean_N_per_um = 50\nstd_N_per_mm = 5'),
     "parameters[0] ('bearings.input_B1.radial_stiffness_N_per_um').std_N_per_mm: unit N_per_mm, but the "
     "parameter is in N_per_um; write std_N_per_um"),
    (parameter_block("bearings.input_B1.radial_stiffness_N_per_um", 'distribution = "normal"\nmean = 50\nstd = 5'),
     "mean: no unit, but the parameter is in N_per_um; write mean_N_per_um"),
    (parameter_block("bearings.nowhere.radial_stiffness_N_per_um", 'distribution = "uniform"\nlow_N_per_um = 40\n'
                     'high_N_per_um = 60'), "parameters[0] ('bearings.nowhere.radial_stiffness_N_per_um').address: "
                                            "no bearing named 'nowhere'"),
    (parameter_block("bearings.input_B1.radial_stiffness_N_per_um",
                     'distribution = "normal"\nmean_N_per_um = 50\nstd_N_per_um = 10'),
     "the distribution reaches -32.0954, which the rig rejects: Input should be greater than 0 (use truncated_normal"),
    (parameter_block("bearings.input_B1.radial_stiffness_N_per_um", 'distribution = "uniform"\nlow_N_per_um = 60\n'
                     'high_N_per_um = 40'), "high (40.0) must be greater than low (60.0)"),
    (parameter_block("torque_lateral_loads.sun_gear_load_sharing.imbalance", 'distribution = "uniform"\nlow = 0\n'
                     'high = 0.1\n[[limits]]\nshaft = "input"\nY_max_mm = 0.002\nbeta_deg = 0.001'),
     "limits[0]: give exactly one of Y_max_mm"),
    (parameter_block("torque_lateral_loads.sun_gear_load_sharing.imbalance", 'distribution = "triangular"'),
     "parameters[0] ('torque_lateral_loads.sun_gear_load_sharing.imbalance').distribution: Input should be"),
])
def test_tolerance_file_errors_name_the_key(text, expected):
    with pytest.raises(ToleranceFileError) as raised:
        parse_tolerances(text, "bad.toml", RIG)
    message = str(raised.value)
    assert message.startswith("tolerance file bad.toml:")
    assert expected in " ".join(message.split()), message


# --- sampling and reuse ---------------------------------------------------------------------------


def test_sampling_is_seeded_stratified_and_respects_bounds():
    laws = (Distribution("normal", mean=1.0, std=0.1), Distribution("uniform", low=-2.0, high=3.0),
            Distribution("truncated_normal", mean=0.0, std=1.0, low=-0.5, high=2.0))
    a, b = sample_values(laws, 64, "lhs", seed=7), sample_values(laws, 64, "lhs", seed=7)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, sample_values(laws, 64, "lhs", seed=8))
    unit = unit_design(64, 3, "lhs", seed=7)
    for j in range(3):  # a Latin hypercube has one point in each of the 64 strata of every column
        assert sorted(np.floor(unit[:, j] * 64).astype(int)) == list(range(64))
    assert np.all((a[:, 1] >= -2.0) & (a[:, 1] <= 3.0)) and np.all((a[:, 2] >= -0.5) & (a[:, 2] <= 2.0))
    assert np.allclose(a, to_values(laws, unit))
    with pytest.raises(ValueError, match="power of two"):
        unit_design(100, 3, "sobol")


def test_reuse_strategy_found_per_parameter():
    assert classify_parameter(RIG, CRANK_ERROR, 1.0) == "loads"
    assert classify_parameter(RIG, "couplings.C3.parallel_offset_um", 20.0) == "loads"
    assert classify_parameter(RIG, "bearings.input_B1.radial_stiffness_N_per_um", 60.0) == "frame"
    assert classify_parameter(RIG, "couplings.C3.mass_kg", 1.2) == "full"  # self-weight changes
    assert classify_parameter(RIG, "parts.output_shaft.outer_diameter_deviation_mm", 0.02) == "full"


def test_reused_model_gives_the_fresh_solution_exactly(example, example_study):
    """A sample solved on the reused model equals the same sample assembled and solved from scratch."""
    study = example_study
    assert study.strategy == "frame"
    full = Study(study.rig, study.cases, study.settings, study.addresses, "full", study.key + "-full")
    values = sample_values(example.distributions, 3, "lhs", seed=3)
    for row in values:
        assert evaluate_sample(study, row) == evaluate_sample(full, row)
    from rvcoax.results.studies import montecarlo

    kept = montecarlo._MEMO[study.key]  # every sample factorises its own matrix: no factor of the nominal one is made
    assert kept.prepared is None and kept.system.stiffness.shape[0] > 0


# --- Dask execution ---------------------------------------------------------------------------


def _example_run(study, folder, scheduler, n=40, **options):
    values = sample_values(tuple(_EXAMPLE_LAWS), n, "lhs", seed=11)
    return run_samples(evaluate_sample, study, values, folder, f"example-{n}", scheduler=scheduler, **options)


_EXAMPLE_LAWS = load_tolerances(EXAMPLE, RIG).distributions


def test_local_cluster_gives_the_serial_results(example_study, cluster, tmp_path):
    serial, serial_run = _example_run(example_study, tmp_path / "serial", "serial")
    parallel, parallel_run = _example_run(example_study, tmp_path / "cluster", cluster.scheduler_address)
    assert parallel_run.workers == 2 and serial_run.workers == 1
    assert parallel == serial  # exactly: the same floats, in sample order
    assert len(list((tmp_path / "cluster").glob("sample_*.json"))) == 40


def test_cli_against_a_cluster_address_equals_serial(cluster, tmp_path):
    common = ["--tolerances", str(EXAMPLE), "--samples", "24", "--seed", "5"]
    runner = CliRunner()
    for name, scheduler in (("serial", "serial"), ("cluster", cluster.scheduler_address)):
        result = runner.invoke(app, ["montecarlo", *common, "--scheduler", scheduler, "--out", str(tmp_path / name)])
        assert result.exit_code == 0, (result.output, result.exception)
    for name in ("montecarlo_samples.csv", "montecarlo_distribution.csv", "montecarlo_exceedance.csv"):
        assert (tmp_path / "serial" / name).read_bytes() == (tmp_path / "cluster" / name).read_bytes()
    assert (tmp_path / "cluster" / "montecarlo_beta_histogram.png").stat().st_size > 10_000
    document = json.loads((tmp_path / "cluster" / "montecarlo.json").read_text())
    assert document["strategy"]["name"] == "frame" and document["run"]["workers"] == 2
    assert document["measured_from"] == "unloaded"

    result = runner.invoke(app, ["sensitivity", "--tolerances", str(EXAMPLE), "--method", "morris", "--samples", "3",
                                 "--scheduler", cluster.scheduler_address, "--out", str(tmp_path / "morris")])
    assert result.exit_code == 0, (result.output, result.exception)
    assert "tighten first" in result.output
    assert (tmp_path / "morris" / "sensitivity_indices.png").stat().st_size > 10_000


def test_resume_computes_only_missing_samples(example_study, tmp_path):
    first, _ = _example_run(example_study, tmp_path, "serial", n=12)
    sample_path(tmp_path, 3).unlink()
    sample_path(tmp_path, 7).write_text("{ half a file")
    again, report = _example_run(example_study, tmp_path, "serial", n=12, resume=True)
    assert (report.resumed, report.computed) == (10, 2)
    assert again == first
    study = example_study
    with pytest.raises(ResumeError, match="another study"):
        run_samples(evaluate_sample, study, np.zeros((12, len(study.addresses))), tmp_path, "other", scheduler="serial",
                    resume=True)


def test_cli_errors_exit_2_with_a_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(parameter_block("bearings.input_B1.radial_stiffness_N_per_um",
                                   'distribution = "uniform"\nlow_um = 40\nhigh_um = 60'))
    runner = CliRunner()
    cases = [
        (["montecarlo", "--tolerances", str(bad)], "low_um: unit um, but the parameter is in N_per_um"),
        (["montecarlo", "--tolerances", str(EXAMPLE), "--sampling", "sobol", "--samples", "100"], "power of two"),
        (["montecarlo", "--tolerances", str(EXAMPLE), "--scheduler", "somewhere"], "--scheduler"),
        (["sensitivity", "--tolerances", str(EXAMPLE), "--samples", "100"], "power of two"),
        (["sensitivity", "--tolerances", str(tmp_path / "missing.toml")], "file not found"),
    ]
    for args, expected in cases:
        result = runner.invoke(app, [*args, "--out", str(tmp_path / "out")])
        assert result.exit_code == 2, (args, result.output)
        assert expected in " ".join(result.output.split()), result.output
        assert "Traceback" not in result.output


# --- statistics with known answers ------------------------------------------------------------


def test_sobol_indices_of_the_ishigami_function():
    a, b = 7.0, 0.1
    variance = a * a / 8 + b * np.pi**4 / 5 + b * b * np.pi**8 / 18 + 0.5
    v1 = 0.5 * (1 + b * np.pi**4 / 5) ** 2
    v2 = a * a / 8
    v13 = b * b * np.pi**8 * (1 / 18 - 1 / 50)
    exact_s1 = np.array([v1, v2, 0.0]) / variance
    exact_st = np.array([v1 + v13, v2, v13]) / variance
    laws = (Distribution("uniform", low=-np.pi, high=np.pi),) * 3

    def ishigami(x):
        return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])

    points = sobol_design(4096, 3, seed=2)
    found = sobol_indices(ishigami(to_values(laws, points)), 3, seed=2)
    assert np.all(np.abs(found.S1 - exact_s1) <= found.S1_conf), (found.S1, exact_s1, found.S1_conf)
    assert np.all(np.abs(found.ST - exact_st) <= found.ST_conf), (found.ST, exact_st, found.ST_conf)
    assert np.all(found.S1_conf < 0.05)
    morris_points = morris_design(40, 3, seed=2)
    screening = morris_indices(morris_points, ishigami(morris_values(laws, morris_points)), seed=2)
    assert screening.mu_star[2] < screening.mu_star[0] and screening.mu_star[2] < screening.mu_star[1]
    assert screening.sigma[2] > 0.5 * screening.mu_star[2]  # x3 acts only through its interaction with x1


def test_exceedance_of_one_linear_normal_parameter_matches_the_closed_form():
    """Y_output = |a + c ε| with ε ~ N(0, 1 µm): P(Y > Y_lim) = 1 − Φ((Y_lim − a)/c) + Φ((−Y_lim − a)/c)."""
    tolerances = parse_tolerances(LOAD_ONLY, "load-only.toml", RIG)
    study = plan_study(RIG, tolerances)
    assert study.strategy == "loads"

    def y_output(error_um):
        return evaluate_sample(study, [error_um])["Y_signed_mm"][0][1]

    a, c = y_output(0.0), y_output(1.0) - y_output(0.0)
    assert y_output(-2.5) == pytest.approx(a - 2.5 * c, rel=1e-9)  # linear in the parameter
    limit = tolerances.limits[0]
    y_limit = 160.0 * math.sin(math.radians(limit.beta_deg))
    exact = (1 - stats.norm.cdf((y_limit - a) / abs(c))) + stats.norm.cdf((-y_limit - a) / abs(c))
    assert 0.1 < exact < 0.6
    values = sample_values(tolerances.distributions, 1000, "lhs", seed=4)
    records = [evaluate_sample(study, row) for row in values]
    found = exceedance(stack_records(records, "beta_deg")[:, 0, 1], limit.beta_deg, 0.95)
    assert found.lower <= exact <= found.upper, (found, exact)
    assert found.upper - found.lower < 0.07


def test_wilson_interval_edges():
    none = exceedance(np.zeros(50), 1.0)
    assert none.probability == 0.0 and none.lower == 0.0 and 0.05 < none.upper < 0.08  # 3.84/53.84 = 0.071
    every = exceedance(np.ones(50), 0.5)
    assert every.probability == 1.0 and every.upper == 1.0


# --- a worker dies (last: it restarts one of the cluster's workers) -----------------------------


def test_killed_worker_loses_only_its_in_flight_samples(cluster, tmp_path):
    from distributed import Client

    tolerances = parse_tolerances(LOAD_ONLY, "load-only.toml", RIG)
    study = plan_study(RIG, tolerances)
    values = sample_values(tolerances.distributions, 200, "lhs", seed=9)
    serial, _ = run_samples(evaluate_sample, study, values, tmp_path / "serial", "kill", scheduler="serial")
    with Client(cluster.scheduler_address) as client:
        before = client.run(os.getpid)
        victim = sorted(before.values())[0]
        killed = []

        def kill_once(index, result):
            if not killed:  # at the first result: the victim still holds most of its samples
                os.kill(victim, signal.SIGKILL)
                killed.append(index)

        results, report = run_samples(evaluate_sample, study, values, tmp_path / "cluster", "kill",
                                      scheduler=cluster.scheduler_address, on_result=kill_once)
        client.wait_for_workers(2, timeout=120)
        after = client.run(os.getpid)
    assert killed and victim not in after.values()  # the worker died mid-run and the nanny replaced it
    assert report.computed == 200 and results == serial
    assert len(list((tmp_path / "cluster").glob("sample_*.json"))) == 200


def test_result_lost_with_its_worker_after_completing_is_waited_for(cluster):
    """The race behind a CI failure: a task completes, then the worker holding its result dies.

    The future goes from ``finished`` back to ``lost``/``pending`` and is computed again; reading
    it as failed (its ``exception()`` is ``None`` once the re-run finishes) aborted a whole sweep.
    """
    from distributed import Client

    with Client(cluster.scheduler_address) as client:
        terms = 40_000_000  # about a second of work, so the second run can be watched
        future = client.submit(sum, range(terms), pure=False)
        assert future.result() == terms * (terms - 1) // 2
        holder = client.who_has([future])[future.key][0]
        os.kill(client.run(os.getpid, workers=[holder])[holder], signal.SIGKILL)
        deadline = time.monotonic() + 60
        while future.status == "finished" and time.monotonic() < deadline:
            time.sleep(0.02)
        assert future.status != "finished"  # the client has heard that the result is gone
        assert future_outcome(future) == (terms * (terms - 1) // 2, None)
        client.wait_for_workers(2, timeout=120)
