"""The diurnal warm layer of Zeng & Beljaars (2005): a prognostic equation of ΔT_warm,
its stability, one exact step, its equilibrium and its integration over a series.

References in brackets: :mod:`shipthermal.environment.sea_skin`.
"""

from __future__ import annotations

import math

import numpy as np

from .constants import (SOLOVIEV_ATTENUATION, SOLOVIEV_FRACTIONS, VON_KARMAN, WARM_LAYER_DEPTH,
                        WARM_LAYER_NU, WATER_DENSITY, WATER_HEAT_CAPACITY)
from .thermodynamics import thermal_expansion_seawater


def warm_layer_solar_fraction(depth=WARM_LAYER_DEPTH):
    """Fraction of the net solar flux absorbed between the surface and ``depth`` [-].

    ``1 − R(−d)/R_s = 1 − Σ a_i exp(−b_i d)`` with the three bands of [S82]
    (:data:`SOLOVIEV_FRACTIONS`, :data:`SOLOVIEV_ATTENUATION`), as [ZB05]: 0.635 at 3 m;
    the rest (the blue-green band) passes below the warm layer.
    """
    d = np.asarray(depth, dtype=float)
    return 1.0 - sum(a * np.exp(-b * d) for a, b in zip(SOLOVIEV_FRACTIONS,
                                                        SOLOVIEV_ATTENUATION))


def warm_layer_stability(delta_warm, heat_flux, ustar_water, temp_sea,
                         depth=WARM_LAYER_DEPTH, nu=WARM_LAYER_NU, gravity=9.80665):
    """Stability function φ_t(d/L) of the warm layer [-] ([ZB05] eqs. 9, 10, 12).

    Parameters
    ----------
    delta_warm : array_like
        ΔT_warm [K].
    heat_flux : array_like
        Heat flux into the layer ``Q = Q_0 + R_s − R(−d)`` [W m-2] (non-solar flux into the
        sea plus the solar absorbed above d).
    ustar_water : array_like
        u*_w [m s-1].
    temp_sea : array_like
        [K] (expansion coefficient).
    depth, nu : float
        d [m], ν [-].
    gravity : float
        [m s-2].

    Returns
    -------
    numpy.ndarray
        ``φ_t(ζ) = 1 + 5ζ`` (ζ ≥ 0) or ``(1 − 16ζ)^(−1/2)`` (ζ < 0) ([ZB05] eq. 9, from
        [L94]) with ``ζ = d/L``, ``L = ρ_w c_w u*_w³ / (κ F_d)`` (eq. 10) and the buoyancy
        flux (eq. 12) ``F_d = g α_w Q`` or, for an existing warm layer, its own
        stratification ``F_d = (ν g α_w / (5 d))^(1/2) ρ_w c_w u*_w² ΔT^(1/2)``.

    Notes
    -----
    Which F_d applies when: ECMWF's implementation of the scheme by its co-author (IFS
    routine VOSKIN, formulation C, A. Beljaars; IFS cycle 36r1) takes the ΔT form when
    ΔT > 0 and Q < 0, else ``g α_w Q``. That switch jumps at Q = 0: a layer of several
    kelvin that the evening sun heats by 1 W m-2 is mixed as if neutral (φ_t = 1), 1 W m-2
    later as strongly stable, and the result depends on the time step by 0.1–0.4 K on calm
    days (measured here at 1–2 m s-1). ASSUMPTION (our continuous form of eq. 12): for
    ΔT > 0 the larger of the two buoyancy fluxes, ``max(g α_w Q, ΔT form)``. The ΔT form
    is the heating that sustains the layer in a steady state — at the equilibrium of eq.
    11, ``(φ − 1)² = (φ_Q − 1) φ`` exactly, φ_Q the stability of ``g α_w Q`` — so the two
    agree to the 1 of φ = 1 + 5ζ while the sun holds the layer near equilibrium, and the
    maximum differs from VOSKIN's switch mainly in the evening, when Q falls through
    zero: it equals VOSKIN whenever Q < 0, removes the jump (time-step error < 2e-3 K at
    10 min) and keeps a stratified layer stratified while the sun's flux is weak. On the
    sunny test days it moves the daily peak of ΔT_warm by < 0.06 K: < 1.5 % at 0.5–5 m s-1,
    +0.02–0.04 K on the 0.1–0.25 K layers of 8–10 m s-1.
    """
    dtw = np.asarray(delta_warm, dtype=float)
    q = np.asarray(heat_flux, dtype=float)
    usw = np.asarray(ustar_water, dtype=float)
    alpha = thermal_expansion_seawater(temp_sea)
    rc = WATER_DENSITY * WATER_HEAT_CAPACITY
    fd_q = gravity * alpha * q / rc
    fd_dt = np.sqrt(nu * gravity * alpha / (5.0 * depth)) * usw ** 2 \
        * np.sqrt(np.maximum(dtw, 0.0))
    fd_over_rc = np.where(dtw > 0.0, np.maximum(fd_q, fd_dt), fd_q)
    zeta = depth * VON_KARMAN * fd_over_rc / usw ** 3
    return np.where(zeta >= 0.0, 1.0 + 5.0 * np.maximum(zeta, 0.0),
                    1.0 / np.sqrt(1.0 - 16.0 * np.minimum(zeta, 0.0)))


def warm_layer_rates(delta_warm, heat_flux, ustar_water, temp_sea, depth=WARM_LAYER_DEPTH,
                     nu=WARM_LAYER_NU):
    """The two rates of the warm-layer equation ``dΔT/dt = A − B ΔT`` ([ZB05] eq. 11).

    Returns
    -------
    A : numpy.ndarray
        Heating rate ``Q / (d ρ_w c_w ν / (ν + 1))`` [K s-1].
    B : numpy.ndarray
        Mixing rate ``(ν + 1) κ u*_w / (d φ_t(d/L))`` [s-1] (:func:`warm_layer_stability`).
    """
    q = np.asarray(heat_flux, dtype=float)
    a = q * (nu + 1.0) / (depth * WATER_DENSITY * WATER_HEAT_CAPACITY * nu)
    phi = warm_layer_stability(delta_warm, q, ustar_water, temp_sea, depth, nu)
    b = (nu + 1.0) * VON_KARMAN * np.asarray(ustar_water, dtype=float) / (depth * phi)
    return a, b


def _step(cur, q0, slope, usw, alpha, dt, depth, nu, sweeps, gravity=9.80665):
    """Scalar kernel of :func:`warm_layer_step` (plain floats; see there).

    ``Q(ΔT) = q0 + slope ΔT`` over the step (slope ≤ 0)."""
    rc = WATER_DENSITY * WATER_HEAT_CAPACITY
    c = (nu + 1.0) / (depth * rc * nu)            # dΔT/dt per W m-2 [K s-1 / (W m-2)]
    k = (nu + 1.0) * VON_KARMAN * usw / depth
    zeta_per_fd = depth * VON_KARMAN / usw ** 3
    sq = math.sqrt(nu * gravity * alpha / (5.0 * depth))
    new = cur
    for _ in range(sweeps):
        mid = 0.5 * (cur + new)
        q_mid = q0 + slope * mid
        fd = gravity * alpha * q_mid / rc
        if mid > 0.0:
            fd = max(fd, sq * usw * usw * math.sqrt(mid))
        zeta = zeta_per_fd * fd
        phi = 1.0 + 5.0 * zeta if zeta >= 0.0 else 1.0 / math.sqrt(1.0 - 16.0 * zeta)
        x = (k / phi - c * slope) * dt
        growth = dt * (-math.expm1(-x) / x if x > 1e-12 else 1.0 - 0.5 * x)
        new = max(cur * math.exp(-x) + c * q0 * growth, 0.0)
    return new


def warm_layer_step(delta_warm, heat_flux, ustar_water, temp_sea, dt,
                    depth=WARM_LAYER_DEPTH, nu=WARM_LAYER_NU, heat_flux_slope=0.0, sweeps=4):
    """One time step of the warm layer, exact for frozen rates [K].

    Parameters
    ----------
    delta_warm : float
        ΔT_warm at the start of the step [K].
    heat_flux : float
        Heat flux into the layer over the step, Q [W m-2], at ΔT = ``delta_warm``.
    ustar_water, temp_sea : float
        Forcing over the step (its mean) [m s-1], [K].
    dt : float
        Step [s] (> 0).
    depth, nu : float
        d [m], ν [-].
    heat_flux_slope : float
        ``∂Q/∂ΔT`` [W m-2 K-1] (≤ 0: a warmer surface loses more heat); 0 freezes Q.
    sweeps : int
        Fixed-point passes for the stability at the step's midpoint.

    Returns
    -------
    float
        ``ΔT(t + dt) = max(ΔT e^{−B dt} + A dt (1 − e^{−B dt})/(B dt), 0)``: the exact
        solution of ``dΔT/dt = A − B ΔT`` ([ZB05] eq. 11, :func:`warm_layer_rates`) for
        constant rates (stable for any dt), with the surface-flux feedback moved into them
        (``Q = Q_0 + s ΔT``: A from Q_0, B raised by ``−s (ν+1)/(d ρ_w c_w ν)``) and the
        stability at the midpoint ``(ΔT(t) + ΔT(t + dt))/2`` (``sweeps`` fixed-point
        passes: φ_t depends on ΔT, eq. 12).

    Notes
    -----
    ΔT_warm is kept ≥ 0 (ASSUMPTION, as ECMWF's implementation of the scheme, VOSKIN): the
    profile of [ZB05] (``1 − (z/d)^ν`` of ΔT) describes a warm, stratified layer; a layer cooled from the
    surface overturns (convection much faster than an hourly step) and is mixed, ΔT = 0.
    At night Q < 0 makes A < 0, so a warm layer decays to zero in finite time and stays
    there until the sun heats it again: the nightly reset the model implies.
    """
    s = min(float(heat_flux_slope), 0.0)
    q0 = float(heat_flux) - s * float(delta_warm)
    return _step(float(delta_warm), q0, s, float(ustar_water),
                 float(thermal_expansion_seawater(temp_sea)), float(dt), float(depth),
                 float(nu), max(int(sweeps), 1))


def warm_layer_equilibrium(heat_flux, ustar_water, temp_sea, depth=WARM_LAYER_DEPTH,
                           nu=WARM_LAYER_NU, gravity=9.80665):
    """Steady ΔT_warm under constant forcing [K] (closed form of [ZB05] eqs. 9–12).

    ``dΔT/dt = A − B ΔT = 0`` gives ``ΔT = A/B = c φ_t / (κ u*_w)`` with
    ``c = Q / (ρ_w c_w ν)``. With the stability of :func:`warm_layer_stability`,
    ``φ_t = max(φ_Q, 1 + a ΔT^(1/2))``: ``φ_Q = 1 + 5 d κ g α_w Q / (ρ_w c_w u*_w³)`` from
    the heating and ``a = 5 d κ (ν g α_w / (5 d))^(1/2) / u*_w`` from the layer's own
    stratification. The fixed point is the larger of ``c φ_Q / (κ u*_w)`` and the positive
    root ``s²`` of ``κ u*_w s² − c a s − c = 0``. Zero when ``Q ≤ 0``. The integrator
    (:func:`warm_layer_step`) must converge to it.
    """
    q = np.maximum(np.asarray(heat_flux, dtype=float), 0.0)
    usw = np.asarray(ustar_water, dtype=float)
    alpha = thermal_expansion_seawater(temp_sea)
    c = q / (WATER_DENSITY * WATER_HEAT_CAPACITY * nu)
    phi_q = warm_layer_stability(0.0, q, usw, temp_sea, depth, nu, gravity)
    from_heating = c * phi_q / (VON_KARMAN * usw)
    a = 5.0 * depth * VON_KARMAN * np.sqrt(nu * gravity * alpha / (5.0 * depth)) / usw
    s = (c * a + np.sqrt((c * a) ** 2 + 4.0 * VON_KARMAN * usw * c)) / (2.0 * VON_KARMAN * usw)
    return np.maximum(from_heating, s * s)


def warm_layer_series(seconds, heat_flux, ustar_water, temp_sea, initial=0.0,
                      depth=WARM_LAYER_DEPTH, nu=WARM_LAYER_NU, period=None,
                      heat_flux_slope=0.0, reference=0.0):
    """Integrate ΔT_warm over a time series (forcing linear between the samples).

    Parameters
    ----------
    seconds : array_like
        Increasing sample times [s].
    heat_flux : array_like
        Heat flux into the layer Q at the samples [W m-2], evaluated at ΔT = ``reference``.
    ustar_water, temp_sea : array_like
        u*_w [m s-1] and the bulk temperature [K] at the samples.
    initial : float
        ΔT_warm at ``seconds[0]`` [K].
    depth, nu : float
        d [m], ν [-].
    period : float, optional
        Periodic forcing: the samples cover one period ``[t0, t0 + period)``; a last step
        from ``seconds[-1]`` to ``t0 + period`` uses the first sample again.
    heat_flux_slope : array_like
        ``∂Q/∂ΔT`` at the samples [W m-2 K-1] (≤ 0); Q follows ΔT linearly around
        ``reference``: ``Q(ΔT) = heat_flux + slope (ΔT − reference)``.
    reference : array_like
        The ΔT_warm [K] at which ``heat_flux`` was evaluated.

    Returns
    -------
    numpy.ndarray
        ΔT_warm at the samples (and, with ``period``, one more value: at ``t0 + period``).

    Notes
    -----
    Each step by :func:`warm_layer_step` with the forcing averaged over the step (mean of
    its ends).
    """
    t = np.asarray(seconds, dtype=float)
    slope = np.minimum(np.broadcast_to(np.asarray(heat_flux_slope, dtype=float), t.shape),
                       0.0)
    q0 = np.asarray(heat_flux, dtype=float) - slope * np.asarray(reference, dtype=float)
    q0, us, ts = (np.broadcast_to(np.asarray(x, dtype=float), t.shape)
                  for x in (q0, ustar_water, temp_sea))
    if period is not None:
        t = np.append(t, t[0] + float(period))
        q0, slope, us, ts = (np.append(x, x[0]) for x in (q0, slope, us, ts))
    # forcing averaged over each step (mean of its ends)
    q_mid, s_mid, us_mid, ts_mid = (0.5 * (x[1:] + x[:-1]) for x in (q0, slope, us, ts))
    alpha = thermal_expansion_seawater(ts_mid)
    out = np.empty(t.size)
    out[0] = cur = float(initial)
    d, n_ = float(depth), float(nu)
    for i, (qi, si, ui, ai, dti) in enumerate(zip(q_mid.tolist(), s_mid.tolist(),
                                                 us_mid.tolist(), alpha.tolist(),
                                                 np.diff(t).tolist())):
        cur = _step(cur, qi, si, ui, ai, dti, d, n_, 4)
        out[i + 1] = cur
    return out
