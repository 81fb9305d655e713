"""Step kernels of the surface energy balance: the Thomas elimination of each column with
Newton on its surface node, a numba build (blocks of one class in parallel or on one thread),
a plain numpy reference doing the same arithmetic, and a numba kernel that runs a whole span
of steps with the log-law convection (each block through every step on one thread)."""

from __future__ import annotations

import types

import numpy as np
from numba import njit, prange

from shipthermal.units import SIGMA

from .air import GAS_CONSTANT_DRY_AIR, SPECIFIC_HEAT_AIR, VON_KARMAN



_NEWTON_TOL = 1.0e-7
"""Newton stops after an update below this [K]: the error left is about |F''/(2F')| δ² with
|F''/(2F')| < 1e-3 K-1 here (F' is dominated by the top half cell's conductance, ~1e3
W m-2 K-1; F'' by 12 εσT² and the latent term's e°''), i.e. below 1e-17 K: round-off."""
_NEWTON_MAX = 60
_KARMAN_SQUARED = VON_KARMAN ** 2


# ---------------------------------------------------------------------------------------------
# Step kernels
# ---------------------------------------------------------------------------------------------
def _factorise(n_cells, capacity, conductance, dt, theta):
    """The time-independent part of the Thomas elimination from the bottom up, per class:
    ``C/Δt``, ``Q_i`` and ``1/den_i`` (elimination T_i = P_i + Q_i T_{i−1})."""
    n_cls, m_max = capacity.shape
    cap_dt = capacity / dt
    q = np.zeros((n_cls, m_max))
    inv_den = np.zeros((n_cls, m_max))
    for c in range(n_cls):
        m = n_cells[c]
        k = conductance[c]
        q_next = 0.0
        for i in range(m - 1, -1, -1):           # 0-based cell i, faces k[i] above, k[i+1] below
            den = cap_dt[c, i] + theta * (k[i] + k[i + 1])
            if i < m - 1:
                den -= theta * k[i + 1] * q_next
            inv_den[c, i] = 1.0 / den
            q[c, i] = theta * k[i] * inv_den[c, i]
            q_next = q[c, i]
    return cap_dt, q, inv_den


BLOCK = 64
"""Columns per block of the kernels: one class per block, the cell loops run across the
block's columns (independent chains: SIMD lanes and pipelining instead of one latency-bound
Thomas recurrence at a time)."""


def _blocks(class_index: np.ndarray, block: int = BLOCK) -> tuple:
    """Columns sorted by class (stable) and blocks ``(class, start, end)`` of that order, no
    block straddling two classes."""
    order = np.argsort(class_index, kind="stable")
    sorted_cls = class_index[order]
    rows = []
    start = 0
    n = len(order)
    while start < n:
        c = sorted_cls[start]
        end = start
        while end < n and end - start < block and sorted_cls[end] == c:
            end += 1
        rows.append((c, start, end))
        start = end
    return order.astype(np.int64), np.array(rows, dtype=np.int64).reshape(-1, 3)


def _step_blocks(temp, order, blocks, n_cells, cap_dt, cond, q, inv_den, theta, emis, rs, tbot,
                sw, lw, ta, rh, pres, h, dt, out, sb_old, acc, acc_abs, imbalance, work):
    """One step of every column, blocks in parallel; the arithmetic of
    :func:`_step_reference`. ``temp`` (M + 1, N): surface node then cells, columns in the
    sorted order ``order`` (sorted position → column), updated in place. Inputs and outputs
    per column are in the caller's order; ``out`` (6, N): long-wave net, sensible, latent,
    ground, bottom flux, new surface temperature. ``work`` (11, N): scratch rows (no
    allocation inside the loop)."""
    for bk in prange(blocks.shape[0]):
        _block_step(bk, temp, order, blocks, n_cells, cap_dt, cond, q, inv_den, theta, emis,
                    rs, tbot, sw, lw, ta, rh, pres, h, dt, out, sb_old, acc, acc_abs,
                    imbalance, work)


@njit(cache=True)
def _block_step(bk, temp, order, blocks, n_cells, cap_dt, cond, q, inv_den, theta, emis, rs,
                tbot, sw, lw, ta, rh, pres, h, dt, out, sb_old, acc, acc_abs, imbalance, work):
    """One step of the columns of block ``bk`` (:func:`_step_blocks`); it reads and writes
    only that block's columns (blocks run in parallel)."""
    c = blocks[bk, 0]
    j0 = blocks[bk, 1]
    nb = blocks[bk, 2] - j0
    m = n_cells[c]
    col = order[j0:j0 + nb]
    tb = work[0, j0:j0 + nb]
    t_below_old = work[1, j0:j0 + nb]
    p_below = work[2, j0:j0 + nb]
    for jj in range(nb):
        tb[jj] = tbot[col[jj]]
        t_below_old[jj] = tb[jj]
        p_below[jj] = 0.0
    # upward elimination, temp[i] <- P_i (old values kept where still needed)
    for i in range(m, 0, -1):
        cd = cap_dt[c, i - 1]
        k_up = cond[c, i - 1]
        k_dn = cond[c, i]
        idn = inv_den[c, i - 1]
        c_bot = theta * k_dn if i == m else 0.0
        c_p = 0.0 if i == m else theta * k_dn
        row = temp[i, j0:j0 + nb]        # 1-D views: plain non-negative indices
        if theta < 1.0:
            above = temp[i - 1, j0:j0 + nb]
            for jj in range(nb):
                ti = row[jj]
                rhs = cd * ti + (1.0 - theta) * (k_up * (above[jj] - ti)
                                                 - k_dn * (ti - t_below_old[jj]))
                p = (rhs + c_bot * tb[jj] + c_p * p_below[jj]) * idn
                row[jj] = p
                p_below[jj] = p
                t_below_old[jj] = ti
        else:
            for jj in range(nb):
                p = (cd * row[jj] + c_bot * tb[jj] + c_p * p_below[jj]) * idn
                row[jj] = p
                p_below[jj] = p
    # surface node: G(x) = k0 (x − P_1 − Q_1 x) = a x − b; Newton on the block together
    k0 = cond[c, 0]
    a = k0 * (1.0 - q[c, 0])
    latent = rs[col[0]] >= 0.0
    swb = work[3, j0:j0 + nb]
    lwb = work[4, j0:j0 + nb]
    tab = work[5, j0:j0 + nb]
    hb = work[6, j0:j0 + nb]
    eb = work[7, j0:j0 + nb]
    ce = work[8, j0:j0 + nb]
    ea = work[9, j0:j0 + nb]
    x = work[10, j0:j0 + nb]
    surface = temp[0, j0:j0 + nb]
    t1 = temp[1, j0:j0 + nb]
    for jj in range(nb):
        ce[jj] = 0.0
        ea[jj] = 0.0
        j = col[jj]
        swb[jj] = sw[j]
        lwb[jj] = lw[j]
        tab[jj] = ta[j]
        hb[jj] = h[j]
        eb[jj] = emis[j]
        x[jj] = surface[jj]
        if latent:
            rho_cp = 1013.0 * pres[j] / (1.01 * 287.0 * ta[j])
            gamma = 1013.0 * pres[j] / (0.622 * 2.45e6)
            ce[jj] = rho_cp / gamma * h[j] / (rho_cp + h[j] * rs[j])
            tca = ta[j] - 273.15
            ea[jj] = rh[j] / 100.0 * (610.8 * np.exp(17.27 * tca / (tca + 237.3)))
    for it in range(60):
        dmax = 0.0
        if latent:
            for jj in range(nb):
                xj = x[jj]
                x3 = xj * xj * xj
                tc = xj - 273.15
                es = 610.8 * np.exp(17.27 * tc / (tc + 237.3))
                f = (swb[jj] + eb[jj] * (lwb[jj] - 5.670374419e-8 * x3 * xj)
                     - hb[jj] * (xj - tab[jj]) - (a * xj - k0 * t1[jj])
                     - ce[jj] * (es - ea[jj]))
                df = (-4.0 * eb[jj] * 5.670374419e-8 * x3 - hb[jj] - a
                      - ce[jj] * es * (17.27 * 237.3) / ((tc + 237.3) * (tc + 237.3)))
                dx = -f / df
                x[jj] = xj + dx
                dmax = max(dmax, abs(dx))
        else:
            for jj in range(nb):
                xj = x[jj]
                x3 = xj * xj * xj
                f = (swb[jj] + eb[jj] * (lwb[jj] - 5.670374419e-8 * x3 * xj)
                     - hb[jj] * (xj - tab[jj]) - (a * xj - k0 * t1[jj]))
                df = -4.0 * eb[jj] * 5.670374419e-8 * x3 - hb[jj] - a
                dx = -f / df
                x[jj] = xj + dx
                dmax = max(dmax, abs(dx))
        if dmax < 1e-7:
            break
    # back substitution (temp[0] holds the new surface temperature, then each row the new
    # cell temperature: T_i = P_i + Q_i T_{i−1})
    for jj in range(nb):
        surface[jj] = x[jj]
    for i in range(1, m + 1):
        qi = q[c, i - 1]
        row = temp[i, j0:j0 + nb]
        above = temp[i - 1, j0:j0 + nb]
        for jj in range(nb):
            row[jj] = row[jj] + qi * above[jj]
    k_bot = cond[c, m]
    bottom = temp[m, j0:j0 + nb]
    for jj in range(nb):
        j = col[jj]
        xj = x[jj]
        x3 = xj * xj * xj
        lwn = eb[jj] * (lwb[jj] - 5.670374419e-8 * x3 * xj)
        sens = hb[jj] * (xj - tab[jj])
        lat = 0.0
        if latent:
            tc = xj - 273.15
            lat = ce[jj] * (610.8 * np.exp(17.27 * tc / (tc + 237.3)) - ea[jj])
        g = k0 * (xj - t1[jj])
        bot = k_bot * (bottom[jj] - tb[jj])
        s = swb[jj] + lwn - sens - lat
        out[0, j] = lwn
        out[1, j] = sens
        out[2, j] = lat
        out[3, j] = g
        out[4, j] = bot
        out[5, j] = xj
        acc[j] += dt * (theta * (s - bot) + (1.0 - theta) * sb_old[j])
        acc_abs[j] += dt * (abs(swb[jj]) + abs(lwn) + abs(sens) + abs(lat) + abs(bot))
        sb_old[j] = s - bot
        d = abs(s - g)
        if d > imbalance[j]:
            imbalance[j] = d


@njit(cache=True)
def _h_aerodynamic(temp_surface, temp_air, wind, log_product, height_temp, stability,
                   pressure):
    """:func:`.convection.convection_aerodynamic`'s coefficient for one column, the same
    arithmetic in the same order [W m-2 K-1]."""
    u = max(wind, 0.5)
    hn = (SPECIFIC_HEAT_AIR * pressure / (1.01 * GAS_CONSTANT_DRY_AIR * temp_air)
          * _KARMAN_SQUARED * u / log_product)
    if not stability:
        return hn
    ri = min(9.80665 * height_temp * (temp_air - temp_surface) / (temp_air * u * u), 0.19)
    if ri < 0.0:
        return hn * (1.0 - 16.0 * ri) ** 0.75
    return hn * (1.0 - 5.0 * ri) ** 2


@njit(cache=True)
def _lerp(table, a, b, j, w):
    """Column ``j`` of a forcing row between instants ``a`` and ``b`` at weight ``w`` (in
    float64; exactly row ``b`` at ``w`` = 1)."""
    end = np.float64(table[b, j])
    if w == 1.0:
        return end
    start = np.float64(table[a, j])
    return start + w * (end - start)


@njit(parallel=True, cache=True)
def _span_numba(k_from, k_to, substeps, rows, conv, temp, order, blocks, n_cells, cap_dt, cond,
                q, inv_den, theta, emis, rs, tbot, dt, out, sb_old, acc, acc_abs, imbalance,
                work, now, keep, outputs):
    """The forcing intervals ``k_from[n] → k_to[n]`` in turn, ``substeps`` steps each, with
    the aerodynamic convection (:func:`_h_aerodynamic`) at each step's start: every block
    runs the whole span on one thread (one parallel launch instead of one per step; the
    columns of a block depend on nothing else). The arithmetic of the solver's Python loop
    (``_Run.interval`` with :func:`_step_blocks`).

    ``rows``: the forcing (n_t, N) of short-wave, long-wave, air temperature, humidity,
    pressure, wind; ``conv``: (log_product, height_temp, stability, pressure (N,)) of the
    convection; ``now`` (7, N): scratch for the step's forcing and coefficient; ``outputs``
    the solver's seven output arrays (n_t, N) in ``_OUTPUTS`` order, written where
    ``keep``."""
    sw_t, lw_t, ta_t, rh_t, pres_t, wind_t = rows
    log_product, height_temp, stability, p_conv = conv
    for bk in prange(blocks.shape[0]):
        j0 = blocks[bk, 1]
        j1 = blocks[bk, 2]
        for n in range(k_from.shape[0]):
            a = k_from[n]
            b = k_to[n]
            for s in range(1, substeps + 1):
                w = s / substeps
                for jj in range(j0, j1):
                    j = order[jj]
                    now[0, j] = _lerp(sw_t, a, b, j, w)
                    now[1, j] = _lerp(lw_t, a, b, j, w)
                    now[2, j] = _lerp(ta_t, a, b, j, w)
                    now[3, j] = _lerp(rh_t, a, b, j, w)
                    now[4, j] = _lerp(pres_t, a, b, j, w)
                    now[5, j] = _lerp(wind_t, a, b, j, w)
                    now[6, j] = _h_aerodynamic(temp[0, jj], now[2, j], now[5, j],
                                               log_product[j], height_temp, stability,
                                               p_conv[j])
                _block_step(bk, temp, order, blocks, n_cells, cap_dt, cond, q, inv_den, theta,
                            emis, rs, tbot, now[0], now[1], now[2], now[3], now[4], now[6], dt,
                            out, sb_old, acc, acc_abs, imbalance, work)
            for jj in range(j0, j1):
                j = order[jj]
                for r, value in enumerate((out[5, j], now[0, j], out[0, j], out[1, j],
                                           out[2, j], out[3, j], now[6, j])):
                    if keep[r]:
                        outputs[r][b, j] = value


def _step_reference(temp, order, blocks, n_cells, cap_dt, cond, q, inv_den, theta, emis, rs,
                    tbot, sw, lw, ta, rh, pres, h, dt, out, sb_old, acc, acc_abs, imbalance,
                    work=None):
    """Plain numpy version of :func:`_step_numba`: the same blocks, the same arithmetic in the
    same order, vectorised over the columns of a block.

    For cell i (1-based, capacity C_i, faces K_{i−1} above and K_i below):
    ``C_i/Δt (T'_i − T_i) = θ [K_{i−1}(T'_{i−1} − T'_i) − K_i(T'_i − T'_{i+1})]
    + (1 − θ)[same at the old level]``, T_0 the surface node, T_{m+1} the bottom temperature.
    Eliminating from the bottom, T'_i = P_i + Q_i T'_{i−1}; the surface balance
    ``S(T_s) − K_0 (T_s − P_1 − Q_1 T_s) = 0`` is solved by Newton (all columns of a block
    iterate until the largest update is below :data:`_NEWTON_TOL`), then T' follows downward.
    Every term of that balance is concave and decreasing in T_s (−εσT⁴, −h T, −λE with e°
    convex, the linear conduction), so Newton converges from any start, monotonically from
    above after its first step.
    """
    for c, j0, j1 in blocks:
        sl = slice(j0, j1)
        col = order[sl]
        m = n_cells[c]
        tb = tbot[col]
        t_below_old = tb.copy()
        p_below = np.zeros(j1 - j0)
        for i in range(m, 0, -1):
            cd = cap_dt[c, i - 1]
            k_up = cond[c, i - 1]
            k_dn = cond[c, i]
            idn = inv_den[c, i - 1]
            c_bot = theta * k_dn if i == m else 0.0
            c_p = 0.0 if i == m else theta * k_dn
            ti = temp[i, sl].copy()
            if theta < 1.0:
                rhs = cd * ti + (1.0 - theta) * (k_up * (temp[i - 1, sl] - ti)
                                                 - k_dn * (ti - t_below_old))
                p = (rhs + c_bot * tb + c_p * p_below) * idn
                t_below_old = ti
            else:
                p = (cd * ti + c_bot * tb + c_p * p_below) * idn
            temp[i, sl] = p
            p_below = p
        k0 = cond[c, 0]
        a = k0 * (1.0 - q[c, 0])
        latent = rs[col[0]] >= 0.0
        swb, lwb, tab, hb, eb = sw[col], lw[col], ta[col], h[col], emis[col]
        ce = np.zeros(j1 - j0)
        ea = np.zeros(j1 - j0)
        if latent:
            rho_cp = 1013.0 * pres[col] / (1.01 * 287.0 * tab)
            gamma = 1013.0 * pres[col] / (0.622 * 2.45e6)
            ce = rho_cp / gamma * hb / (rho_cp + hb * rs[col])
            tca = tab - 273.15
            ea = rh[col] / 100.0 * (610.8 * np.exp(17.27 * tca / (tca + 237.3)))
        x = temp[0, sl].copy()
        t1 = temp[1, sl]
        for _ in range(_NEWTON_MAX):
            x3 = x * x * x
            f = swb + eb * (lwb - SIGMA * x3 * x) - hb * (x - tab) - (a * x - k0 * t1)
            df = -4.0 * eb * SIGMA * x3 - hb - a
            if latent:
                tc = x - 273.15
                es = 610.8 * np.exp(17.27 * tc / (tc + 237.3))
                f = f - ce * (es - ea)
                df = df - ce * es * (17.27 * 237.3) / ((tc + 237.3) * (tc + 237.3))
            dx = -f / df
            x = x + dx
            if np.max(np.abs(dx)) < _NEWTON_TOL:
                break
        temp[0, sl] = x
        for i in range(1, m + 1):
            temp[i, sl] = temp[i, sl] + q[c, i - 1] * temp[i - 1, sl]
        x3 = x * x * x
        lwn = eb * (lwb - SIGMA * x3 * x)
        sens = hb * (x - tab)
        lat = np.zeros(j1 - j0)
        if latent:
            tc = x - 273.15
            lat = ce * (610.8 * np.exp(17.27 * tc / (tc + 237.3)) - ea)
        g = k0 * (x - temp[1, sl])
        bot = cond[c, m] * (temp[m, sl] - tb)
        s = swb + lwn - sens - lat
        out[0, col] = lwn
        out[1, col] = sens
        out[2, col] = lat
        out[3, col] = g
        out[4, col] = bot
        out[5, col] = x
        acc[col] += dt * (theta * (s - bot) + (1.0 - theta) * sb_old[col])
        acc_abs[col] += dt * (np.abs(swb) + np.abs(lwn) + np.abs(sens) + np.abs(lat)
                              + np.abs(bot))
        sb_old[col] = s - bot
        imbalance[col] = np.maximum(imbalance[col], np.abs(s - g))


def _renamed(func, name: str):
    """A copy of a plain function under another name (numba caches compiled code per
    qualified name: the parallel and the serial build must not share an entry)."""
    copy = types.FunctionType(func.__code__, func.__globals__, name, func.__defaults__,
                              func.__closure__)
    copy.__qualname__ = name
    copy.__doc__ = func.__doc__
    return copy


_step_numba = njit(parallel=True, cache=True)(_renamed(_step_blocks, "_step_numba"))
_step_numba_serial = njit(cache=True)(_renamed(_step_blocks, "_step_numba_serial"))
"""The kernel of :func:`_step_blocks` compiled twice: blocks on numba's threads, and on the
calling thread alone for small problems (a parallel launch costs tens of µs per step, far
more while other processes hold the cores; same blocks, same arithmetic, same results)."""

_KERNELS = {"numba": _step_numba, "reference": _step_reference}
