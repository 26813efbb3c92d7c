"""rvcoax: finite-element static coaxiality of robot-reducer (RV / cycloidal) test rigs.

The public Python API. The command line calls exactly these functions; a notebook or a Dask worker
can too. Names load on first use (``import rvcoax`` itself imports nothing heavy), so the command
line starts in a fraction of a second.

Example
-------
>>> import rvcoax
>>> rig = rvcoax.load_rig()                      # the built-in reference rig (or a path to yours)
>>> sweep = rvcoax.run_sweep(rig, rvcoax.paper_cases())
>>> round(sweep.cases[0].paths["output"].beta_deg * 1e6, 1)  # µ°, paper 000's definition
63.3

Steps, in the order data flows:

- rig file: :func:`load_rig`, :func:`parse_rig_text`, :func:`reference_rig_text`, :class:`Rig`,
  :func:`reference_from_geometry` (the reference rig with gear data, condensed blocks, temperatures),
  :func:`load_example_rig`, :func:`example_rig_text`, :func:`is_reference_rig`
- load cases: :class:`LoadCase`, :func:`default_cases` (the rig file's; paper 000's for the reference rig
  only), :func:`rig_cases`, :func:`paper_cases`, :func:`paper_table`, :func:`read_cases`,
  :func:`paired_cases`, :func:`grid_cases`
- model and solve: :data:`MODEL_KINDS`, :func:`assemble_rig`, :class:`SweepSettings`,
  :func:`prepare_model`, :func:`run_sweep`, :func:`engineering_tables` (couplings, bearings, reactions per case)
- files and pictures: :func:`write_sweep`, :func:`run_durable_sweep`, :func:`write_check`,
  :func:`draw_sweep_pictures`, :func:`plot_y_vs_torque`, :func:`render_deformed`,
  :func:`plot_bending_line`, :func:`write_report`
- studies: :func:`run_check`, :func:`measured_rows`, :func:`calibrate`, :func:`read_measured`,
  :func:`run_discrepancy`
- ball bearings from geometry: :class:`BallBearingGeometry`, :func:`ball_loads`, :func:`bearing_force`,
  :func:`radial_deflection`, :data:`BALL_BEARINGS` (the catalogue)
- angular-contact and roller bearings from geometry: :class:`RollerBearingGeometry`, :func:`roller_loads`,
  :class:`BearingRow`, :class:`RollingBearing` (rows, pairs), :func:`rolling_element_loads` (every element's load
  and contact pressure at a state), :data:`ROLLING_BEARINGS` (the catalogue)
- errors: :class:`RvcoaxError`, the base of every error raised on purpose

Units: SI inside the solver; files and results say their unit in every key (``Y_input_mm``,
``beta_output_deg``, ``T2_output_Nm``).
"""

from __future__ import annotations

from rvcoax._lazy import lazy_names

__version__ = "0.1.0"

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.geometry.schema": ("Rig",),
    "rvcoax.geometry.rigfile": ("load_rig", "parse_rig_text", "reference_rig_text"),
    "rvcoax.geometry.variants": ("reference_from_geometry",),
    "rvcoax.geometry.builtin": ("load_example_rig", "example_rig_text", "is_reference_rig"),
    "rvcoax.loadcases.cases": ("default_cases", "rig_cases", "LoadCase", "paper_cases", "paper_table", "read_cases",
                               "paired_cases", "grid_cases"),
    "rvcoax.geometry.model.system": ("MODEL_KINDS", "RigSystem"),
    "rvcoax.geometry.model.assemble": ("assemble_rig",),
    "rvcoax.results.sweep": ("SweepSettings", "PreparedModel", "Sweep", "prepare_model", "run_sweep"),
    "rvcoax.results.engineering": ("engineering_tables",),
    "rvcoax.results.io.result_files": ("write_sweep",),
    "rvcoax.results.reports.check_files": ("write_check",),
    "rvcoax.results.io.durable_sweep": ("run_durable_sweep",),
    "rvcoax.results.io.pictures": ("plot_y_vs_torque", "render_deformed"),
    "rvcoax.results.io.bending_line": ("plot_bending_line",),
    "rvcoax.results.reports.report": ("write_report",),
    "rvcoax.results.io.sweep_pictures": ("draw_sweep_pictures",),
    "rvcoax.results.studies.check_run": ("CheckRun", "run_check"),
    "rvcoax.results.studies.check": ("measured_rows",),
    "rvcoax.results.studies.calibration": ("calibrate",),
    "rvcoax.results.studies.discrepancy.measured": ("read_measured",),
    "rvcoax.results.studies.discrepancy.workflow": ("DiscrepancySettings", "run_discrepancy"),
    "rvcoax.errors": ("RvcoaxError",),
    "rvcoax.fem.ball_bearing": ("BallBearingGeometry", "ball_loads", "bearing_force", "radial_deflection"),
    "rvcoax.geometry.ball_bearings": ("BALL_BEARINGS",),
    "rvcoax.fem.roller_bearing": ("RollerBearingGeometry", "roller_loads"),
    "rvcoax.fem.rolling_bearing": ("BearingRow", "RollingBearing", "rolling_element_loads"),
    "rvcoax.geometry.rolling_catalogue": ("ROLLING_BEARINGS",),
}, eager=("__version__",))
