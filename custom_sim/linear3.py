"""x = a^-1 b for a 3x3 system, in place and allocation-free (the Newton steps of implicit Euler)."""
from __future__ import annotations

from numba import njit


@njit(cache=True)
def solve3(a, b, x):
    """x = a^-1 b for the 3x3 system in a[:3, :3], Gaussian elimination with partial pivoting
    (a, b overwritten). Returns False, x unset, where a pivot is exactly 0: the largest entry
    left in its column is 0, the matrix singular (a Newton matrix whose iterate ran far off, as
    the jump step's lam can), never a division by zero."""
    for col in range(3):
        p = col
        for r in range(col + 1, 3):
            if abs(a[r, col]) > abs(a[p, col]):
                p = r
        if a[p, col] == 0.0:
            return False
        if p != col:
            for j in range(3):
                a[col, j], a[p, j] = a[p, j], a[col, j]
            b[col], b[p] = b[p], b[col]
        for r in range(col + 1, 3):
            f = a[r, col] / a[col, col]
            for j in range(col, 3):
                a[r, j] -= f * a[col, j]
            b[r] -= f * b[col]
    for r in range(2, -1, -1):
        s = b[r]
        for j in range(r + 1, 3):
            s -= a[r, j] * x[j]
        x[r] = s / a[r, r]
    return True
