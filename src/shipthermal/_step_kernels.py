"""The per-cell and per-face kernels of a Newton pass of :mod:`.simulation` (numba, on the
process's threads): the residual and its boundary diagonal, the convergence estimate, the
surface temperatures moved with their cells, and the face-to-face exchange couplings of
the Jacobian."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

__all__ = ["cell_residual", "max_ratio", "moved_faces_kernel", "exchange_values"]


@njit(parallel=True, cache=True)
def exchange_values(data, row, col, t3, s, scale, out):
    """``scale · R_ij · ½(T_i³ + T_j³) · s_i s_j`` for every stored ``R_ij``."""
    for k in prange(data.shape[0]):
        i = np.uint64(row[k])
        j = np.uint64(col[k])
        out[k] = scale * data[k] * 0.5 * (t3[i] + t3[j]) * s[i] * s[j]


def cell_residual(g, temp, hist, a, dt, theta, bs, corr_cell, source, explicit):
    """Per cell: the net flow ``F = −K T + Σ_b Q_b + corr + source`` [W], the residual
    ``C (a T − T*)/Δt − θ F − explicit`` [W] and the boundary part of the Jacobian's diagonal
    ``θ Σ_b G_b`` [W K-1], in one pass over the cells on the process's threads (each cell
    gathers its faces; conduction from temperature differences as in
    :func:`.model.conduction_flows`)."""
    n = g.n_cells
    ptr, nb, gc = g.cell_faces
    bptr, bface = g.cell_bfaces
    none = np.zeros(0)
    corr = none if np.isscalar(corr_cell) else np.ascontiguousarray(corr_cell, dtype=np.float64)
    if np.isscalar(corr_cell) and corr_cell != 0.0:
        corr = np.full(n, float(corr_cell))
    flow, resid, jdiag_b = np.empty(n), np.empty(n), np.empty(n)
    _cell_residual_kernel(ptr, nb, gc, bptr, bface, np.ascontiguousarray(temp), hist,
                          g.heat_capacity, float(a), float(dt), float(theta), bs.flow,
                          bs.conductance, corr, np.ascontiguousarray(source, dtype=np.float64),
                          none if explicit is None else explicit, flow, resid, jdiag_b)
    return flow, resid, jdiag_b


@njit(parallel=True, cache=True)
def _cell_residual_kernel(ptr, nb, gc, bptr, bface, temp, hist, cap, a, dt, theta, bflow,
                          bcond, corr, source, explicit, flow, resid, jdiag_b):
    with_corr = corr.shape[0] > 0
    with_explicit = explicit.shape[0] > 0
    for c in prange(temp.shape[0]):
        tc = temp[c]
        f = 0.0
        for k in range(np.uint64(ptr[c]), np.uint64(ptr[c + 1])):
            f += gc[k] * (temp[np.uint64(nb[k])] - tc)
        fb = 0.0
        gb = 0.0
        for k in range(np.uint64(bptr[c]), np.uint64(bptr[c + 1])):
            b = np.uint64(bface[k])
            fb += bflow[b]
            gb += bcond[b]
        fl = f + fb
        if with_corr:
            fl += corr[c]
        fl += source[c]
        flow[c] = fl
        r = cap[c] / dt * (a * tc - hist[c]) - theta * fl
        if with_explicit:
            r -= explicit[c]
        resid[c] = r
        jdiag_b[c] = theta * gb


def max_ratio(num, den):
    """``max |num / den|`` without the temporaries (NaN if any ratio is)."""
    blocks = min(_REDUCE_BLOCKS, max(1, num.shape[0]))
    part = np.empty(blocks)
    _max_ratio_kernel(num, den, part)
    return float(np.max(part))     # (a NaN block wins, as in numpy's max)


#: Blocks of the one-pass maxima (a max does not depend on their order).
_REDUCE_BLOCKS = 64


@njit(parallel=True, cache=True)
def _max_ratio_kernel(num, den, part):
    n = num.shape[0]
    nb = part.shape[0]
    for b in prange(nb):
        m = 0.0
        for i in range(b * n // nb, (b + 1) * n // nb):
            v = abs(num[i] / den[i])
            if v != v:
                m = v
                break
            if v > m:
                m = v
        part[b] = m


@njit(parallel=True, cache=True)
def moved_faces_kernel(temp_face, delta, slope, bcell, out):
    """``out = T_s + s ΔT_cell`` face by face (no gathered temporary)."""
    for i in prange(temp_face.shape[0]):
        out[i] = temp_face[i] + slope[i] * delta[np.uint64(bcell[i])]
