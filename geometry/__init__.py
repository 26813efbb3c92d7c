"""Rig description: the TOML rig file, its validation, and the beam model built from it."""
