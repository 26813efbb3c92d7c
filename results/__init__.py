"""Solving and sweeps, shaft-path results, and the rooms that use them: files and pictures (:mod:`.io`),
dynamics exports (:mod:`.export`), studies (:mod:`.studies`) and the command line (:mod:`.cli`).

Public names (loaded on first use): a sweep, its settings and the prepared model it solves.
"""

from rvcoax._lazy import lazy_names

# public name → the module that defines it
_WHERE = {
    "PreparedModel": "rvcoax.results.sweep",
    "Sweep": "rvcoax.results.sweep",
    "SweepSettings": "rvcoax.results.sweep",
    "prepare_model": "rvcoax.results.sweep",
    "run_sweep": "rvcoax.results.sweep",
    "ConnectionsUnavailableError": "rvcoax.results.connections",
}

__all__ = [*_WHERE]

__getattr__, __dir__ = lazy_names(__name__, _WHERE, globals())
