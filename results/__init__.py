"""Sweeps, shaft-path results, the published-table check, calibration, reports and the CLI."""
