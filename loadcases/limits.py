"""Bounds every load-case reader applies (imported by the command line before anything heavy)."""

__all__ = ["MAX_CASE_FILE_BYTES", "MAX_TORQUE_NM"]

MAX_CASE_FILE_BYTES = 20_000_000  # about a million load cases
MAX_TORQUE_NM = 1e6  # |T1|, |T2| beyond this are no rig torque (RV-20E: 1.43 and 200 N·m); every reader uses it
