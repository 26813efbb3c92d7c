"""The rig and the synthetic measurements of the discrepancy tests and benchmark.

The rig is the reference rig with Y measured from the unloaded geometry (so load-independent
effects are observable), self-weight off (so ``self_weight`` is a candidate) and Euler–Bernoulli
shafts (so ``shear_deformation`` is one). The data come from the rig *with* a hidden effect.
"""

from __future__ import annotations

from rvcoax.geometry.rigfile import load_rig
from rvcoax.geometry.schema import Rig
from rvcoax.loadcases.cases import paper_cases
from rvcoax.results.studies.discrepancy.synthetic import effect_size_for, observation_layout, synthetic_data

__all__ = ["LENGTHS", "STATIONS", "discrepancy_rig", "hidden_data"]

LENGTHS = {"input": 120.0, "output": 160.0}
STATIONS = 11


def discrepancy_rig(reference: Rig | None = None) -> Rig:
    """``reference`` (default: the reference rig) measured from the unloaded geometry, self-weight off, Euler–Bernoulli."""
    data = (reference or load_rig()).model_dump(by_alias=True)
    data["paths"]["measured_from"] = "unloaded"
    data["gravity"]["enabled"] = False
    data["beam"]["shear_deformation"] = False
    return Rig.model_validate(data)


def hidden_data(rig, effects, name, schema, noise, seed, fraction=0.3):
    """Measured data of ``rig`` with effect ``name`` (None: nothing hidden) at ``fraction`` of the signal, plus noise."""
    template = observation_layout(paper_cases(), STATIONS, LENGTHS, schema)
    truth = rig if name is None else effects[name].apply(
        rig, [effect_size_for(effects[name], rig, paper_cases(), template, fraction)])
    return synthetic_data(truth, template, noise, seed)
