"""Rig → model pieces → assembled system: the beam, hybrid and solid models of a rig, its unit loads, and the
checks made before a model is solved (sizes, memory, sag).

Public names (loaded on first use): the assembled system and how to build it, and the size checks
that refuse or announce work before it starts.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "MODEL_KINDS": "rvcoax.geometry.model.system",
    "assemble_rig": "rvcoax.geometry.model.assemble",
    "RigSystem": "rvcoax.geometry.model.system",
    "build_rig_model": "rvcoax.geometry.model.beam",
    "gear_mesh_forces": "rvcoax.geometry.model.loads",
    "sag_warnings": "rvcoax.geometry.model.preflight",
    "REPORT_AFTER_S": "rvcoax.geometry.model.workload",
    "Workload": "rvcoax.geometry.model.workload",
    "WorkloadError": "rvcoax.geometry.model.workload",
    "beam_size": "rvcoax.geometry.model.workload",
    "check_cases": "rvcoax.geometry.model.workload",
    "check_study": "rvcoax.geometry.model.workload",
    "check_workers": "rvcoax.geometry.model.workload",
    "check_workload": "rvcoax.geometry.model.workload",
    "count_text": "rvcoax.geometry.model.workload",
    "rig_problem": "rvcoax.geometry.model.workload",
    "sweep_workload": "rvcoax.geometry.model.workload",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
