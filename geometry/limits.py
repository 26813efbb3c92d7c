"""Bounds of user-given sizes that the command line needs before anything heavy is imported."""

__all__ = ["MESH_SIZE_RANGE_MM"]

MESH_SIZE_RANGE_MM = (0.05, 1000.0)  # finer than 0.05 mm meshes no rig part in memory; coarser than 1 m is no mesh
