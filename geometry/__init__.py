"""Rig description: the TOML rig file, its validation, the effect library, and the model built from it.

Public names (loaded on first use): reading and writing rig files, the input-file parsers every
reader shares, plausibility warnings, and the candidate effects of the discrepancy workflow.
The model built from a rig is :mod:`rvcoax.geometry.model`.
"""

if __name__ != "rvcoax.geometry":  # run from the repository root, the folder itself is on sys.path: not a package of its own
    raise ImportError("'geometry' is part of rvcoax and is imported as rvcoax.geometry "
                      "(install the project, e.g. `make test`, and import rvcoax.geometry)")

from rvcoax._lazy import lazy_names

MEASURED_SHAFTS = ("input", "output")
"""The shafts whose Y is measured and reported, named as the rig file's ``[paths]`` names them."""

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.geometry.schema": ("Rig",),
    "rvcoax.geometry.rigfile": ("REFERENCE_VARIANTS", "load_rig", "parse_rig_text", "reference_rig_text"),
    "rvcoax.geometry.rigwrite": ("updated_rig_text",),
    "rvcoax.geometry.effects": ("candidate_effects",),
    "rvcoax.geometry.catalogue": ("plausibility_warnings",),
    "rvcoax.geometry.inputfiles": ("InputFileError", "csv_rows", "plain_number", "read_input_text"),
    "rvcoax.geometry.limits": ("MESH_SIZE_RANGE_MM",),
    "rvcoax.geometry.ball_model": ("clearance_um_of", "geometry_of"),
    "rvcoax.geometry.builtin": ("example_rig_text", "is_reference_rig", "load_example_rig", "reference_differences"),
    "rvcoax.geometry.thermal": ("free_axial_growth_um", "mount_lift_um"),
}, eager=("MEASURED_SHAFTS",))
