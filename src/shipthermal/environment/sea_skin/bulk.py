"""Air–sea fluxes by the COARE 3.6 bulk algorithm, its cool skin inside the iteration.

References in brackets: :mod:`shipthermal.environment.sea_skin`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shipthermal.units import SIGMA, ZERO_CELSIUS

from .constants import (_CHARNOCK_A1, _CHARNOCK_A2, _CHARNOCK_UMAX, _CP_AIR, _R_DRY, _SMOOTH,
                        _ZETA_CAP, BOUNDARY_LAYER_HEIGHT, COARE_EMISSIVITY, GUSTINESS_BETA,
                        SALINITY, STANDARD_PRESSURE, VON_KARMAN, WATER_DENSITY)
from .cool_layer import cool_skin
from .stability import psi_temperature, psi_wind
from .thermodynamics import normal_gravity, specific_humidity_air, specific_humidity_sea


class BulkFluxes(NamedTuple):
    """Air–sea fluxes of :func:`bulk_fluxes` (arrays broadcast like the inputs).

    Heat fluxes are positive **upward** (from the sea to the air), as in COARE, except
    ``shortwave_net`` (into the sea).
    """

    tau: np.ndarray                 #: wind stress [N m-2]
    ustar: np.ndarray               #: friction velocity in air, with gustiness [m s-1]
    ustar_water: np.ndarray         #: friction velocity in water u* (ρ_a/ρ_w)^(1/2) [m s-1]
    sensible: np.ndarray            #: sensible heat flux, up [W m-2]
    latent: np.ndarray              #: latent heat flux, up [W m-2]
    longwave_net: np.ndarray        #: net long-wave ε(σT_skin⁴ − L_down), up [W m-2]
    shortwave_net: np.ndarray       #: net solar flux into the sea [W m-2]
    delta_cool: np.ndarray          #: ΔT_cool = T(−δ) − T_skin [K]
    skin_thickness: np.ndarray      #: cool-skin thickness δ [m]
    temp_skin: np.ndarray           #: T(−δ) − ΔT_cool [K]
    obukhov_length: np.ndarray      #: Monin–Obukhov length in air [m]
    air_density: np.ndarray         #: [kg m-3]

    @property
    def heat_flux_nonsolar(self) -> np.ndarray:
        """Net non-solar heat flux INTO the sea, ``−(H_s + H_l + LW_net)`` [W m-2]."""
        return -(self.sensible + self.latent + self.longwave_net)


def bulk_fluxes(temp_sea, wind_speed, temp_air, relative_humidity, shortwave_net,
                longwave_down, pressure=STANDARD_PRESSURE, *, height_wind=10.0,
                height_temp=2.0, height_humidity=None, latitude=45.0, salinity=SALINITY,
                boundary_layer_height=BOUNDARY_LAYER_HEIGHT, emissivity=COARE_EMISSIVITY,
                cool_skin_on=True, iterations=10) -> BulkFluxes:
    """Turbulent and radiative air–sea fluxes by the COARE 3.6 bulk algorithm, with its cool
    skin.

    Parameters
    ----------
    temp_sea : array_like
        Water temperature just below the cool skin, ``T(−δ)`` [K] (the bulk SST plus the
        warm layer; the cool skin is applied here).
    wind_speed : array_like
        Wind speed relative to the sea surface at ``height_wind`` [m s-1].
    temp_air : array_like
        Air temperature at ``height_temp`` [K].
    relative_humidity : array_like
        Relative humidity at ``height_humidity`` [%].
    shortwave_net : array_like
        Net solar flux into the sea ``(1 − albedo) R_s`` [W m-2].
    longwave_down : array_like
        Downwelling long-wave irradiance [W m-2].
    pressure : array_like
        Surface air pressure [Pa].
    height_wind, height_temp, height_humidity : float
        Measurement heights [m]; humidity defaults to ``height_temp``.
    latitude : float
        [deg] (normal gravity).
    salinity : float
        [psu].
    boundary_layer_height : float
        z_i [m] (gustiness).
    emissivity : float
        Sea emissivity of the net long-wave [-].
    cool_skin_on : bool
        False: ``temp_sea`` is the radiating surface (no cool skin, ΔT_cool = 0).
    iterations : int
        Passes of the stability / cool-skin iteration (COARE: 10; [F03]: converged in 3).

    Returns
    -------
    BulkFluxes

    Notes
    -----
    The algorithm of [F03] with the 3.5 momentum roughness of [E13] and the 3.6 salinity
    terms of [C36]:

    * Monin–Obukhov similarity, ``u* = κ S / (ln(z_u/z_0) − ψ_u(z_u/L))`` and
      ``θ*, q* = −κ Δθ, Δq / (ln(z/z_0t) − ψ_t(z/L))`` (:func:`psi_wind`,
      :func:`psi_temperature`), ``L`` from the virtual-temperature buoyancy flux;
    * the wind speed ``S = (U² + u_g²)^(1/2)`` with the convective gustiness
      ``u_g = β (B_f z_i)^(1/3)`` (0.2 m s-1 when stable);
    * momentum roughness ``z_0 = α_ch u*²/g + 0.11 ν_a/u*``, Charnock's
      ``α_ch = 0.0017 U10N − 0.005`` up to U10N = 19 m s-1 ([E13]); scalar roughness
      ``z_0t = z_0q = min(1.6e-4, 5.8e-5 Re*^(−0.72))`` ([F03]);
    * the air's potential temperature ``θ = T + (g/c_pa) z_t``; the sea's saturation humidity
      with 2 % salt lowering (:func:`specific_humidity_sea`);
    * fluxes ``τ = ρ_a u*² U/S``, ``H_s = −ρ_a c_pa u* θ*``, ``H_l = −ρ_a L_e u* q*``,
      ``LW_net = ε(σ T_skin⁴ − L_down)``;
    * the cool skin (:func:`cool_skin`) inside the same iteration, the air–sea differences
      taken from the skin ``T(−δ) − ΔT_cool`` and ``q_s − (dq_s/dT) ΔT_cool``;
    * COARE's first guess (neutral transfer coefficients, bulk Richardson number) and its
      treatment of extremely stable cases (first-guess ζ > 50: the first iteration's
      solution is kept).

    Differences from [C36] (ΔT_cool within 1e-3 K, the fluxes within 1e-3 relative; see the
    tests): temperatures converted with 273.15 K (COARE adds 273.16), λ with the exponent
    −1/3 (COARE −0.333), the skin thickness bounded in convection too.

    Limits. In calm (≲ 1.5 m s-1), stable (air warmer than the sea) and sunny weather the
    iteration does not settle — in COARE's code as here: a limit cycle over which ΔT_cool
    moves by ~0.05 K and the stress by tens of per cent with the iteration count. There
    too the cool skin turns into a warm skin of up to ~1–2 K (the solar flux absorbed in the
    thickest skin, δ → 10 mm, exceeds the heat loss): COARE's formula, kept as it is.
    """
    (ts, u, ta_k, rh, rns, rl, p), shape = _flat_inputs(
        temp_sea, wind_speed, temp_air, relative_humidity, shortwave_net, longwave_down, pressure)
    zt = float(height_temp)
    s = _air_sea(ts, u, ta_k, rh, rns, rl, p, salinity=salinity, emissivity=emissivity,
                 cool_skin_on=cool_skin_on, zu=float(height_wind), zt=zt,
                 zq=zt if height_humidity is None else float(height_humidity),
                 zi=float(boundary_layer_height), grav=float(normal_gravity(latitude)))
    dter = 0.3 * np.ones_like(ts)
    rnl = _net_longwave(s, dter)
    ut, usr, tsr, qsr, tkt, charn, k50 = _first_guess(s, dter)
    scales, first, rnl, gf = _stability_iteration(s, iterations, ut, usr, tsr, qsr, dter, tkt,
                                                  rnl, charn)
    if k50.any():
        for arr, val in zip(scales, first):
            arr[k50] = val[k50]
        rnl = _net_longwave(s, scales.dter)
    return _flux_terms(s, scales, rnl, gf, shape)


def _flat_inputs(*values):
    """The inputs broadcast against each other, as flat float arrays, and their shape."""
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in values))
    shape = arrays[0].shape
    return [np.array(a, dtype=float).ravel() for a in arrays], shape


class _AirSea(NamedTuple):
    """What stays fixed through one call of :func:`bulk_fluxes`: the flat inputs, the air's
    and the sea's properties, the air–sea differences at the bulk temperature, the heights
    [m] and the switches."""

    ts: np.ndarray          #: water temperature below the skin [K]
    du: np.ndarray          #: wind speed [m s-1]
    ta: np.ndarray          #: air temperature [K]
    rns: np.ndarray         #: net solar flux into the sea [W m-2]
    rl: np.ndarray          #: downwelling long-wave [W m-2]
    q: np.ndarray           #: the air's specific humidity [kg kg-1]
    lv: np.ndarray          #: latent heat of vaporisation [J kg-1]
    rhoa: np.ndarray        #: air density [kg m-3]
    visa: np.ndarray        #: the air's kinematic viscosity [m2 s-1]
    wetc: np.ndarray        #: dq_s/dT of the sea's saturation humidity [kg kg-1 K-1]
    rho_ratio: np.ndarray   #: (ρ_a/ρ_w)^(1/2) [-]
    dt: np.ndarray          #: sea minus the air's potential temperature [K]
    dq: np.ndarray          #: sea's saturation minus the air's specific humidity [kg kg-1]
    zu: float
    zt: float
    zq: float
    zi: float
    grav: float             #: [m s-2]
    jcool: float            #: 1 with the cool skin, else 0
    emissivity: float
    cool_skin_on: bool


def _air_sea(ts, u, ta_k, rh, rns, rl, p, *, salinity, emissivity, cool_skin_on, zu, zt, zq,
             zi, grav) -> _AirSea:
    """The properties of air and water and the air–sea differences ([C36])."""
    t_c = ta_k - ZERO_CELSIUS
    ts_c = ts - ZERO_CELSIUS
    qs = specific_humidity_sea(ts, p, salinity)
    q = specific_humidity_air(ta_k, rh, p)
    lv = (2.501 - 0.00237 * ts_c) * 1e6
    rhoa = p / (_R_DRY * ta_k * (1.0 + 0.61 * q))
    visa = 1.326e-5 * (1.0 + 6.542e-3 * t_c + 8.301e-6 * t_c ** 2 - 4.84e-9 * t_c ** 3)
    # Clausius–Clapeyron slope of q_s: ΔT_cool lowers the skin's humidity by wetc ΔT_cool
    wetc = 0.622 * lv * qs / (_R_DRY * ts ** 2)
    rho_ratio = np.sqrt(rhoa / WATER_DENSITY)
    dt = ts - ta_k - grav / _CP_AIR * zt
    dq = qs - q
    return _AirSea(ts=ts, du=u, ta=ta_k, rns=rns, rl=rl, q=q, lv=lv, rhoa=rhoa, visa=visa,
                   wetc=wetc, rho_ratio=rho_ratio, dt=dt, dq=dq, zu=zu, zt=zt, zq=zq, zi=zi,
                   grav=grav, jcool=1.0 if cool_skin_on else 0.0, emissivity=emissivity,
                   cool_skin_on=cool_skin_on)


def _net_longwave(s: _AirSea, dter):
    """Net long-wave ``ε(σ T_skin⁴ − L_down)`` of the skin ``T(−δ) − ΔT_cool``, up [W m-2]."""
    return s.emissivity * (SIGMA * (s.ts - dter * s.jcool) ** 4 - s.rl)


def _charnock(u10):
    """Charnock's parameter at the 10 m neutral wind ([E13], [C36])."""
    return np.where(u10 > _CHARNOCK_UMAX, _CHARNOCK_A1 * _CHARNOCK_UMAX + _CHARNOCK_A2,
                    _CHARNOCK_A1 * u10 + _CHARNOCK_A2)


def _heat_fluxes(s: _AirSea, usr, tsr, qsr):
    """Sensible and latent heat fluxes ``−ρ_a c_pa u* θ*``, ``−ρ_a L_e u* q*``, up [W m-2]."""
    hsb = -s.rhoa * _CP_AIR * usr * tsr
    hlb = -s.rhoa * s.lv * usr * qsr
    return hsb, hlb


class _Scales(NamedTuple):
    """The surface layer's scales and the cool skin, as the iteration updates them."""

    usr: np.ndarray         #: u* [m s-1]
    tsr: np.ndarray         #: θ* [K]
    qsr: np.ndarray         #: q* [kg kg-1]
    obl: np.ndarray         #: Obukhov length [m]
    dter: np.ndarray        #: ΔT_cool [K]
    tkt: np.ndarray         #: cool-skin thickness [m]


def _first_guess(s: _AirSea, dter):
    """COARE's first guess: neutral transfer coefficients and the bulk Richardson number.

    Returns the gusty wind speed, u*, θ*, q*, the skin thickness, Charnock's parameter and
    where the first-guess ζ exceeds 50 (extremely stable: the first iteration is kept)."""
    kap, grav, zu, zt, zq, zi, ta = VON_KARMAN, s.grav, s.zu, s.zt, s.zq, s.zi, s.ta
    du, dt, dq, jcool = s.du, s.dt, s.dq, s.jcool
    ug = 0.5
    ut = np.sqrt(du ** 2 + ug ** 2)
    u10 = ut * np.log(10.0 / 1e-4) / np.log(zu / 1e-4)
    usr = 0.035 * u10
    zo10 = 0.011 * usr ** 2 / grav + _SMOOTH * s.visa / usr
    cd10 = (kap / np.log(10.0 / zo10)) ** 2
    ch10 = 0.00115
    ct10 = ch10 / np.sqrt(cd10)
    zot10 = 10.0 / np.exp(kap / ct10)
    cd = (kap / np.log(zu / zo10)) ** 2
    ct = kap / np.log(zt / zot10)
    cc = kap * ct / cd
    ribcu = -zu / zi / 0.004 / GUSTINESS_BETA ** 3
    ribu = -grav * zu / ta * ((dt - dter * jcool) + 0.61 * ta * dq) / ut ** 2
    zetu = cc * ribu * (1.0 + 27.0 / 9.0 * ribu / cc)
    k50 = zetu > _ZETA_CAP
    unst = ribu < 0.0
    zetu = np.where(unst, cc * ribu / (1.0 + ribu / ribcu), zetu)
    obl = zu / zetu
    usr = ut * kap / (np.log(zu / zo10) - psi_wind(zu / obl, 1.0, 18.0, 10.0))
    tsr = -(dt - dter * jcool) * kap / (np.log(zt / zot10) - psi_temperature(zt / obl))
    qsr = -(dq - s.wetc * dter * jcool) * kap / (np.log(zq / zot10) - psi_temperature(zq / obl))
    tkt = 0.001 * np.ones_like(s.ts)
    charn = _charnock(u10)
    return ut, usr, tsr, qsr, tkt, charn, k50


def _stability_iteration(s: _AirSea, iterations, ut, usr, tsr, qsr, dter, tkt, rnl, charn):
    """The stability / roughness / gustiness / cool-skin iteration (``iterations`` passes, at
    least one).

    Returns the scales after the last pass, those after the first, the net long-wave and the
    gustiness factor ``S/U`` of the last pass."""
    kap, grav, zu, zt, zq, zi, ta = VON_KARMAN, s.grav, s.zu, s.zt, s.zq, s.zi, s.ta
    du, dt, dq, jcool = s.du, s.dt, s.dq, s.jcool
    first = None
    for it in range(max(int(iterations), 1)):
        zet = kap * grav * zu / ta * (tsr + 0.61 * ta * qsr) / usr ** 2
        obl = zu / zet
        zo = charn * usr ** 2 / grav + _SMOOTH * s.visa / usr
        rr = zo * usr / s.visa
        zot = np.minimum(1.6e-4, 5.8e-5 / rr ** 0.72)
        usr = ut * kap / (np.log(zu / zo) - psi_wind(zu / obl))
        qsr = -(dq - s.wetc * dter * jcool) * kap / (np.log(zq / zot) - psi_temperature(zq / obl))
        tsr = -(dt - dter * jcool) * kap / (np.log(zt / zot) - psi_temperature(zt / obl))
        tvsr = tsr * (1.0 + 0.61 * s.q) + 0.61 * ta * qsr
        bf = -grav / ta * usr * tvsr
        ug = np.where(bf > 0.0, GUSTINESS_BETA * np.cbrt(np.maximum(bf, 0.0) * zi), 0.2)
        ut = np.sqrt(du ** 2 + ug ** 2)
        gf = np.divide(ut, du, out=np.full_like(ut, np.inf), where=du != 0.0)
        hsb, hlb = _heat_fluxes(s, usr, tsr, qsr)
        if s.cool_skin_on:
            dter, tkt = cool_skin(rnl + hsb + hlb, hlb, s.rns, usr * s.rho_ratio, s.ts, tkt,
                                  s.lv, grav)
        else:
            dter = np.zeros_like(s.ts)
        rnl = _net_longwave(s, dter)
        if it == 0:
            first = _Scales(usr.copy(), tsr.copy(), qsr.copy(), obl.copy(), dter.copy(),
                            tkt.copy())
        u10n = usr / kap / gf * np.log(10.0 / zo)
        charn = _charnock(u10n)
    return _Scales(usr, tsr, qsr, obl, dter, tkt), first, rnl, gf


def _flux_terms(s: _AirSea, scales: _Scales, rnl, gf, shape) -> BulkFluxes:
    """The fluxes of the settled scales, in the inputs' shape."""
    usr, tsr, qsr, obl, dter, tkt = scales
    hsb, hlb = _heat_fluxes(s, usr, tsr, qsr)
    tau = s.rhoa * usr ** 2 / gf
    return BulkFluxes(*(a.reshape(shape) for a in (
        tau, usr, usr * s.rho_ratio, hsb, hlb, rnl, s.rns, dter * s.jcool, tkt,
        s.ts - dter * s.jcool, obl, s.rhoa)))
