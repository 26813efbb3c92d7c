"""Rig description: the TOML rig file, its validation, the effect library, and the model built from it.

Public names (loaded on first use): reading and writing rig files, the input-file parsers every
reader shares, plausibility warnings, and the candidate effects of the discrepancy workflow.
The model built from a rig is :mod:`rvcoax.geometry.model`.
"""

from rvcoax._lazy import lazy_names

MEASURED_SHAFTS = ("input", "output")
"""The shafts whose Y is measured and reported, named as the rig file's ``[paths]`` names them."""

# public name → the module that defines it
_WHERE = {
    "Rig": "rvcoax.geometry.schema",
    "load_rig": "rvcoax.geometry.rigfile",
    "parse_rig_text": "rvcoax.geometry.rigfile",
    "reference_rig_text": "rvcoax.geometry.rigfile",
    "updated_rig_text": "rvcoax.geometry.rigwrite",
    "candidate_effects": "rvcoax.geometry.effects",
    "plausibility_warnings": "rvcoax.geometry.catalogue",
    "InputFileError": "rvcoax.geometry.inputfiles",
    "csv_rows": "rvcoax.geometry.inputfiles",
    "plain_number": "rvcoax.geometry.inputfiles",
    "read_input_text": "rvcoax.geometry.inputfiles",
    "MESH_SIZE_RANGE_MM": "rvcoax.geometry.limits",
}

__all__ = ["MEASURED_SHAFTS", *_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
