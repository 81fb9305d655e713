"""Linear solves for the implicit thermal system: a reusable preconditioner and PCG.

The Jacobian of every time step is ``J = a C/Δt + θ (K + diag(G_b))``: symmetric positive
definite, with ``K`` fixed by the mesh and only the diagonal boundary part ``G_b`` (convection,
linearised radiation) changing from step to step. So one preconditioner — an exact sparse
factorisation or an algebraic-multigrid hierarchy of some earlier ``J`` — serves many
steps: each Newton correction is a preconditioned conjugate-gradient solve with the *current*
``J`` (one iteration when the preconditioner is the exact factor of it), and the
preconditioner is rebuilt only when the iterations creep up or ``Δt``/the scheme changes.

Backends
--------
``"direct"``
    SuperLU (scipy) with the ``MMD_AT_PLUS_A`` ordering. Shell meshes fill in like 2-D
    problems and factor in seconds; 3-D tetrahedral meshes do not (372 s with COLAMD at
    205 k unknowns, measured on a 2-core machine), so ``auto`` tries it only on small ones.
``"amg"``
    pyamg smoothed aggregation (Olson & Schroder 2018), one V-cycle per preconditioner
    application.
``"column"``
    Shell graphs only: the tridiagonal through-thickness part of ``J`` (every plate column
    with its exact current diagonal; lateral conduction left out), Cholesky-factorised as
    one tridiagonal matrix (LDLᵀ, O(n), numba: :mod:`._tridiagonal`) and rebuilt at every
    Newton iteration. In a plate the lateral conductance of a cell is ~1e-3–1e-2 of its
    diagonal (thin layers, large C/Δt), so PCG converges to 1e-13 in a handful of O(n)
    iterations; the matrix is diagonally dominant, so the banded part is positive definite.
``"cholmod"``
    Sparse Cholesky (SuiteSparse CHOLMOD, supernodal) through the ``kvxopt`` wheel, which
    bundles SuiteSparse (a main dependency; no system packages). Measured here (2 shared
    cores) on the vertex-centred graph of a pytetwild cube, 96 k vertices (~15 nonzeros per
    row): factor 10.6–11.4 s, solve 0.105–0.12 s; SuperLU (MMD_AT_PLUS_A) 590 s and 3.0 s
    (190 M fill); pyamg setup 0.3–0.5 s, 0.34 s per PCG solve to 1e-13 in isolation.
``"auto"``
    ``"column"`` for shell graphs. Otherwise chosen by measurement on the first matrix of a
    given size (:func:`measure_backends`): every candidate builds its preconditioner and
    does one PCG solve of a fixed right-hand side to ``rtol = 1e-10``; the predicted cost of
    ``n`` solves is ``setup + n × solve`` (CPU seconds of the process) with ``n`` =
    :data:`AUTO_SOLVES` (a preconditioner
    is reused over many steps), and the cheapest wins (AMG only by a margin,
    :data:`AUTO_AMG_MARGIN`, over an exact factor). The loser's set-up is the price of
    the measurement; the winner's preconditioner is the one returned. The choice is logged
    (logger ``shipthermal.linear``), kept per matrix size and pattern for later rebuilds
    (a new Δt), and changes results only within the solver tolerance: every backend solves
    the same system by PCG to the same residual.

    Candidates: CHOLMOD (when ``kvxopt`` imports), AMG, and SuperLU where its fill cannot
    blow up the measurement — without CHOLMOD, and up to :data:`SUPERLU_MEASURE_LIMIT`
    unknowns (2.8 s at 23 k vertices, 590 s at 96 k: its fill on 3-D graphs grows far faster
    than CHOLMOD's). Without ``kvxopt`` this is the fallback: SuperLU or AMG, measured.

    Measured here on the steel box of ``benchmarks/bench_solver.py box`` (one pytetwild
    mesh, BDF2 Jacobian at Δt = 10 s; set-up + one solve): vertex-centred, 24 k unknowns,
    CHOLMOD 0.82 + 0.025 s, AMG 0.33 + 0.089 s (6 PCG iterations), SuperLU 4.3 + 0.052 s;
    cell-centred, 128 k unknowns, CHOLMOD 2.7 + 0.084 s, AMG 0.47 + 0.38 s (9 iterations).
    On the 257 k-cell frigate shells the ``column`` preconditioner stays: 6 h of the day in
    34 s against 72 s with a CHOLMOD factor reused as preconditioner (1.6 PCG iterations
    per Newton pass at 0.16 s a solve), same answer to 5e-11 K.
"""

from __future__ import annotations

import functools
import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numba import njit, prange

from ._tridiagonal import ColumnSolve, _ordered_sum, column_bounds, tridiagonal_factor
from .errors import require

__all__ = ["LINEAR_SOLVERS", "Preconditioner", "make_preconditioner", "pcg", "choose_backend",
           "measure_backends", "has_cholmod", "Anderson", "AUTO_SOLVES", "AUTO_AMG_MARGIN",
           "SUPERLU_MEASURE_LIMIT", "JacobianPattern", "single_threaded_blas"]

LINEAR_SOLVERS = ("auto", "direct", "amg", "column", "cholmod")
#: Number of solves one preconditioner is expected to serve, for ``auto``'s cost prediction
#: ``setup + AUTO_SOLVES × solve``: a run reuses it over its steps (one or two Newton
#: solves each), and a new Δt or scheme rebuilds it; 100 ≈ a few dozen to a few hundred steps.
AUTO_SOLVES = 100
#: AMG replaces an exact factor only when predicted at least this much cheaper (× the
#: factor's cost): timings on a shared machine vary by ±30 %, and an exact factor keeps a
#: linear step at one PCG iteration, i.e. its Newton passes independent of conditioning.
AUTO_AMG_MARGIN = 0.5
#: Largest system on which ``auto`` measures SuperLU (3-D fill: 2.8 s at 23 k unknowns,
#: 590 s at 96 k, measured on the benchmark cubes of ``benchmarks/bench_solver.py``).
SUPERLU_MEASURE_LIMIT = 40_000

_log = logging.getLogger(__name__)
# ``auto``'s choice per matrix pattern (size, nonzeros, a fingerprint of the column indices)
# and set of candidates, so that rebuilding the preconditioner (a new Δt, a drifted Jacobian) does not measure again.
_AUTO_CHOICES: dict[tuple, str] = {}


def choose_backend(backend: str, n_cells: int, kind: str) -> str:
    """Validate ``backend`` and resolve what can be resolved without a matrix.

    ``"auto"`` becomes ``"column"`` on shell graphs and stays ``"auto"`` otherwise (chosen
    by measurement when the first preconditioner is built, see the module docstring).
    """
    require(backend in LINEAR_SOLVERS, "linear_solver", backend, f"must be one of {LINEAR_SOLVERS}")
    if backend == "column":
        require(kind == "shell", "linear_solver", backend,
                f"'column' needs a shell cell graph (this one is {kind!r})")
    if backend == "cholmod":
        require(has_cholmod(), "linear_solver", backend,
                "'cholmod' needs the kvxopt package", "pip install kvxopt")
    if backend == "auto" and kind == "shell":
        return "column"
    return backend


def has_cholmod() -> bool:
    """True when ``kvxopt`` (CHOLMOD) imports."""
    try:
        import kvxopt.cholmod  # noqa: F401
    except ImportError:
        return False
    return True


def _cholmod_factor(matrix: sp.spmatrix):
    """CHOLMOD ``L Lᵀ`` of an SPD matrix (kvxopt); returns ``solve(r)``."""
    import kvxopt
    from kvxopt import cholmod

    low = sp.tril(matrix, format="coo")
    n = matrix.shape[0]
    a = kvxopt.spmatrix(low.data.astype(float), kvxopt.matrix(low.row.astype(np.int64)),
                        kvxopt.matrix(low.col.astype(np.int64)), (n, n))
    factor = cholmod.symbolic(a, uplo="L")
    cholmod.numeric(a, factor)

    def solve(r):
        b = kvxopt.matrix(np.asarray(r, dtype=float))
        cholmod.solve(factor, b)
        return np.asarray(b).ravel()

    return solve


def _candidates(n: int) -> tuple[str, ...]:
    if has_cholmod():
        return ("cholmod", "amg")
    return ("direct", "amg") if n <= SUPERLU_MEASURE_LIMIT else ("amg",)


def _pattern_key(matrix: sp.csr_matrix) -> tuple:
    idx = matrix.indices
    step = max(1, len(idx) // 1000)
    return (matrix.shape[0], matrix.nnz, hash(idx[::step].tobytes()))


def measure_backends(matrix: sp.spmatrix, candidates=None, solves: int = AUTO_SOLVES):
    """Time each candidate backend on ``matrix``: preconditioner set-up and one PCG solve of a
    fixed right-hand side to ``rtol = 1e-10``.

    Returns ``(best, table, preconditioners)``: the backend with the least predicted cost
    ``setup + solves × solve`` (AMG by :data:`AUTO_AMG_MARGIN` over an exact factor), ``{backend: (setup s, solve s, PCG iterations, predicted
    s)}`` and the built preconditioners (so the winner's need not be built again).
    """
    m = sp.csr_matrix(matrix)
    n = m.shape[0]
    candidates = _candidates(n) if candidates is None else tuple(candidates)
    # A smooth, deterministic solution: the right-hand side is the same on every call.
    x = np.sin(np.linspace(0.0, 7.0, n)) + 1.0
    rhs = m @ x
    table, precs = {}, {}
    # One BLAS thread, as in the solver's loop (a spinning OpenBLAS pool under load made
    # AMG's PCG solve 40× slower in a measurement here and would bias the choice).
    from threadpoolctl import threadpool_limits

    # Costs in the process's CPU time, not on the wall clock: on a shared machine a
    # descheduled set-up or solve reads several times its cost on the wall clock (box of
    # ``benchmarks/bench_solver.py`` beside five busy processes: CHOLMOD's factor 2.5 s on
    # the wall for 0.3 s of CPU, which handed the choice to AMG and doubled the run's CPU).
    with threadpool_limits(limits=1, user_api="blas"):
        for b in candidates:
            c0 = time.process_time()
            prec = make_preconditioner(m, b)
            t_setup = time.process_time() - c0
            t_solve = np.inf
            for _ in range(2):      # the cheaper of two: a cold first solve is not its cost
                c0 = time.process_time()
                _, it, _ = pcg(m, rhs, prec.apply, rtol=1e-10, max_iterations=500)
                t_solve = min(t_solve, time.process_time() - c0)
            table[b] = (t_setup, t_solve, it, t_setup + solves * t_solve)
            precs[b] = prec
    best = min(table, key=lambda b: table[b][3])
    exact = [b for b in table if b in ("cholmod", "direct")]
    if best == "amg" and exact and table["amg"][3] > AUTO_AMG_MARGIN * table[exact[0]][3]:
        best = exact[0]
    return best, table, precs


def _auto_preconditioner(matrix: sp.spmatrix) -> "Preconditioner":
    m = sp.csr_matrix(matrix)
    key = (*_pattern_key(m), _candidates(m.shape[0]))
    if key in _AUTO_CHOICES:
        return make_preconditioner(m, _AUTO_CHOICES[key])
    t0 = time.perf_counter()
    best, table, precs = measure_backends(m)
    _AUTO_CHOICES[key] = best
    why = "; ".join(f"{b}: set-up {s:.3g} s + {AUTO_SOLVES} × {t:.3g} s ({it} PCG it.) = {c:.3g} s"
                    for b, (s, t, it, c) in table.items())
    note = f"auto → {best} ({m.shape[0]} unknowns; {why})"
    _log.info("linear solver %s", note)
    prec = precs[best]
    return Preconditioner(best, prec.apply, time.perf_counter() - t0, note=note)


@dataclass
class Preconditioner:
    """An approximate inverse of a fixed SPD matrix: ``apply(r) ≈ A⁻¹ r``."""

    backend: str
    apply: object
    seconds_setup: float
    n_builds: int = 1
    note: str = ""


def make_preconditioner(matrix: sp.spmatrix, backend: str,
                        column_break: np.ndarray | None = None) -> Preconditioner:
    """Factorise (``direct``), build an AMG hierarchy (``amg``) or the banded through-thickness
    part (``column``; ``column_break[i]`` True where cells i and i+1 are not one plate
    column) of ``matrix``; ``auto``: the fastest of these by measurement (module docstring)."""
    if backend == "auto":
        return _auto_preconditioner(matrix)
    t0 = time.perf_counter()
    if backend == "column":
        m = sp.csr_matrix(matrix)
        apply = ColumnSolve(tridiagonal_factor(m.diagonal(),
                                               np.where(column_break, 0.0, m.diagonal(1)),
                                               column_bounds(column_break)))
    elif backend == "direct":
        lu = spla.splu(sp.csc_matrix(matrix), permc_spec="MMD_AT_PLUS_A",
                       options=dict(SymmetricMode=True))
        apply = lu.solve
    elif backend == "cholmod":
        apply = _cholmod_factor(matrix)
    elif backend == "amg":
        import pyamg

        ml = pyamg.smoothed_aggregation_solver(sp.csr_matrix(matrix), symmetry="symmetric",
                                               max_coarse=500)
        prec = ml.aspreconditioner(cycle="V")
        apply = prec.matvec
    else:  # pragma: no cover - guarded by choose_backend
        raise ValueError(backend)
    return Preconditioner(backend, apply, time.perf_counter() - t0)


def pcg(matrix: sp.csr_matrix, rhs: np.ndarray, precond, x0: np.ndarray | None = None,
        rtol: float = 1e-12, max_iterations: int = 200) -> tuple[np.ndarray, int, float]:
    """Preconditioned conjugate gradients for SPD ``matrix``.

    Stops when ``‖r‖ ≤ rtol ‖b‖``. Returns ``(x, iterations, relative residual)``; the caller
    decides what a slow convergence means (here: rebuild the preconditioner).

    A float64 CSR matrix goes through numba kernels on the process's thread budget
    (``numba.get_num_threads()``): the product fused with ``p·Ap``, and the vector updates
    fused with ``‖r‖²``. Measured on the 257 k-row, 2.64 M-nonzero Jacobian of the frigate
    day: the product 2.4 ms in scipy, 2.7 ms here on one thread, 1.6 ms on two. Every dot
    product is summed over :data:`PCG_BLOCKS` fixed row blocks and then in block order, so
    the iterates do not depend on the number of threads.
    """
    m = matrix if sp.issparse(matrix) else None
    fast = (m is not None and m.format == "csr" and m.dtype == np.float64
            and rhs.dtype == np.float64)
    if not fast:
        return _pcg_generic(matrix, rhs, precond, x0, rtol, max_iterations)
    n = len(rhs)
    blocks = _blocks(n)
    part = np.empty(len(blocks) - 1)
    rhs = np.ascontiguousarray(rhs)
    ap = np.empty(n)
    if x0 is None:
        x = np.zeros(n)
        r = rhs.copy()
    else:
        x = np.array(x0, dtype=np.float64)
        _csr_matvec_dot(m.indptr, m.indices, m.data, x, ap, blocks, part)
        r = rhs - ap
    bnorm = np.sqrt(_dot(rhs, rhs, blocks, part))
    if bnorm == 0.0:
        return x, 0, 0.0
    # A column preconditioner's solve is fused with the vector updates and dot products
    # (one pass over each block of unknowns instead of four over the whole vectors).
    fused = getattr(precond, "update_solve", None)
    if fused is not None:
        z = np.empty(n)
        rz = precond.solve_dot(r, z)
    else:
        z = np.ascontiguousarray(precond(r), dtype=np.float64)
        rz = _dot(r, z, blocks, part)
    p = z.copy()
    rel = np.sqrt(_dot(r, r, blocks, part)) / bnorm
    it = 0
    while rel > rtol and it < max_iterations:
        pap = _csr_matvec_dot(m.indptr, m.indices, m.data, p, ap, blocks, part)
        alpha = rz / pap
        if fused is not None:
            # (z of the last iteration is not needed: one solve of a block too many, for
            # one pass fewer over the vectors on every iteration)
            rr, rz_new = fused(x, r, p, ap, alpha, z)
            rel = np.sqrt(rr) / bnorm
        else:
            rel = np.sqrt(_update(x, r, p, ap, alpha, blocks, part)) / bnorm
        it += 1
        if rel <= rtol:
            break
        if fused is None:
            z = np.ascontiguousarray(precond(r), dtype=np.float64)
            rz_new = _dot(r, z, blocks, part)
        _xpby(z, p, rz_new / rz)
        rz = rz_new
    return x, it, rel


def _pcg_generic(matrix, rhs, precond, x0, rtol, max_iterations):
    x = np.zeros_like(rhs) if x0 is None else x0.copy()
    r = rhs - matrix @ x if x0 is not None else rhs.copy()
    bnorm = np.linalg.norm(rhs)
    if bnorm == 0.0:
        return x, 0, 0.0
    z = precond(r)
    p = z.copy()
    rz = r @ z
    rel = np.linalg.norm(r) / bnorm
    it = 0
    while rel > rtol and it < max_iterations:
        ap = matrix @ p
        alpha = rz / (p @ ap)
        x += alpha * p
        r -= alpha * ap
        rel = np.linalg.norm(r) / bnorm
        it += 1
        if rel <= rtol:
            break
        z = precond(r)
        rz_new = r @ z
        p = z + (rz_new / rz) * p
        rz = rz_new
    return x, it, rel


#: Row blocks of the PCG dot products: a fixed split, so sums do not depend on threads.
PCG_BLOCKS = 64


def _blocks(n: int) -> np.ndarray:
    return np.linspace(0, n, min(PCG_BLOCKS, max(n, 1)) + 1).astype(np.int64)


# The kernels index through unsigned integers: numba then drops the negative-index
# wraparound test on every access, which made a plain CSR product 1.7× slower than scipy's.
@njit(parallel=True, cache=True)
def _csr_matvec_dot(indptr, indices, data, x, out, blocks, part):
    """``out = A x`` and ``x·out`` (summed per block, then over blocks)."""
    for b in prange(blocks.shape[0] - 1):
        s_b = 0.0
        for i in range(blocks[b], blocks[b + 1]):
            s = 0.0
            for k in range(np.uint64(indptr[i]), np.uint64(indptr[i + 1])):
                s += data[k] * x[np.uint64(indices[k])]
            out[i] = s
            s_b += x[i] * s
        part[b] = s_b
    return _ordered_sum(part)


@njit(parallel=True, cache=True)
def _update(x, r, p, ap, alpha, blocks, part):
    """``x += α p``, ``r −= α Ap``; returns ``‖r‖²``."""
    for b in prange(blocks.shape[0] - 1):
        s_b = 0.0
        for i in range(blocks[b], blocks[b + 1]):
            x[i] += alpha * p[i]
            ri = r[i] - alpha * ap[i]
            r[i] = ri
            s_b += ri * ri
        part[b] = s_b
    return _ordered_sum(part)


@njit(parallel=True, cache=True)
def _dot(u, v, blocks, part):
    for b in prange(blocks.shape[0] - 1):
        s_b = 0.0
        for i in range(blocks[b], blocks[b + 1]):
            s_b += u[i] * v[i]
        part[b] = s_b
    return _ordered_sum(part)


@njit(parallel=True, cache=True)
def _xpby(z, p, beta):
    """``p = z + β p``."""
    for i in prange(p.shape[0]):
        p[i] = z[i] + beta * p[i]


class Anderson:
    """Anderson acceleration of a fixed-point iteration ``x ← x + f(x)`` (Walker & Ni 2011,
    type II, depth ``m``).

    Used where part of the operator is lagged inside a step (non-orthogonal correction on
    tetrahedra, face-to-face radiation): the plain deferred-correction iteration converges
    linearly (rate ≈ 0.5 on pytetwild cubes); for a linear map Anderson acceleration is
    equivalent to GMRES on it and needs a fraction of the iterations.
    """

    def __init__(self, depth: int = 5):
        self.depth = int(depth)
        self._x: list[np.ndarray] = []
        self._f: list[np.ndarray] = []

    def update(self, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        """Next iterate from the current one ``x`` and its update ``f``."""
        self._x.append(x.copy())
        self._f.append(f.copy())
        if len(self._x) > self.depth + 1:
            self._x.pop(0)
            self._f.pop(0)
        if len(self._x) == 1:
            return x + f
        df = np.stack([b - a for a, b in zip(self._f[:-1], self._f[1:])], axis=1)
        dx = np.stack([b - a for a, b in zip(self._x[:-1], self._x[1:])], axis=1)
        gamma, *_ = np.linalg.lstsq(df, f, rcond=None)
        return x + f - (dx + df) @ gamma


class JacobianPattern:
    """A fixed sparse matrix ``B`` (θ K) plus a diagonal that changes every Newton iteration.

    ``J = B + diag(d)`` was rebuilt with ``B + sp.diags(d)`` (a sparse sum: index checks,
    a new CSR, a sort) at every iteration: that was a third of a small tetrahedral run's
    time. Here the CSR structure of ``B`` with every diagonal entry stored is kept, and
    ``J``'s values are one copy of ``B``'s plus the diagonal added in place. Each call
    gives the matrix a fresh value array, so a preconditioner built from an earlier ``J``
    (which may share that array) is not changed under it.
    """

    def __init__(self, base: sp.spmatrix, extra_rows=None, extra_cols=None):
        n = base.shape[0]
        coo = sp.coo_matrix(base)
        eye = np.arange(n)
        er = np.zeros(0, np.int64) if extra_rows is None else np.asarray(extra_rows, np.int64)
        ec = np.zeros(0, np.int64) if extra_cols is None else np.asarray(extra_cols, np.int64)
        m = sp.csr_matrix((np.concatenate([coo.data, np.zeros(n), np.zeros(len(er))]),
                           (np.concatenate([coo.row, eye, er]), np.concatenate([coo.col, eye, ec]))),
                          shape=base.shape)
        m.sum_duplicates()
        m.sort_indices()
        rows = np.repeat(eye, np.diff(m.indptr))
        self.diag_pos = np.flatnonzero(m.indices == rows)
        assert len(self.diag_pos) == n
        # Positions of extra entries (face-to-face exchange couplings) in the value array.
        keys = rows.astype(np.int64) * n + m.indices
        self.extra_pos = np.searchsorted(keys, er * n + ec)
        # The same grouped by position (several exchange pairs may share one), in their
        # own order within a position: the fill then runs over positions in parallel and
        # adds in the order a plain loop over the extras would.
        order = np.argsort(self.extra_pos, kind="stable")
        upos, first = np.unique(self.extra_pos[order], return_index=True)
        self._extra_order = order.astype(np.int64)
        self._extra_upos = upos.astype(np.int64)
        self._extra_ptr = np.append(first, len(order)).astype(np.int64)
        # The cell whose diagonal such a position is (−1: off the diagonal).
        cell_of_pos = np.full(len(m.data), -1, np.int64)
        cell_of_pos[self.diag_pos] = eye
        self._extra_upos_cell = cell_of_pos[self._extra_upos]
        # Extras already in value-array order, one per position (the usual case): the fill
        # then reads them straight, without the grouping arrays.
        self._extra_plain = bool(len(upos) == len(order)
                                 and np.array_equal(order, np.arange(len(order))))
        self._filled = False    # does the matrix hold B everywhere the fill does not write?
        # Extra entries that land on the diagonal (two exchanging faces of one cell).
        self.extra_diag = np.flatnonzero(er == ec)
        self.extra_diag_cell = er[self.extra_diag]
        # Position of (i, i + 1) in the value array, −1 where not stored (column
        # preconditioner: the through-thickness band, read without scipy's diagonal()).
        pos = np.searchsorted(keys, eye[:-1] * (n + 1) + 1)
        pos = np.minimum(pos, len(keys) - 1)
        self.sup_pos = np.where(keys[pos] == eye[:-1] * (n + 1) + 1, pos, -1)
        self.base = m.data.copy()
        self.base_diag = self.base[self.diag_pos].copy()
        self.matrix = m
        self.n = n

    def diagonal(self, diagonal: np.ndarray, extra: np.ndarray | None = None) -> np.ndarray:
        """The diagonal of ``B + diag(diagonal)`` (+ ``extra``) without building the matrix."""
        d = self.base_diag + diagonal
        if extra is not None and len(self.extra_diag):
            d += np.bincount(self.extra_diag_cell, extra[self.extra_diag], self.n)
        return d

    def jacobian(self, diagonal: np.ndarray, extra: np.ndarray | None = None,
                 fresh: bool = True) -> sp.csr_matrix:
        """``B + diag(diagonal)`` (+ ``extra`` values at the extra entries, summed where
        they repeat). ``fresh=False`` refills the matrix's current value array in place
        (for a caller whose preconditioner keeps nothing of an earlier matrix: a new array
        of 10⁶–10⁷ values per Newton pass costs its page faults)."""
        # In place, only the diagonal and the exchange positions change (B's other values
        # stay): on the frigate a fresh fill takes 3.0 ms, this one 1.7 ms (two threads).
        full = fresh or not self._filled
        data = np.empty_like(self.matrix.data) if fresh else self.matrix.data
        none = np.zeros(0, np.int64)
        if extra is None:
            _fill_values(self.base, self.diag_pos, diagonal, none, np.zeros(1, np.int64), none,
                         np.zeros(0), none, data, full, True)
        else:
            _fill_values(self.base, self.diag_pos, diagonal, self._extra_upos, self._extra_ptr,
                         self._extra_order, extra, self._extra_upos_cell, data, full,
                         self._extra_plain)
        self._filled = True
        self.matrix.data = data
        return self.matrix


@njit(parallel=True, cache=True)
def _fill_values(base, diag_pos, diagonal, upos, ptr, order, extra, upos_cell, out, full,
                 plain):
    """``out = B + diag(diagonal) + extras`` (``full``: every value; else only the diagonal
    and the extra positions, ``out`` holding ``B`` elsewhere). Each value is summed as
    ``(B + d) + e₁ + e₂ …`` in the extras' own order (``plain``: extra u is the only one at
    ``upos[u]``)."""
    if full:
        for k in prange(base.shape[0]):
            out[k] = base[k]
    for i in prange(diag_pos.shape[0]):
        p = np.uint64(diag_pos[i])
        out[p] = base[p] + diagonal[i]
    for u in prange(upos.shape[0]):
        p = np.uint64(upos[u])
        c = upos_cell[u]
        acc = base[p] + diagonal[c] if c >= 0 else base[p]
        if plain:
            acc += extra[u]
        else:
            for k in range(np.uint64(ptr[u]), np.uint64(ptr[u + 1])):
                acc += extra[np.uint64(order[k])]
        out[p] = acc


def single_threaded_blas():
    """BLAS limited to one thread: the solver's vector operations (dot products of 10⁴–10⁶
    entries) gain nothing from threads, and an OpenBLAS pool spinning against other busy
    processes turned 10 µs dot products into milliseconds (measured here under load)."""
    return _blas_controller().limit(limits=1, user_api="blas")


@functools.cache
def _blas_controller():
    """threadpoolctl's view of the process's thread pools, found once: finding them scans
    every loaded library (8.5 ms per call in a ship run, paid at every ``run_until``: 48 a
    simulated day of 30-min outputs, 8 % of a weather record's solve at 2 m); limiting
    through it then takes 10 µs. By the first solve every BLAS the solver uses is loaded
    (numpy's and scipy's, imported with this module)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()
