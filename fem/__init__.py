"""Finite-element core of rvcoax: 3D Timoshenko beams, bushings, point masses, constraints, solvers.

Everything here knows nothing about rigs: it works on node coordinates, element tables and
DOF numbers, in SI units. Every model piece returns a :class:`rvcoax.fem.pieces.Contribution`
(stiffness triplets, load entries, constraint rows) and one function assembles a list of them.

Public names (loaded on first use): the error base and the solver error, the two
process-wide settings the ``rvcoax`` command makes at start, and the C heap's policy it sets for the
model it prepares (a program using the library may do the same).
"""

if __name__ != "rvcoax.fem":  # run from the repository root, the folder itself is on sys.path: not a package of its own
    raise ImportError("'fem' is part of rvcoax and is imported as rvcoax.fem "
                      "(install the project, e.g. `make test`, and import rvcoax.fem)")

from rvcoax._lazy import lazy_names

DOFS_PER_NODE = 6
"""Nodal DOFs: ux, uy, uz, rx, ry, rz (translations in m, rotations in rad)."""

# the module that defines each public name
_WHERE, __all__, __getattr__, __dir__ = lazy_names(__name__, globals(), {
    "rvcoax.errors": ("RvcoaxError",),
    "rvcoax.fem.errors": ("SolverError",),
    "rvcoax.fem.hugepages": ("avoid_compaction_stalls",),
    "rvcoax.fem.blas_threads": ("single_threaded_openblas",),
    "rvcoax.fem.memory": ("apply_heap_policy",),
}, eager=("DOFS_PER_NODE",))
