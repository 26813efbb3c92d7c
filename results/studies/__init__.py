"""Studies built on sweeps: calibration, the published-table check, orthogonal experiments, the discrepancy
workflow, Monte Carlo, sensitivity, tolerance files and the chain-error model."""
