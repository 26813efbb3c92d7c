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
- errors: :class:`RvcoaxError`, the base of every error raised on purpose

Units: SI inside the solver; files and results say their unit in every key (``Y_input_mm``,
``beta_output_deg``, ``T2_output_Nm``).
"""

from __future__ import annotations

from rvcoax._lazy import lazy_names

__version__ = "0.1.0"

# public name → the module that defines it
_WHERE = {
    "Rig": "rvcoax.geometry.schema",
    "load_rig": "rvcoax.geometry.rigfile",
    "parse_rig_text": "rvcoax.geometry.rigfile",
    "reference_rig_text": "rvcoax.geometry.rigfile",
    "reference_from_geometry": "rvcoax.geometry.variants",
    "load_example_rig": "rvcoax.geometry.builtin",
    "example_rig_text": "rvcoax.geometry.builtin",
    "is_reference_rig": "rvcoax.geometry.builtin",
    "default_cases": "rvcoax.loadcases.cases",
    "rig_cases": "rvcoax.loadcases.cases",
    "LoadCase": "rvcoax.loadcases.cases",
    "paper_cases": "rvcoax.loadcases.cases",
    "paper_table": "rvcoax.loadcases.cases",
    "read_cases": "rvcoax.loadcases.cases",
    "paired_cases": "rvcoax.loadcases.cases",
    "grid_cases": "rvcoax.loadcases.cases",
    "MODEL_KINDS": "rvcoax.geometry.model.system",
    "RigSystem": "rvcoax.geometry.model.system",
    "assemble_rig": "rvcoax.geometry.model.assemble",
    "SweepSettings": "rvcoax.results.sweep",
    "PreparedModel": "rvcoax.results.sweep",
    "Sweep": "rvcoax.results.sweep",
    "prepare_model": "rvcoax.results.sweep",
    "run_sweep": "rvcoax.results.sweep",
    "engineering_tables": "rvcoax.results.engineering",
    "write_sweep": "rvcoax.results.io.result_files",
    "run_durable_sweep": "rvcoax.results.io.durable_sweep",
    "write_check": "rvcoax.results.io.result_files",
    "plot_y_vs_torque": "rvcoax.results.io.pictures",
    "plot_bending_line": "rvcoax.results.io.bending_line",
    "write_report": "rvcoax.results.io.report",
    "render_deformed": "rvcoax.results.io.pictures",
    "draw_sweep_pictures": "rvcoax.results.io.sweep_pictures",
    "CheckRun": "rvcoax.results.studies.check_run",
    "run_check": "rvcoax.results.studies.check_run",
    "measured_rows": "rvcoax.results.studies.check",
    "calibrate": "rvcoax.results.studies.calibration",
    "read_measured": "rvcoax.results.studies.discrepancy.measured",
    "DiscrepancySettings": "rvcoax.results.studies.discrepancy.workflow",
    "run_discrepancy": "rvcoax.results.studies.discrepancy.workflow",
    "RvcoaxError": "rvcoax.fem.errors",
    "BallBearingGeometry": "rvcoax.fem.ball_bearing",
    "ball_loads": "rvcoax.fem.ball_bearing",
    "bearing_force": "rvcoax.fem.ball_bearing",
    "radial_deflection": "rvcoax.fem.ball_bearing",
    "BALL_BEARINGS": "rvcoax.geometry.ball_bearings",
}

__all__ = ["__version__", *_WHERE]


__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
