"""Moving a sparse matrix into a file mapping: the same matrix, usable as before."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from rvcoax.fem.memory import move_to_file


def test_a_moved_matrix_keeps_every_entry_and_its_products():
    a = sp.random(300, 300, density=0.02, format="csr", random_state=4)
    a = (a + a.T).tocsr()
    reference = a.copy()
    x = np.random.default_rng(2).standard_normal((300, 3))
    assert move_to_file(a)
    assert isinstance(a.data.base, np.ndarray) and not a.data.flags.owndata  # a view of the mapping now
    assert np.array_equal(a.indptr, reference.indptr) and np.array_equal(a.indices, reference.indices)
    assert np.array_equal(a.data, reference.data)
    assert np.array_equal(a @ x, reference @ x)
    a.data[0] += 1.0  # copy-on-write: the process's copy changes, nothing else
    assert a.data[0] == reference.data[0] + 1.0


def test_a_folder_that_cannot_take_the_file_leaves_the_matrix_as_it_was(tmp_path):
    a = sp.identity(50, format="csr")
    data = a.data
    assert not move_to_file(a, folder=str(tmp_path / "missing"))
    assert a.data is data


def test_nothing_is_moved_to_a_file_system_held_in_memory(monkeypatch):
    from rvcoax.fem import memory

    monkeypatch.setattr(memory, "_in_memory_filesystem", lambda folder: True)  # a tmpfs temporary folder
    a = sp.identity(50, format="csr")
    data = a.data
    assert not move_to_file(a)
    assert a.data is data


def test_arrays_moved_to_a_file_are_the_same_arrays():
    from rvcoax.fem.memory import arrays_to_file

    rng = np.random.default_rng(5)
    arrays = [rng.standard_normal((7, 3)), np.arange(11, dtype=np.int8), np.asfortranarray(rng.integers(0, 9, (4, 5))),
              np.zeros(0)]
    moved = arrays_to_file(arrays)
    assert moved is not None
    for before, after in zip(arrays, moved):
        assert after.dtype == before.dtype and after.shape == before.shape and np.array_equal(after, before)
        assert not after.flags.owndata  # a view of the mapping
    moved[0][0, 0] += 1.0  # copy-on-write, the original untouched
    assert moved[0][0, 0] == arrays[0][0, 0] + 1.0
