"""The private numpy and scipy hooks of rvcoax.fem.compat exist in the installed versions and do what we use them for."""

import numpy as np
import scipy
import scipy.sparse as sp

from rvcoax.fem import assembly, compat


def _version(text: str) -> tuple[int, int]:
    major, minor = text.split(".")[:2]
    return int(major), int(minor)


def test_scipy_sparse_kernels_are_there_and_assembly_uses_them():
    assert (1, 11) <= _version(scipy.__version__) <= (1, 17), f"compat.py is tested up to scipy 1.17: {scipy.__version__}"
    kernels = compat.sparse_kernels()
    assert kernels is not None and all(callable(k) for k in kernels)
    assert assembly.coo_tocsr is kernels[0]
    rows, cols, vals = np.array([0, 1, 0, 2]), np.array([0, 1, 0, 1]), np.array([1.0, 2.0, 3.0, 4.0])
    matrix = assembly.assemble_matrix(3, [(rows, cols, vals)])
    assert (matrix != sp.coo_matrix((vals, (rows, cols)), shape=(3, 3)).tocsr()).nnz == 0


def test_numpy_madvise_switch_is_there_and_returns_the_previous_setting():
    assert (2, 0) <= _version(np.__version__) <= (2, 4), f"compat.py is tested up to numpy 2.4: {np.__version__}"
    switch = compat.numpy_madvise_switch()
    assert switch is not None
    before = switch(True)
    try:
        assert switch(False) is True
        assert switch(before) is False
    finally:
        switch(before)
