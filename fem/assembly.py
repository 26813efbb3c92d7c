"""Assembly of COO triplets from any model piece into one sparse matrix."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import scipy.sparse as sp


def assemble_matrix(n_dofs: int, pieces: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> sp.csr_matrix:
    """Sum the triplets ``(rows, cols, values)`` of every piece into an (n, n) CSR matrix."""
    rows, cols, vals = [], [], []
    for r, c, v in pieces:
        rows.append(np.asarray(r, dtype=np.int64))
        cols.append(np.asarray(c, dtype=np.int64))
        vals.append(np.asarray(v, dtype=float))
    if not rows:
        return sp.csr_matrix((n_dofs, n_dofs))
    matrix = sp.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n_dofs, n_dofs)
    ).tocsr()
    matrix.sum_duplicates()
    return matrix
