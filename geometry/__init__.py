"""Rig description: the TOML rig file, its validation, and the model built from it."""

__all__ = ["MEASURED_SHAFTS"]

MEASURED_SHAFTS = ("input", "output")
"""The shafts whose Y is measured and reported, named as the rig file's ``[paths]`` names them."""
