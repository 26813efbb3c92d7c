"""Standard orthogonal arrays (L9, L18, L27, L81) and the orthogonality check.

The three-level arrays L9(3^4), L27(3^13) and L81(3^40) are linear arrays over GF(3): with base
digits (a, b, c, …) of the run number (a slowest), every column is a combination Σ c_i d_i mod 3
whose last non-zero coefficient is 1, in Taguchi's order (a, b, a+b, 2a+b, c, a+c, 2a+c, b+c, …).
That rule reproduces the standard L9 and L27 tables (columns 3 and 4 of L27 carry the interaction
of columns 1 and 2). L18(2^1 × 3^7) is not linear and is written out. Levels are numbered from 1.
"""

from __future__ import annotations

import itertools
from collections import Counter
from dataclasses import dataclass

import numpy as np

__all__ = ["ARRAYS", "OrthogonalArray", "linear_three_level", "match_columns", "orthogonality_problems",
           "same_partition", "standard_array", "three_level_coefficients"]

_L18 = (
    "11111111", "11222222", "11333333", "12112233", "12223311", "12331122",
    "13121323", "13232131", "13313212", "21133221", "21211332", "21322113",
    "22123132", "22231213", "22312321", "23132312", "23213123", "23321231",
)
ARRAYS = ("L9", "L18", "L27", "L81")


@dataclass(frozen=True)
class OrthogonalArray:
    """A standard array: ``table[run, column]`` holds level codes 1 … levels[column]."""

    name: str
    table: np.ndarray

    @property
    def runs(self) -> int:
        return self.table.shape[0]

    @property
    def columns(self) -> int:
        return self.table.shape[1]

    @property
    def levels(self) -> tuple[int, ...]:
        return tuple(int(c.max()) for c in self.table.T)


def three_level_coefficients(n_base: int) -> np.ndarray:
    """(columns × n_base) coefficients of the base digits in each column of a linear three-level array."""
    coefficients = []
    for k in range(n_base):
        for prefix in itertools.product(range(3), repeat=k):
            coefficients.append(list(prefix[::-1]) + [1] + [0] * (n_base - 1 - k))
    return np.array(coefficients)


def linear_three_level(n_base: int) -> np.ndarray:
    """The 3^n_base-run linear array with (3^n_base − 1)/2 three-level columns, Taguchi's column order."""
    runs = 3**n_base
    digits = np.array([[(r // 3 ** (n_base - 1 - i)) % 3 for i in range(n_base)] for r in range(runs)])
    return (digits @ three_level_coefficients(n_base).T) % 3 + 1


def standard_array(name: str) -> OrthogonalArray:
    """``L9``, ``L18``, ``L27`` or ``L81``."""
    if name == "L18":
        return OrthogonalArray(name, np.array([[int(c) for c in row] for row in _L18]))
    base = {"L9": 2, "L27": 3, "L81": 4}
    if name not in base:
        raise ValueError(f"unknown orthogonal array '{name}' (known: {', '.join(ARRAYS)})")
    return OrthogonalArray(name, linear_three_level(base[name]))


def orthogonality_problems(table: np.ndarray, names=None) -> list[str]:
    """Why ``table`` (runs × columns of level codes) is not an orthogonal array of strength 2; empty if it is.

    Every column must use each of its levels equally often, and every pair of columns every
    combination of their levels equally often.
    """
    table = np.asarray(table)
    names = list(names) if names is not None else [f"column {j + 1}" for j in range(table.shape[1])]
    problems = []
    for j, column in enumerate(table.T):
        counts = Counter(column.tolist())
        if len(set(counts.values())) != 1:
            problems.append(f"{names[j]}: levels are not equally frequent ({dict(sorted(counts.items()))})")
    for i, j in itertools.combinations(range(table.shape[1]), 2):
        counts = Counter(zip(table[:, i].tolist(), table[:, j].tolist()))
        expected = len(set(table[:, i].tolist())) * len(set(table[:, j].tolist()))
        if len(counts) != expected or len(set(counts.values())) != 1:
            problems.append(f"{names[i]} and {names[j]}: level pairs are not equally frequent")
    return problems


def same_partition(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two columns are the same up to renumbering their levels."""
    forward: dict = {}
    backward: dict = {}
    for x, y in zip(a.tolist(), b.tolist()):
        if forward.setdefault(x, y) != y or backward.setdefault(y, x) != x:
            return False
    return True


def match_columns(table: np.ndarray, array: OrthogonalArray) -> list[int | None]:
    """For each column of ``table``, the (1-based) column of ``array`` it equals up to level renumbering."""
    table = np.asarray(table)
    if table.shape[0] != array.runs:
        return [None] * table.shape[1]
    return [next((j + 1 for j in range(array.columns) if same_partition(column, array.table[:, j])), None)
            for column in table.T]
