"""``--scheduler auto``: serial for small studies, a local cluster only where the estimated work pays for it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rvcoax.geometry.rigfile import load_rig
from rvcoax.results.studies.distributed import (
    CLUSTER_START_SECONDS,
    PAYS_BELOW,
    TASK_OVERHEAD_SECONDS,
    choose_scheduler,
    run_samples,
)
from rvcoax.results.studies.montecarlo import evaluate_sample, plan_study
from rvcoax.results.studies.sampling import sample_values
from rvcoax.results.studies.tolerances import load_tolerances

EXAMPLE = Path(__file__).resolve().parents[2] / "loadcases" / "data" / "example_tolerances.toml"


def test_two_cores_always_run_serially():
    # measured on 2 cores: 2 workers gave 0.71x (beam) and 0.79x (hybrid) of the serial rate
    for n, per_sample in ((64, 0.34), (20_000, 0.0126), (8, 14.6), (10_000, 14.6)):
        assert choose_scheduler(n, per_sample, setup_seconds=1.0, cores=2).scheduler == "serial"


def test_many_cores_pay_for_large_studies_only():
    small = choose_scheduler(64, 0.0126, setup_seconds=0.1, cores=16)
    assert small.scheduler == "serial" and small.serial_seconds == pytest.approx(64 * 0.0126)
    large = choose_scheduler(2000, 14.6, setup_seconds=33.0, cores=16)
    assert large.scheduler == "local"
    assert large.cluster_seconds == pytest.approx(CLUSTER_START_SECONDS + 33.0 + 2000 * (14.6 + TASK_OVERHEAD_SECONDS) / 15)
    # the break-even: the cluster's start and set-up against the work the extra workers take over
    workers = 7  # 8 cores, one for the client and scheduler
    setup, per_sample = 5.0, 1.0
    share = (per_sample + TASK_OVERHEAD_SECONDS) / workers  # cluster time per sample
    break_even = (CLUSTER_START_SECONDS + setup) / (PAYS_BELOW * per_sample - share)
    assert choose_scheduler(int(break_even) - 1, per_sample, setup, cores=8).scheduler == "serial"
    assert choose_scheduler(int(break_even) + 2, per_sample, setup, cores=8).scheduler == "local"
    assert "serial" in small.describe() and "local cluster" in small.describe()


def test_small_study_runs_serially_by_default_with_the_serial_results(tmp_path):
    rig = load_rig()
    tolerances = load_tolerances(EXAMPLE, rig)
    study = plan_study(rig, tolerances)
    values = sample_values(tolerances.distributions, 6, "lhs", seed=3)
    auto, auto_run = run_samples(evaluate_sample, study, values, tmp_path / "auto", "auto-6", scheduler="auto")
    serial, serial_run = run_samples(evaluate_sample, study, values, tmp_path / "serial", "serial-6", scheduler="serial")
    assert auto_run.scheduler == "serial" and auto_run.choice is not None and auto_run.choice.scheduler == "serial"
    assert auto_run.computed == serial_run.computed == 6 and auto_run.workers == 1
    assert auto == serial  # the same floats, in sample order
    assert serial_run.choice is None
    assert np.isfinite(auto_run.choice.serial_seconds) and auto_run.choice.cluster_seconds > CLUSTER_START_SECONDS
