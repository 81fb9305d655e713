"""Symmetric tridiagonal LDLᵀ factor and solve (numba): the ``column`` preconditioner's
kernels.

scipy's ``cholesky_banded``/``cho_solve_banded`` (LAPACK ``pbtrf``/``pbtrs`` through banded
BLAS) took 6 ms and 4.3 ms per call for 257 k unknowns with one off-diagonal — a third of
a frigate day's time loop; these loops do the same arithmetic in well under 1 ms (the
factor keeps ``1/D``: a multiplication per unknown instead of a division in every solve).
The tests compare them with scipy's.

Where the matrix splits into independent blocks (plate columns: no coupling across a
column boundary), factor and solve run block by block on the process's threads
(:func:`column_bounds`): the arithmetic of every unknown is the same as in one sweep, so the
result is too, bit for bit, whatever the number of threads.

:func:`column_factor` reads the two bands straight from the value array of the Jacobian
(known positions) instead of through scipy's ``diagonal()``.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

__all__ = ["tridiagonal_factor", "tridiagonal_solve", "column_factor", "column_bounds",
           "ColumnSolve"]

#: Blocks of a split tridiagonal system (each a run of whole columns): enough for the
#: threads of any machine to share, few enough to stay long.
BLOCKS = 64


@njit(cache=True)
def _ordered_sum(part):
    """Sum of per-block partial sums, in block order (deterministic whatever the threads)."""
    s = 0.0
    for b in range(part.shape[0]):
        s += part[b]
    return s


@njit(parallel=True, cache=True)
def _factor(diag, sup, dinv, l, bounds):
    """Blocks ``bounds[b] … bounds[b + 1]`` are independent (``sup`` is zero between them).
    (Unsigned indices: numba then drops its negative-index test on every access.)"""
    bad = np.zeros(bounds.shape[0] - 1, np.bool_)
    for b in prange(bounds.shape[0] - 1):
        lo = np.uint64(bounds[b])
        hi = np.uint64(bounds[b + 1])
        one = np.uint64(1)
        d = diag[lo]
        ok = d > 0.0
        dinv[lo] = 1.0 / d
        if lo > 0:
            l[lo - one] = 0.0
        for i in range(lo + one, hi):
            li = sup[i - one] * dinv[i - one]
            l[i - one] = li
            d = diag[i] - li * sup[i - one]
            if not d > 0.0:
                ok = False
            dinv[i] = 1.0 / d
        bad[b] = not ok
    return not np.any(bad)


@njit(inline="always")
def _sweeps(dinv, l, r, x, lo, hi):
    one = np.uint64(1)
    x[lo] = r[lo]
    for i in range(lo + one, hi):
        x[i] = r[i] - l[i - one] * x[i - one]
    x[hi - one] = x[hi - one] * dinv[hi - one]
    for k in range(hi - lo - one):           # i = hi − 2 … lo
        i = hi - np.uint64(2) - k
        x[i] = x[i] * dinv[i] - l[i] * x[i + one]


@njit(parallel=True, cache=True)
def _solve(dinv, l, r, x, bounds):
    for b in prange(bounds.shape[0] - 1):
        _sweeps(dinv, l, r, x, np.uint64(bounds[b]), np.uint64(bounds[b + 1]))


@njit(parallel=True, cache=True)
def _solve_dot(dinv, l, r, x, bounds, part):
    """``x = A⁻¹ r``; returns ``r·x`` (summed per block, then over blocks in order)."""
    for b in prange(bounds.shape[0] - 1):
        lo = np.uint64(bounds[b])
        hi = np.uint64(bounds[b + 1])
        _sweeps(dinv, l, r, x, lo, hi)
        s = 0.0
        for i in range(lo, hi):
            s += r[i] * x[i]
        part[b] = s
    return _ordered_sum(part)


@njit(parallel=True, cache=True)
def _update_solve_dot(dinv, l, bounds, x, r, p, ap, alpha, z, part_rr, part_rz):
    """One PCG update fused with the preconditioner, block by block (each block's vectors
    stay in cache between the passes): ``x += α p``, ``r −= α Ap``, ``z = A⁻¹ r``. Returns
    ``(‖r‖², r·z)``, each summed per block and then over blocks in order."""
    for b in prange(bounds.shape[0] - 1):
        lo = np.uint64(bounds[b])
        hi = np.uint64(bounds[b + 1])
        s = 0.0
        for i in range(lo, hi):
            x[i] += alpha * p[i]
            ri = r[i] - alpha * ap[i]
            r[i] = ri
            s += ri * ri
        part_rr[b] = s
        _sweeps(dinv, l, r, z, lo, hi)
        s = 0.0
        for i in range(lo, hi):
            s += r[i] * z[i]
        part_rz[b] = s
    return _ordered_sum(part_rr), _ordered_sum(part_rz)


def column_bounds(cut: np.ndarray, blocks: int = BLOCKS) -> np.ndarray:
    """Start of each of up to ``blocks`` runs of unknowns (and the end, ``n``) that split a
    tridiagonal system where ``cut[i]`` drops the coupling of i and i + 1: the first cut at or
    after each of ``blocks`` equal shares."""
    n = len(cut) + 1
    cuts = np.flatnonzero(np.asarray(cut, bool)) + 1        # a new block may start here
    want = np.linspace(0, n, blocks + 1)[1:-1]
    pos = np.searchsorted(cuts, want)
    starts = cuts[pos[pos < len(cuts)]]
    return np.unique(np.concatenate([[0], starts, [n]])).astype(np.int64)


def tridiagonal_factor(diag: np.ndarray, sup: np.ndarray, bounds: np.ndarray | None = None):
    """``A = L D Lᵀ`` of the symmetric tridiagonal matrix with diagonal ``diag`` (n,) and
    super-diagonal ``sup`` (n − 1,) (``sup[i]`` couples i and i + 1). ``bounds``
    (:func:`column_bounds`) splits it where ``sup`` is zero. Returns ``(1/D, l, bounds)``;
    raises :class:`numpy.linalg.LinAlgError` unless ``A`` is positive definite."""
    diag = np.ascontiguousarray(diag, dtype=np.float64)
    sup = np.ascontiguousarray(sup, dtype=np.float64)
    n = len(diag)
    bounds = np.array([0, n], np.int64) if bounds is None else bounds
    dinv = np.empty_like(diag)
    l = np.empty(max(n - 1, 0))
    if n and not _factor(diag, sup, dinv, l, bounds):
        raise np.linalg.LinAlgError("tridiagonal matrix is not positive definite")
    return dinv, l, bounds


def tridiagonal_solve(factor, rhs: np.ndarray) -> np.ndarray:
    """Solve ``A x = rhs`` with the factor of :func:`tridiagonal_factor`."""
    dinv, l, bounds = factor
    x = np.empty_like(dinv)
    if len(dinv):
        _solve(dinv, l, np.ascontiguousarray(rhs, dtype=np.float64), x, bounds)
    return x


class ColumnSolve:
    """``r ↦ A⁻¹ r`` with a :func:`tridiagonal_factor` (a preconditioner's ``apply``), and
    optionally groups of columns solved as dense blocks instead (``aggregates``, factorised:
    :mod:`shipthermal._aggregates`).

    :func:`shipthermal.linear.pcg` recognises it (``update_solve``) and fuses the solve with
    its vector updates and dot products, the sums then taken over the factor's blocks and
    the groups: deterministic whatever the number of threads.
    """

    def __init__(self, factor, aggregates=None):
        self.factor = factor
        self.aggregates = aggregates if aggregates is not None and aggregates.n_groups else None
        self._part = np.empty(max(len(factor[2]) - 1, 0))
        self._part2 = np.empty_like(self._part)
        self._part_agg = np.empty(self.aggregates.n_groups if self.aggregates else 0)

    def _groups(self, r, z) -> float:
        return 0.0 if self.aggregates is None else self.aggregates.solve(r, z, self._part_agg)

    def __call__(self, r: np.ndarray) -> np.ndarray:
        r = np.ascontiguousarray(r, dtype=np.float64)
        z = tridiagonal_solve(self.factor, r)
        self._groups(r, z)
        return z

    def solve_dot(self, r: np.ndarray, z: np.ndarray) -> float:
        """``z = A⁻¹ r`` (into ``z``); returns ``r·z``. ``r`` float64, contiguous."""
        dinv, l, bounds = self.factor
        if not len(dinv):
            return 0.0
        rz = _solve_dot(dinv, l, r, z, bounds, self._part)
        return rz + self._groups(r, z)

    def update_solve(self, x, r, p, ap, alpha: float, z):
        """``x += α p``, ``r −= α Ap``, ``z = A⁻¹ r``; returns ``(‖r‖², r·z)``."""
        dinv, l, bounds = self.factor
        if not len(dinv):
            return 0.0, 0.0
        rr, rz = _update_solve_dot(dinv, l, bounds, x, r, p, ap, float(alpha), z, self._part,
                                   self._part2)
        return rr, rz + self._groups(r, z)


@njit(parallel=True, cache=True)
def _bands(data, diag_pos, sup_pos, cut, diag, sup):
    n = diag_pos.shape[0]
    for i in prange(n):
        diag[i] = data[np.uint64(diag_pos[i])]
    for i in prange(n - 1):
        sup[i] = 0.0 if (cut[i] or sup_pos[i] < 0) else data[np.uint64(sup_pos[i])]


def column_factor(data: np.ndarray, diag_pos: np.ndarray, sup_pos: np.ndarray,
                  cut: np.ndarray, bounds: np.ndarray | None = None):
    """The tridiagonal factor of a CSR matrix's through-thickness band, read from its value
    array ``data``: diagonal at ``diag_pos``, ``(i, i + 1)`` at ``sup_pos`` (−1: not
    stored); couplings with ``cut[i]`` True (column boundaries) are dropped. ``bounds``:
    :func:`column_bounds` of ``cut`` (computed here when not given)."""
    n = len(diag_pos)
    diag = np.empty(n)
    sup = np.empty(max(n - 1, 0))
    _bands(data, diag_pos, sup_pos, cut, diag, sup)
    return tridiagonal_factor(diag, sup, column_bounds(cut) if bounds is None else bounds)
