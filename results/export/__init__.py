"""Inputs for dynamics models: per-case tilts, offsets and forces (JSON/CSV), ADAMS datasets, ROSS rotors."""
