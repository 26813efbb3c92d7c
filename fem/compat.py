"""The private parts of numpy and scipy rvcoax relies on, in one place.

Each hook is optional: without it the code falls back to the public API (slower, or with the
default behaviour). ``tests/fem/test_compat.py`` checks, for the installed versions, that every
hook is still there and behaves as used; a numpy or scipy release that drops one fails that test
before it silently costs speed.

- scipy's compiled sparse kernels (``scipy.sparse._sparsetools``): the counting-sort assembly of
  :mod:`rvcoax.fem.assembly`. Tested with scipy 1.11 … 1.17.
- numpy's switch for huge-page requests (``numpy._core.multiarray._set_madvise_hugepage``):
  :mod:`rvcoax.fem.hugepages`. Tested with numpy 2.0 … 2.4.

meshio's XDMF internals (time-series writer and reader classes, the ``meshio.xdmf.common`` tables) are
used in one module, :mod:`rvcoax.results.io.fields`, which says why; ``tests/results/io/test_fields.py``
pins them the same way (tested with meshio 5.3).
"""

from __future__ import annotations

__all__ = ["numpy_madvise_switch", "sparse_kernels"]


def sparse_kernels():
    """scipy's ``(coo_tocsr, csr_hstack, csr_sum_duplicates, csr_tocsc)``, or None where they are gone."""
    try:
        from scipy.sparse._sparsetools import coo_tocsr, csr_hstack, csr_sum_duplicates, csr_tocsc
    except ImportError:  # pragma: no cover - a scipy without the private module
        return None
    return coo_tocsr, csr_hstack, csr_sum_duplicates, csr_tocsc


def numpy_madvise_switch():
    """numpy's ``_set_madvise_hugepage(flag) -> previous flag``, or None where it is gone."""
    try:
        from numpy._core import multiarray
    except ImportError:  # pragma: no cover - numpy < 2
        return None
    return getattr(multiarray, "_set_madvise_hugepage", None)
