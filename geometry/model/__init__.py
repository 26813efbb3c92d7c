"""Rig → model pieces → assembled system: the beam, hybrid and solid models of a rig, its unit loads, and the
checks made before a model is solved (sizes, memory, sag).

Public names (loaded on first use): the assembled system and how to build it, and the size checks
that refuse or announce work before it starts.
"""

from rvcoax._lazy import lazy_names

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.geometry.model.system": ("MODEL_KINDS", "RigSystem"),
    "rvcoax.geometry.model.assemble": ("assemble_rig",),
    "rvcoax.geometry.model.beam": ("build_rig_model",),
    "rvcoax.geometry.model.housings": ("SeatStiffness", "housing_condensation", "seat_stiffness"),
    "rvcoax.geometry.gear_loads": ("gear_contact_torques", "gear_mesh_forces"),
    "rvcoax.geometry.model.preflight": ("peak_memory_bytes", "sag_warnings"),
    "rvcoax.geometry.model.workload": ("REPORT_AFTER_S", "Workload", "WorkloadError", "beam_size", "check_cases",
                                       "check_study", "check_workers", "check_workload", "count_text",
                                       "housing_problem", "housing_workload", "rig_problem", "sweep_workload"),
})
