"""The command applies the C heap's policy (rvcoax.fem.memory) to the model it prepares, from the preflight estimate."""

from __future__ import annotations

import rvcoax.fem
from rvcoax import SweepSettings, load_rig
from rvcoax.geometry.model.preflight import peak_memory_bytes
from rvcoax.results.cli import support


def test_preparing_a_model_sets_the_heap_policy_from_its_estimated_peak(monkeypatch):
    asked = []
    monkeypatch.setattr(rvcoax.fem, "apply_heap_policy", lambda peak: asked.append(peak))  # nothing set in this process
    rig = load_rig()
    prepared = support.prepare_with_status(rig, SweepSettings(model="beam"))
    assert asked == [peak_memory_bytes(rig, "beam")]
    assert prepared.system.n_dofs > 0
