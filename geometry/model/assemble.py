"""One entry from a rig to its assembled system, whatever the fidelity: beam, hybrid or solid."""

from __future__ import annotations

from rvcoax.geometry.model.system import MODEL_KINDS, RigSystem, assemble_beam
from rvcoax.geometry.schema import Rig

__all__ = ["MODEL_KINDS", "assemble_rig"]


def assemble_rig(rig: Rig, kind: str = "beam", **options) -> RigSystem:
    """Assemble ``rig`` at fidelity ``kind``.

    Parameters
    ----------
    rig : Rig
    kind : {"beam", "hybrid", "solid"}
        ``beam``: every part a line of Timoshenko beams; ``hybrid``: the parts named in ``[solid]
        hybrid_parts`` as quadratic tetrahedra, the rest beams; ``solid``: every part a solid.
    **options
        ``mesh_size_mm`` for the solid parts.

    Returns
    -------
    RigSystem
        The stiffness K, the constraint elimination T (u = T q) and one load vector per unit load.
    """
    if kind == "beam":
        return assemble_beam(rig)
    if kind in ("hybrid", "solid"):
        from rvcoax.geometry.model.hybrid import assemble_with_solids  # scikit-fem and gmsh: only when needed

        return assemble_with_solids(rig, kind, **options)
    raise ValueError(f"unknown model kind {kind!r}; use one of {', '.join(MODEL_KINDS)}")
