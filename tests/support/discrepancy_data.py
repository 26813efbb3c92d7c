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

__all__ = ["LENGTHS", "STATIONS", "claims_what_the_data_carry", "discrepancy_rig", "finer", "hidden_data",
           "write_cli_inputs"]

LENGTHS = {"input": 120.0, "output": 160.0}
STATIONS = 11


def discrepancy_rig(reference: Rig | None = None) -> Rig:
    """``reference`` (default: the reference rig) measured from the unloaded geometry, self-weight off, Euler–Bernoulli."""
    data = (reference or load_rig()).model_dump(by_alias=True)
    data["paths"]["measured_from"] = "unloaded"
    data["gravity"]["enabled"] = False
    data["beam"]["shear_deformation"] = False
    return Rig.model_validate(data)



def identification_rig(datum: str = "aligned_at_rest") -> Rig:
    """The beam model the workflow identifies CalculiX and hybrid-model data with: Timoshenko shafts (their elements and
    solid shafts deform in shear), Y from ``datum`` (default: the rig aligned at rest)."""
    data = discrepancy_rig().model_dump(by_alias=True)
    data["paths"]["measured_from"] = datum
    data["beam"]["shear_deformation"] = True
    return Rig.model_validate(data)


def finer(rig: Rig) -> Rig:
    """The same rig meshed with beam elements of at most 2 mm (the identifying model uses 5 mm)."""
    data = rig.model_dump(by_alias=True)
    data["mesh"]["max_element_length_mm"] = 2.0
    return Rig.model_validate(data)


def hidden_data(rig, effects, name, schema, noise, seed, fraction=0.3):
    """Measured data of ``rig`` with effect ``name`` (None: nothing hidden) at ``fraction`` of the signal, plus noise."""
    template = observation_layout(paper_cases(), STATIONS, LENGTHS, schema)
    truth = rig if name is None else effects[name].apply(
        rig, [effect_size_for(effects[name], rig, paper_cases(), template, fraction)])
    return synthetic_data(truth, template, noise, seed)


def write_cli_inputs(tmp_path, rig: Rig, data):
    """The rig as a TOML file and ``data`` as a paths CSV, for the command (returns both paths)."""
    from rigdata import dump_toml

    rig_file = tmp_path / "rig.toml"
    rig_file.write_text(dump_toml(rig.model_dump(by_alias=True, exclude_none=True, mode="json")), encoding="utf-8")
    lines = ["T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm"]
    for i in range(data.n):
        case = data.cases[data.case_index[i]]
        lines.append(f"{case.input_torque_Nm},{case.output_torque_Nm},{data.shaft[i]},{data.x_mm[i]:.6g},"
                     f"{data.value_mm[i]:.9e}")
    measured = tmp_path / "measured.csv"
    measured.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return rig_file, measured


def claims_what_the_data_carry(result) -> bool:
    """An answer with a named explanation: ``explained`` with groups of at most three look-alikes, or ``ambiguous``
    with its reasons and a description of each larger group (issue 28)."""
    from rvcoax.results.studies.discrepancy.judge import AMBIGUOUS_GROUP

    if result.verdict == "explained":
        return all(len(s.group) <= AMBIGUOUS_GROUP for s in result.selected)
    if result.verdict == "ambiguous":
        described = {a.effect for a in result.ambiguities}
        return bool(result.reasons) and all(s.name in described for s in result.selected
                                            if len(s.group) > AMBIGUOUS_GROUP)
    return False


def relative_gap_to_the_model(rig: Rig, data) -> dict[str, float]:
    """Per measured shaft, RMS(measured − model) / RMS(model) of ``data`` against ``rig``'s beam model: how far a
    file made by another code or discretisation sits from the identification model."""
    import numpy as np

    from rvcoax.geometry import MEASURED_SHAFTS
    from rvcoax.results.studies.discrepancy.responses import Observation, solve_full_paths
    from rvcoax.results.sweep import SweepSettings

    paths, layout = solve_full_paths(rig, data.cases, SweepSettings())
    model = Observation(data, layout)(paths)
    out = {}
    for shaft in MEASURED_SHAFTS:
        mask = data.shaft == shaft
        out[shaft] = float(np.sqrt(np.mean((data.value_mm - model)[mask] ** 2)) / np.sqrt(np.mean(model[mask] ** 2)))
    return out


def assert_honest_answer(result, truth: set[str]) -> None:
    """The answer covers ``truth``, claims no more than the data carry, and names nothing else with confidence."""
    named = {n for s in result.selected for n in (s.name, *s.group)}
    misnamed = [s.name for s in result.selected if s.confident and len(s.group) <= 1 and s.name not in truth]
    assert not misnamed, misnamed
    assert claims_what_the_data_carry(result) and truth <= named, (result.verdict, result.reasons, named)
