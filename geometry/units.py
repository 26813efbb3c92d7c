"""The millimetre, once: rig files are in mm, the solver in SI.

``x_m = x_mm * MM`` and ``x_mm = x_m / MM``; files written for people (field files, pictures) are in mm
and use :data:`M_TO_MM`.
"""

__all__ = ["MM", "M_TO_MM"]

MM = 1e-3
"""One millimetre in metres (mm → m)."""
M_TO_MM = 1e3
"""Millimetres in one metre (m → mm), for lengths written in mm."""
