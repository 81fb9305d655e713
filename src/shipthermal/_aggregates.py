"""Column aggregates of the ``column`` preconditioner: plate columns whose sideways couplings
are strong against their own stiffness, solved together with their neighbours.

The ``column`` preconditioner solves every plate column (the cells through one surface
triangle) exactly and drops the couplings between columns: sideways conduction along the
plates and face-to-face radiation. Its PCG convergence is set by the columns where those
dropped couplings are largest against the column's own stiffness ``Σ (C a/Δt + boundary)``
— small sliver triangles at plate edges, whose neighbours hold them. On a Jacobian of the
built-in frigate day at 0.5 m (then with two steel cells, 257 k cells) the preconditioned
spectrum was [0.42, 1.58], its extreme eigenvectors on such columns (dropped/own above 0.5
on 246 of 59 694 columns; median 0.12).

:func:`column_aggregates` groups every column whose ratio of dropped to own coupling
exceeds :data:`AGGREGATE_RATIO` (and is among the worst :data:`AGGREGATE_SHARE` of the
columns) with its most strongly coupled neighbours (greedily, until the group's own ratio is
below it, at most :data:`AGGREGATE_MAX_COLUMNS` columns); the preconditioner then solves
each group as one small dense SPD block (Cholesky) instead of column by column. Measured on
that Jacobian (PCG iterations to 1e-3 / 1e-4 / 1e-6): columns alone 5–7 / 6–9 / 10–12,
grouped at ratio 0.2 without the share cap 3–4 / 5 / 7–8 (at 0.15 no better); over the
frigate day (197 k cells) 5 730 → 4 110 PCG iterations (4.0 a Newton pass) with the 5 %
cap, 3 801 with 10 % at no gain in time (the dense solves cost more per iteration); a patrol
boat's day 5 800 → 3 202.

The groups depend on the matrix values through the ratio; the solver finds them once, from
its first Jacobian (a step length scales every column's own stiffness alike, so the worst
columns stay the worst), and factorises the dense blocks from every new Jacobian. The
kernels run group by group on the process's threads and sum per group in a fixed order:
results do not depend on the number of threads.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numba import njit, prange

__all__ = ["AGGREGATE_RATIO", "AGGREGATE_MAX_COLUMNS", "AGGREGATE_SHARE", "Aggregates",
           "column_aggregates"]

#: Dropped-to-own coupling ratio above which a column is grouped with its neighbours.
AGGREGATE_RATIO = 0.2
#: Most columns in one group (a group of 6 columns of 6 cells is a 36 × 36 block).
AGGREGATE_MAX_COLUMNS = 6
#: Largest share of the columns that start a group (the worst ones): with long steps the
#: own stiffness shrinks and most columns pass :data:`AGGREGATE_RATIO` (frigate, 900 s
#: steps: 23 k groups holding 89 % of the cells, whose dense solves cost more than the
#: iterations they saved); the ratio of the group's own is then this quantile's.
AGGREGATE_SHARE = 0.05


@dataclass
class Aggregates:
    """Groups of plate columns solved as dense blocks.

    ``cells[ptr[g]:ptr[g + 1]]`` are the cells of group g (ascending); ``pos``, ``li``,
    ``lj`` (grouped by ``entry_ptr``) the value-array positions of the matrix entries inside
    each group and their local row and column; ``fac`` holds the Cholesky factors (group g's
    ``s × s`` block at ``fac_ptr[g]``, row-major, lower triangle)."""

    ptr: np.ndarray
    cells: np.ndarray
    entry_ptr: np.ndarray
    pos: np.ndarray
    li: np.ndarray
    lj: np.ndarray
    fac_ptr: np.ndarray
    fac: np.ndarray
    _scratch: np.ndarray | None = None

    #: the structure's arrays (what a checkpoint keeps: :meth:`from_arrays`)
    FIELDS = ("ptr", "cells", "entry_ptr", "pos", "li", "lj", "fac_ptr")

    @property
    def n_groups(self) -> int:
        return len(self.ptr) - 1

    def arrays(self) -> dict:
        """The groups' structure (no factors) as named arrays."""
        return {k: getattr(self, k) for k in self.FIELDS}

    @classmethod
    def from_arrays(cls, arrays) -> "Aggregates":
        """The groups of :meth:`arrays` (factorise before use)."""
        a = {k: np.asarray(arrays[k], dtype=np.int64).copy() for k in cls.FIELDS}
        return cls(**a, fac=np.zeros(int(a["fac_ptr"][-1]) if len(a["fac_ptr"]) else 0))

    def factor(self, data: np.ndarray) -> None:
        """Fill and factorise every group's block from the matrix value array ``data``."""
        if self.n_groups and not _factor(data, self.ptr, self.entry_ptr, self.pos, self.li,
                                          self.lj, self.fac_ptr, self.fac):
            raise np.linalg.LinAlgError("a column group's block is not positive definite")

    def solve(self, r: np.ndarray, z: np.ndarray, part: np.ndarray) -> float:
        """Overwrite ``z`` on the groups' cells with their block solves of ``r``; returns the
        change of ``r·z`` this makes (``part``: scratch of one value per group)."""
        if not self.n_groups:
            return 0.0
        if self._scratch is None:
            self._scratch = np.empty(len(self.cells))
        return _solve(self.ptr, self.cells, self.fac_ptr, self.fac, r, z, part, self._scratch)


def column_aggregates(matrix: sp.csr_matrix, cut: np.ndarray,
                      ratio: float = AGGREGATE_RATIO,
                      max_columns: int = AGGREGATE_MAX_COLUMNS,
                      share: float = AGGREGATE_SHARE) -> Aggregates:
    """Group the columns of ``matrix`` (a symmetric CSR matrix with sorted indices; columns
    are runs of cells, ``cut[i]`` True where cells i and i + 1 are in different columns) as
    in the module docstring: columns whose ratio exceeds ``ratio`` and the ``1 − share``
    quantile of all ratios."""
    m = matrix
    n = m.shape[0]
    col = np.concatenate([[0], np.cumsum(cut)]).astype(np.int64)
    nc = int(col[-1]) + 1 if n else 0
    starts = np.concatenate([[0], np.flatnonzero(cut) + 1, [n]]).astype(np.int64)
    rows = np.repeat(np.arange(n), np.diff(m.indptr))
    cr, cc = col[rows], col[m.indices]
    off = cr != cc
    a = np.abs(m.data[off])
    # own stiffness of a column: its in-column row sums, Σ_i Σ_{j in column} a_ij
    own = np.bincount(cr[~off], m.data[~off], nc)
    dropped = np.bincount(cr[off], a, nc)
    graph = sp.csr_matrix((a, (cr[off], cc[off])), shape=(nc, nc))
    graph.sum_duplicates()
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(own > 0, dropped / own, np.inf)
    if nc:
        ratio = max(ratio, float(np.quantile(r, 1.0 - share)))
    order = np.argsort(-r, kind="stable")
    order = order[r[order] > ratio].astype(np.int64)
    group = _greedy(order, dropped, own, graph.indptr.astype(np.int64),
                    graph.indices.astype(np.int64), graph.data, float(ratio), int(max_columns),
                    nc)
    # cells of each group, groups in order of their first column
    grouped = np.flatnonzero(group >= 0)
    ccols = grouped[np.argsort(group[grouped], kind="stable")]
    gid = group[ccols]
    lengths = starts[ccols + 1] - starts[ccols]
    cells = np.concatenate([np.arange(starts[q], starts[q + 1]) for q in ccols]) \
        if len(ccols) else np.zeros(0, np.int64)
    cell_gid = np.repeat(gid, lengths)
    n_groups = int(gid.max()) + 1 if len(gid) else 0
    size = np.bincount(cell_gid, minlength=n_groups).astype(np.int64)
    ptr = np.concatenate([[0], np.cumsum(size)]).astype(np.int64)
    # cells were emitted group by group and column by column (columns ascend in a group
    # only if their indices do): sort within groups so local indices ascend
    key = np.lexsort((cells, cell_gid))
    cells, cell_gid = cells[key].astype(np.int64), cell_gid[key]
    local = np.full(n, -1, np.int64)
    local[cells] = np.arange(len(cells)) - ptr[cell_gid]
    gcell = np.full(n, -1, np.int64)
    gcell[cells] = cell_gid
    # entries inside a group
    gr, gc = gcell[rows], gcell[m.indices]
    inside = np.flatnonzero((gr >= 0) & (gr == gc))
    by = np.argsort(gr[inside], kind="stable")
    inside = inside[by]
    entry_ptr = np.concatenate([[0], np.cumsum(np.bincount(gr[inside],
                                                           minlength=n_groups))]).astype(np.int64)
    fac_ptr = np.concatenate([[0], np.cumsum(size * size)]).astype(np.int64)
    return Aggregates(ptr=ptr, cells=cells, entry_ptr=entry_ptr,
                      pos=inside.astype(np.int64), li=local[rows[inside]],
                      lj=local[m.indices[inside]], fac_ptr=fac_ptr,
                      fac=np.zeros(int(fac_ptr[-1])))


@njit(cache=True)
def _greedy(order, dropped, own, gptr, gidx, gval, ratio, max_columns, nc):
    """Column → group (−1: alone). Worst columns first; a group grows by the free column
    most strongly coupled to it while its ratio (couplings leaving it over its own
    stiffness) exceeds ``ratio``."""
    group = np.full(nc, -1, np.int64)
    acc = np.zeros(nc)
    members = np.empty(max_columns, np.int64)
    n_groups = 0
    for c0 in order:
        if group[c0] >= 0:
            continue
        members[0] = c0
        k = 1
        group[c0] = n_groups
        while k < max_columns:
            out = 0.0
            stiff = 0.0
            for q in range(k):
                m = members[q]
                out += dropped[m]
                stiff += own[m]
                for e in range(gptr[m], gptr[m + 1]):
                    if group[gidx[e]] == n_groups:
                        out -= gval[e]
            if out <= ratio * stiff:
                break
            # the free neighbour most strongly coupled to the group
            best = -1
            best_val = 0.0
            for q in range(k):
                m = members[q]
                for e in range(gptr[m], gptr[m + 1]):
                    j = gidx[e]
                    if group[j] < 0:
                        acc[j] += gval[e]
            for q in range(k):
                m = members[q]
                for e in range(gptr[m], gptr[m + 1]):
                    j = gidx[e]
                    if group[j] < 0:
                        if acc[j] > best_val or (acc[j] == best_val and best >= 0 and j < best):
                            best_val = acc[j]
                            best = j
            for q in range(k):
                m = members[q]
                for e in range(gptr[m], gptr[m + 1]):
                    acc[gidx[e]] = 0.0
            if best < 0:
                break
            members[k] = best
            group[best] = n_groups
            k += 1
        if k == 1:
            group[c0] = -1          # no free neighbour: the column stays alone
        else:
            n_groups += 1
    return group


@njit(parallel=True, cache=True)
def _factor(data, ptr, entry_ptr, pos, li, lj, fac_ptr, fac):
    bad = np.zeros(ptr.shape[0] - 1, np.bool_)
    for g in prange(ptr.shape[0] - 1):
        s = ptr[g + 1] - ptr[g]
        f0 = fac_ptr[g]
        for k in range(s * s):
            fac[f0 + k] = 0.0
        for e in range(entry_ptr[g], entry_ptr[g + 1]):
            fac[f0 + li[e] * s + lj[e]] = data[pos[e]]
        # Cholesky, lower triangle in place (row-major)
        for j in range(s):
            d = fac[f0 + j * s + j]
            for k in range(j):
                d -= fac[f0 + j * s + k] * fac[f0 + j * s + k]
            if not d > 0.0:
                bad[g] = True
                d = 1.0
            d = np.sqrt(d)
            fac[f0 + j * s + j] = d
            for i in range(j + 1, s):
                v = fac[f0 + i * s + j]
                for k in range(j):
                    v -= fac[f0 + i * s + k] * fac[f0 + j * s + k]
                fac[f0 + i * s + j] = v / d
    return not np.any(bad)


@njit(parallel=True, cache=True)
def _solve(ptr, cells, fac_ptr, fac, r, z, part, y):
    # (unsigned indices: numba then drops its negative-index test on every access)
    for g in prange(ptr.shape[0] - 1):
        c0 = np.uint64(ptr[g])
        s = np.uint64(ptr[g + 1]) - c0
        f0 = np.uint64(fac_ptr[g])
        for i in range(s):                       # L y = r, by rows of L
            row = f0 + i * s
            v = r[np.uint64(cells[c0 + i])]
            for k in range(i):
                v -= fac[row + k] * y[c0 + k]
            y[c0 + i] = v / fac[row + i]
        for ii in range(s):                      # Lᵀ x = y, by rows of L as well
            i = s - np.uint64(1) - ii
            row = f0 + i * s
            v = y[c0 + i] / fac[row + i]
            y[c0 + i] = v
            for k in range(i):
                y[c0 + k] -= fac[row + k] * v
        d = 0.0
        for i in range(s):
            c = np.uint64(cells[c0 + i])
            d += r[c] * (y[c0 + i] - z[c])
            z[c] = y[c0 + i]
        part[g] = d
    total = 0.0
    for g in range(part.shape[0]):
        total += part[g]
    return total
