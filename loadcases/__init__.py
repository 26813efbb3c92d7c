"""Load cases: (T1, T2) torque pairs, from the paper's table, a grid, a list or a file."""
