"""Growable row tables for compiled kernels (numba arrays grown fourfold when full).

Rows are copied element by element: numba's slice assignment compiles its broadcasting checks and their
error messages, several seconds of a cold start.

Its functions are compiled helpers of the kernels and take their arguments unchecked (a row index is
not bounds-checked); the kernels that call them size the tables.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["grow_rows", "push_row"]


@njit(cache=True)
def grow_rows(table, n):
    """``table`` with room for row ``n`` (its rows grown fourfold when full: the rows not yet written are never
    touched, so they take address space, not memory, and the copies of the growth total a third of the rows)."""
    if n < table.shape[0]:
        return table
    bigger = np.empty((4 * table.shape[0], table.shape[1]))
    for i in range(n):
        for j in range(table.shape[1]):
            bigger[i, j] = table[i, j]
    return bigger


@njit(cache=True)
def push_row(table, n, row):
    """Append ``row`` as row ``n``; return the (possibly new) table and n + 1."""
    table = grow_rows(table, n)
    for j in range(row.shape[0]):
        table[n, j] = row[j]
    return table, n + 1
