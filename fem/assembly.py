"""Assembly of COO triplets from any model piece into one sparse matrix.

The triplets are brought into CSR order by two stable counting sorts, first by column, then by
row (an LSD radix sort whose digits are the column and the row); duplicates then sit next to each
other and are summed in one linear pass. scipy's ``coo_matrix(...).tocsr()`` instead sorts every
row with a comparison sort. Work arrays use 32-bit indices whenever the size allows (half the
memory traffic); the index buffer of the first pass is reused as the value buffer of the second,
and the matrix is written into the buffers of the first pass and shrunk in place: about 24 bytes
of working memory per triplet besides the caller's arrays, nothing more for the result.

scipy's compiled kernels release the GIL, so large inputs use threads: the two index arrays are
checked and converted concurrently, and the second sort runs on column blocks with equal numbers
of entries (each block yields every row's entries in its own column range, already sorted; the
blocks are joined side by side).

Against scipy's conversion it takes about 60 % of the time and 75 % of the extra memory (figures
with machine and date: benchmarks/RESULTS.md, bench_solid_scaling.py). Where fresh memory is slow
to fault in, the first call in a process pays that on top, in system time.

Duplicates are summed in input order (pieces in the order given, triplets in their order within
a piece), so the result is deterministic and independent of the thread count; against scipy's
conversion values differ only by the summation order (≲ 1e-15 relative). Entries that sum to zero
are kept (the sparsity pattern is that of the triplets), as with scipy's conversion.
"""

from __future__ import annotations

import collections
import os
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rvcoax.fem.compat import sparse_kernels

__all__ = ["BlockPattern", "PARALLEL_MIN_TRIPLETS", "add_element_matrices", "assemble_matrix", "block_diagonal",
           "block_pattern", "element_positions", "in_order", "keep_rows_and_columns", "worker_threads"]

# scipy's compiled sparse kernels (private: rvcoax.fem.compat); the public conversion without them
_KERNELS = sparse_kernels()
coo_tocsr, csr_hstack, csr_sum_duplicates, csr_tocsc = _KERNELS if _KERNELS is not None else (None,) * 4

_INT32_MAX = np.iinfo(np.int32).max
PARALLEL_MIN_TRIPLETS = 1_000_000
"""Below this many triplets everything runs in the calling thread."""


def worker_threads() -> int:
    """Threads for work split over the cores this process may run on (its CPU affinity), at most 8."""
    try:
        available = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        available = os.cpu_count() or 1
    return max(1, min(available, 8))


def in_order(produce, items, consume, threads: int) -> None:
    """``consume(produce(item))`` for every item, consumed in order in the calling thread.

    With ``threads`` > 1 the items are produced on that many worker threads (numpy's array operations release
    the GIL), at most ``threads`` items ahead of the one consumed, so at most ``threads + 1`` results are held.
    """
    items = list(items)
    if threads <= 1 or len(items) < 2:
        for item in items:
            consume(produce(item))
        return
    with ThreadPoolExecutor(threads) as pool:
        pending: collections.deque = collections.deque()
        for item in items:
            pending.append(pool.submit(produce, item))
            if len(pending) > threads:
                consume(pending.popleft().result())
        while pending:
            consume(pending.popleft().result())


def _as_index_array(a) -> np.ndarray:
    array = np.asarray(a)
    if array.dtype.kind not in "iu":
        array = np.asarray(array, dtype=np.int64)  # as before: floats are truncated to integers
    return array.reshape(-1)


def _check_and_copy(parts: list[np.ndarray], n_dofs: int, what: str, out: np.ndarray) -> None:
    """Check that every index lies in [0, n_dofs) and copy the parts one after another into ``out``."""
    start = 0
    for index in parts:
        # one pass: seen as unsigned, a negative index is huge, so the maximum catches both ends
        if index.size and int(index.view(index.dtype.str.replace("i", "u")).max()) >= n_dofs:
            raise ValueError(
                f"{what} index out of range: [{int(index.min())}, {int(index.max())}] "
                f"for a {n_dofs} × {n_dofs} matrix"
            )
        out[start : start + index.size] = index
        start += index.size


def _scipy_assembly(n_dofs, rows, cols, vals) -> sp.csr_matrix:  # pragma: no cover - old scipy only
    matrix = sp.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n_dofs, n_dofs)
    ).tocsr()
    matrix.sum_duplicates()
    return matrix


def assemble_matrix(n_dofs: int, pieces: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> sp.csr_matrix:
    """Sum the triplets ``(rows, cols, values)`` of every piece into an (n, n) CSR matrix.

    The result is in canonical form (column indices sorted within rows, no duplicates); entries
    whose contributions cancel are kept as explicit zeros.

    Raises
    ------
    ValueError
        An index outside [0, n), or rows, cols and values of different lengths.
    """
    n_dofs = int(n_dofs)
    rows, cols, vals = [], [], []
    for r, c, v in pieces:
        r, c = _as_index_array(r), _as_index_array(c)
        v = np.asarray(v, dtype=float).reshape(-1)
        if not r.size == c.size == v.size:
            raise ValueError(f"rows, cols and values differ in length: {r.size}, {c.size}, {v.size}")
        rows.append(r)
        cols.append(c)
        vals.append(v)
    nnz = sum(v.size for v in vals)
    if nnz == 0:
        return sp.csr_matrix((n_dofs, n_dofs))
    if coo_tocsr is None:  # pragma: no cover
        return _scipy_assembly(n_dofs, rows, cols, vals)

    threads = worker_threads() if nnz >= PARALLEL_MIN_TRIPLETS else 1
    if threads == 1:
        return _assemble(n_dofs, nnz, rows, cols, vals, pool=_InlinePool(), threads=1)
    with ThreadPoolExecutor(threads) as pool:
        return _assemble(n_dofs, nnz, rows, cols, vals, pool=pool, threads=threads)


class _InlinePool:
    """The part of an executor that :func:`_assemble` uses, running everything in the calling thread."""

    class _Done:
        def __init__(self, value) -> None:
            self._value = value

        def result(self):
            return self._value

    def submit(self, function, *args):
        return self._Done(function(*args))

    @staticmethod
    def map(function, iterable):
        return map(function, iterable)


def _transpose_block(job) -> tuple[np.ndarray, int]:
    """Transpose columns [c0, c1) of the column-grouped triplets into rows and sum duplicates in place.

    Writes into ``row_cols``/``row_values`` at the block's own entry range; returns the block's row
    pointers (n + 1, relative to that range) and the range's start.
    """
    c0, c1, col_ptr, col_rows, col_values, row_cols, row_values = job
    n_dofs = col_ptr.size - 1
    e0, e1 = int(col_ptr[c0]), int(col_ptr[c1])
    block_ptr = col_ptr[c0 : c1 + 1] - col_ptr[c0]
    out_ptr = np.empty(n_dofs + 1, dtype=col_ptr.dtype)
    out_cols, out_values = row_cols[e0:e1], row_values[e0:e1]
    csr_tocsc(c1 - c0, n_dofs, block_ptr, col_rows[e0:e1], col_values[e0:e1], out_ptr, out_cols, out_values)
    csr_sum_duplicates(n_dofs, c1 - c0, out_ptr, out_cols, out_values)  # in place, linear
    return out_ptr, e0


def _assemble(n_dofs, nnz, rows, cols, vals, *, pool, threads) -> sp.csr_matrix:  # noqa: PLR0913
    index_type = np.int32 if max(nnz, n_dofs) < _INT32_MAX else np.int64
    # rows and columns side by side in one buffer, which the second pass reuses for its values
    pair = np.empty(2 * nnz, dtype=index_type)
    row_index, col_index = pair[:nnz], pair[nnz:]
    checks = [pool.submit(_check_and_copy, rows, n_dofs, "row", row_index),
              pool.submit(_check_and_copy, cols, n_dofs, "column", col_index)]
    for check in checks:
        check.result()
    del rows, cols, checks
    values = vals[0] if len(vals) == 1 else np.concatenate(vals)
    del vals

    # pass 1: group by column (stable): the CSR of the transpose, rows in input order
    col_ptr = np.empty(n_dofs + 1, dtype=index_type)
    col_rows = np.empty(nnz, dtype=index_type)
    col_values = np.empty(nnz, dtype=float)
    coo_tocsr(n_dofs, n_dofs, nnz, col_index, row_index, values, col_ptr, col_rows, col_values)
    del row_index, col_index, values

    # pass 2, per block of columns with about equal numbers of entries: transpose back (stable),
    # giving rows with column indices ascending and duplicates adjacent, then sum duplicates
    row_values = pair.view(np.float64)[:nnz]  # the index buffer is free now (2 nnz indices ≥ nnz floats)
    row_cols = np.empty(nnz, dtype=index_type)
    targets = np.arange(1, threads) * (nnz / threads)
    bounds = np.unique(np.concatenate([[0], np.searchsorted(col_ptr, targets), [n_dofs]]))

    jobs = [(int(c0), int(c1), col_ptr, col_rows, col_values, row_cols, row_values)
            for c0, c1 in zip(bounds[:-1], bounds[1:])]
    blocks = list(pool.map(_transpose_block, jobs))
    del jobs, col_ptr

    # The result goes into the buffers of pass 1 (free now, already in memory), shrunk in place at
    # the end: no fresh memory and no final copy.
    indices, data = col_rows, col_values
    del col_rows, col_values
    if len(blocks) == 1:
        indptr = blocks[0][0]
        kept = int(indptr[-1])
        indices[:kept] = row_cols[:kept]
        data[:kept] = row_values[:kept]
    else:
        # join the blocks side by side: compact them to the front, then csr_hstack interleaves the rows
        kept = 0
        for block_ptr, start in blocks:
            size = int(block_ptr[-1])
            row_cols[kept : kept + size] = row_cols[start : start + size]
            row_values[kept : kept + size] = row_values[start : start + size]
            kept += size
        widths = np.diff(bounds).astype(index_type)
        indptr = np.empty(n_dofs + 1, dtype=index_type)
        csr_hstack(len(blocks), n_dofs, widths, np.concatenate([b[0] for b in blocks]),
                   row_cols[:kept], row_values[:kept], indptr, indices, data)
    del blocks, row_cols, row_values, pair
    indices.resize(kept, refcheck=False)  # owned arrays without other views: realloc shrinks in place
    data.resize(kept, refcheck=False)
    matrix = sp.csr_matrix((data, indices, indptr), shape=(n_dofs, n_dofs), copy=False)
    matrix.has_canonical_format = True  # sorted and summed by construction
    return matrix


# ------------------------------------------------------------------ element matrices into a 3 × 3-block pattern


@dataclass(frozen=True, eq=False)
class BlockPattern:
    """The sparsity of a matrix of 3 × 3 blocks, one block per pair of nodes that share an element.

    Unknowns are interleaved per node (3 i + c). The scalar CSR pattern (``indptr``, ``indices``) is
    that of the assembled matrix; the node graph (``node_indptr``, ``node_cols``) locates a node pair's block.

    Attributes
    ----------
    n_nodes : int
    node_indptr : (n_nodes + 1,) int64 array
        Row pointers of the node graph.
    node_cols : (n_pairs,) array
        Neighbours of every node, ascending within its row (int32 while the sizes allow).
    indptr : (3 n_nodes + 1,) array
    indices : (9 n_pairs,) array
        int32 while the sizes allow.
    """

    n_nodes: int
    node_indptr: np.ndarray
    node_cols: np.ndarray
    indptr: np.ndarray
    indices: np.ndarray

    @property
    def nnz(self) -> int:
        return int(self.indices.size)


def block_pattern(element_nodes: np.ndarray, n_nodes: int, chunk: int = 65536) -> BlockPattern:
    """The 3 × 3-block pattern of elements with nodes ``element_nodes`` (n_elements, k).

    The node graph is Aᵀ A of the element–node incidence A (scipy's sparse product, in chunks of
    elements summed as patterns), so no element-pair list is ever held.
    """
    element_nodes = np.asarray(element_nodes, dtype=np.int64)
    n_elements, k = element_nodes.shape
    graph = sp.csr_matrix((n_nodes, n_nodes), dtype=np.int8)
    for start in range(0, n_elements, chunk):
        block = element_nodes[start:start + chunk]
        rows = np.repeat(np.arange(block.shape[0]), k)
        incidence = sp.csr_matrix((np.ones(rows.size, dtype=np.int8), (rows, block.ravel())),
                                  shape=(block.shape[0], n_nodes))
        pairs = (incidence.T @ incidence).astype(bool)
        graph = (graph.astype(bool) + pairs).astype(bool).tocsr()
    graph.sort_indices()
    node_indptr = graph.indptr.astype(np.int64)
    node_cols = graph.indices.astype(np.int64)
    degree = np.diff(node_indptr)
    del graph
    nnz = 9 * node_cols.size
    index_type = np.int32 if max(nnz, 3 * n_nodes) < _INT32_MAX else np.int64
    # scalar rows 3 i, 3 i + 1, 3 i + 2 each hold, for every neighbour j of i in order, the columns 3 j, 3 j + 1,
    # 3 j + 2: node i's rows start at 9 · node_indptr[i] and are its column triples three times over
    row_length = np.repeat(3 * degree, 3)
    indptr = np.zeros(3 * n_nodes + 1, dtype=index_type)
    np.cumsum(row_length, out=indptr[1:])
    indices = np.empty(nnz, dtype=index_type)
    triples = indices.reshape(-1, 3)  # one row per (scalar row's) neighbour
    for i0 in range(0, n_nodes, chunk):
        i1 = min(i0 + chunk, n_nodes)
        p0, p1 = int(node_indptr[i0]), int(node_indptr[i1])
        cols = (3 * node_cols[p0:p1]).astype(index_type)
        # triple row g = 3 p_i + a deg_i + s (copy a, neighbour s) takes neighbour p_i + s = g − (2 p_i + a deg_i)
        shift = (2 * node_indptr[i0:i1, None] + np.arange(3) * degree[i0:i1, None]).reshape(-1)
        source = np.arange(3 * p0, 3 * p1) - np.repeat(shift, np.repeat(degree[i0:i1], 3)) - p0
        for d in range(3):
            np.add(cols[source], d, out=triples[3 * p0:3 * p1, d])
    return BlockPattern(int(n_nodes), node_indptr, node_cols.astype(index_type), indptr, indices)


def element_positions(pattern: BlockPattern, element_nodes: np.ndarray) -> np.ndarray:
    """Where the entries of element matrices go in the pattern's values, in element order.

    Returns, for elements with nodes ``element_nodes`` (n, k), the positions (n · 9 k²,) in ``data`` of their
    matrices' entries (n, 3k, 3k), local unknown 3 a + c of node a: entry (3 a + c, 3 b + d) of node pair
    (i, j) lies at ``9 p_i + 3 (q − p_i) + 3 c deg_i + d`` with p_i = ``node_indptr[i]``, deg_i node i's
    neighbours and q the place of j among them: node i's three scalar rows are contiguous and each holds
    3 deg_i entries. q is found by bisection within node i's row of the node graph (a few steps over a few
    cache lines; a binary search over all node pairs cost twice as much at 1 M DOF). int32 while the pattern's
    size allows.

    Raises
    ------
    ValueError
        An element couples two nodes that are not in the pattern.
    """
    element_nodes = np.asarray(element_nodes, dtype=np.int64)
    n, k = element_nodes.shape
    index_type = pattern.indices.dtype
    start = pattern.node_indptr[element_nodes]  # (n, k): p_i of each element's nodes (rows)
    end = pattern.node_indptr[element_nodes + 1]
    # lower bound of j in node_cols[p_i : p_i + deg_i] for every (e, a, b)
    low = np.repeat(start.astype(index_type), k, axis=1).reshape(-1)
    high = np.repeat(end.astype(index_type), k, axis=1).reshape(-1)
    row_end = high.copy()
    wanted = np.broadcast_to(element_nodes[:, None, :], (n, k, k)).reshape(-1).astype(pattern.node_cols.dtype)
    middle = np.empty_like(low)
    # as many steps as the longest row needs; a search that has ended (low = high) moves on only where its row
    # lacks j and the next row's entry is smaller, which the check below refuses either way
    for _ in range(int((end - start).max(initial=0)).bit_length()):
        np.add(low, high, out=middle)
        middle >>= 1
        right = pattern.node_cols.take(middle, mode="clip") < wanted
        np.add(middle, 1, out=low, where=right)
        np.copyto(high, middle, where=~right)
    if np.any(low >= row_end) or np.any(pattern.node_cols.take(low, mode="clip") != wanted):
        raise ValueError("an element couples two nodes that are not in the pattern")
    degree = (end - start).astype(index_type)
    base = (3 * low.reshape(n, k, k) + (6 * start[:, :, None]).astype(index_type))  # (n, a, b): 9 p_i + 3 (q − p_i)
    row_step = 3 * degree[:, :, None] * np.arange(3, dtype=index_type)  # (n, a, c): 3 c deg_i
    position = np.empty((n, k, 3, k, 3), dtype=index_type)  # element order: (e, a, c, b, d)
    np.add(base[:, :, None, :, None], row_step[:, :, :, None, None], out=position)
    position += np.arange(3, dtype=index_type)
    return position.reshape(-1)


def add_element_matrices(pattern: BlockPattern, element_nodes: np.ndarray, matrices: np.ndarray,
                         data: np.ndarray) -> None:
    """Add element matrices (n, 3k, 3k), local unknown 3 a + c of node a, into ``data`` (the pattern's values).

    Each element entry is located by its node pair's block (:func:`element_positions`) and added in element order
    (``np.add.at``), so the result does not depend on how the elements are chunked.
    """
    np.add.at(data, element_positions(pattern, element_nodes), np.asarray(matrices, dtype=float).reshape(-1))


def block_diagonal(n_dofs: int, blocks: list[tuple[int, sp.csr_matrix]]) -> sp.csr_matrix:
    """An (n, n) CSR matrix of square CSR ``blocks`` placed at their offsets (ascending, not overlapping),
    written once into arrays of the final size."""
    blocks = sorted(blocks, key=lambda b: b[0])
    nnz = sum(b.nnz for _, b in blocks)
    index_type = np.int32 if max(nnz, n_dofs) < _INT32_MAX else np.int64
    indptr = np.zeros(n_dofs + 1, dtype=index_type)
    indices = np.empty(nnz, dtype=index_type)
    data = np.empty(nnz)
    filled, end = 0, 0
    for offset, block in blocks:
        size = block.shape[0]
        if offset < end or offset + size > n_dofs:
            raise ValueError(f"a block at {offset} of size {size} overlaps another or leaves the {n_dofs} unknowns")
        indptr[end + 1:offset + 1] = filled
        indptr[offset + 1:offset + size + 1] = filled + block.indptr[1:]
        indices[filled:filled + block.nnz] = block.indices + offset
        data[filled:filled + block.nnz] = block.data
        filled += block.nnz
        end = offset + size
    indptr[end + 1:] = filled
    return sp.csr_matrix((data, indices, indptr), shape=(n_dofs, n_dofs))


def keep_rows_and_columns(matrix: sp.csr_matrix, keep, *, overwrite: bool = False, chunk: int = 8192,
                          threads: int | None = None) -> sp.csr_matrix:
    """``matrix[keep][:, keep]`` of a square CSR matrix in one pass over its rows: the constraint elimination
    of fixed unknowns.

    scipy's two slices hold the matrix, its row slice and the result at once (at 1.14 M DOF: +2.1 GB over
    the 1.07 GB stiffness, benchmarks/RESULTS.md). Here the kept entries are gathered block of rows by
    block of rows; with ``overwrite`` they are written over the front of the matrix's own arrays (the
    result's values and indices are views of them), so nothing but one block's temporaries is added and
    ``matrix`` must not be used afterwards.
    Order within rows is kept (sorted indices stay sorted); explicit zeros are kept.

    Parameters
    ----------
    matrix : csr_matrix (n, n)
    keep : (n,) bool array, or the kept indices (ascending)
    overwrite : bool
        Reuse (and consume) ``matrix``'s arrays.
    chunk : int
        Rows per block (8192 rows of a P2 solid: about 16 MB of temporaries).
    threads : int, optional
        Worker threads that gather the next blocks while the calling thread writes (:func:`in_order`; the same
        result); default :func:`worker_threads` from :data:`PARALLEL_MIN_TRIPLETS` stored entries on, else one.
    """
    n = matrix.shape[0]
    if matrix.shape != (n, n) or not (sp.isspmatrix_csr(matrix) or isinstance(matrix, sp.csr_array)):
        raise ValueError(f"expected a square CSR matrix, got {type(matrix).__name__} of shape {matrix.shape}")
    keep = np.asarray(keep)
    if keep.dtype != bool:
        mask = np.zeros(n, dtype=bool)
        mask[keep] = True
        keep = mask
    if keep.shape != (n,):
        raise ValueError(f"keep must have {n} entries, got {keep.shape}")
    indptr, indices, data = matrix.indptr, matrix.indices, matrix.data
    sorted_indices = bool(matrix.has_sorted_indices)
    if not overwrite:
        indices, data = np.empty_like(indices), np.empty_like(data)
    kept_rows = np.flatnonzero(keep)
    renumber = np.full(n, -1, dtype=matrix.indices.dtype)
    renumber[kept_rows] = np.arange(kept_rows.size, dtype=renumber.dtype)
    new_indptr = np.zeros(kept_rows.size + 1, dtype=indptr.dtype)

    def kept_part(r0: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rows r0 … r0 + chunk: the kept entries' values and new columns (copies), and each kept row's count."""
        r1 = min(r0 + chunk, n)
        s, e = int(indptr[r0]), int(indptr[r1])
        columns = matrix.indices[s:e]
        local_row = np.repeat(np.arange(r1 - r0), np.diff(indptr[r0:r1 + 1]))
        selected = keep[columns] & keep[r0:r1][local_row]
        per_row = np.bincount(local_row[selected], minlength=r1 - r0)[keep[r0:r1]]
        return matrix.data[s:e][selected], renumber[columns[selected]], per_row

    written = rows_done = 0

    def write(part) -> None:
        nonlocal written, rows_done
        values, new_columns, per_row = part
        m = values.size
        data[written:written + m] = values
        indices[written:written + m] = new_columns
        new_indptr[rows_done + 1:rows_done + 1 + per_row.size] = written + np.cumsum(per_row)
        written += m
        rows_done += per_row.size

    # Blocks are written in order. Writing block k touches the arrays only below the end of its rows (at most as
    # many entries are kept as there were), so reading later blocks while it is written is safe with overwrite:
    # worker threads read (gather and renumber) the next blocks while the calling thread writes.
    starts = range(0, n, chunk)
    if threads is None:
        threads = worker_threads() if matrix.nnz >= PARALLEL_MIN_TRIPLETS else 1
    in_order(kept_part, starts, write, threads)
    # views of the front of the arrays: the dropped entries' tail (the clamped rows' share) stays allocated,
    # but nothing is copied (scipy's matrices often hold views, which cannot be shrunk in place)
    data, indices = data[:written], indices[:written]
    result = sp.csr_matrix((data, indices, new_indptr), shape=(kept_rows.size,) * 2, copy=False)
    result.has_sorted_indices = sorted_indices
    return result
