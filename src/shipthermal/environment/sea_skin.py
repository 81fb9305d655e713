"""The sea's skin temperature: bulk air–sea fluxes, the cool skin and the diurnal warm layer.

An infrared radiometer sees the top ~10 µm of the sea, its *skin*. The bulk sea surface
temperature of a buoy, a ship's intake or a climatology is measured metres deeper. Two thin
layers separate them::

    T_skin = T_bulk + ΔT_warm − ΔT_cool

* the **cool skin** ``ΔT_cool``: the molecular sub-layer, about a millimetre thick, through
  which the sea's heat loss to the air is conducted; 0.1–0.5 K cooler than the water below it
  whenever the sea loses heat, day and night [F96b]. Here: Fairall et al. (1996b), Saunders'
  constant with the convective correction and the solar absorption in the layer, as in the
  COARE algorithm.
* the **diurnal warm layer** ``ΔT_warm``: solar heating trapped in the upper metres on calm,
  sunny days, up to several kelvin, mixed away by wind and night-time convection [K07]. Two
  models (``warm_layer=``):

  - ``'fairall_coare'`` (default): the COARE warm layer of [F96b] as the COARE 3.x reference
    code runs it [C30, C36] (:func:`coare_warm_layer`). From the morning onset, the heat
    absorbed in the layer and the wind stress are accumulated; the layer's depth D is where
    the accumulated warming and current reach the critical bulk Richardson number 0.65, its
    warming ΔT follows from the heat spread linearly over D; reset at local midnight.
  - ``'zeng_beljaars'``: the prognostic scheme of Zeng & Beljaars (2005) [ZB05], warm-layer
    depth d = 3 m, profile exponent ν = 0.3, integrated in time (:func:`warm_layer_series`).

Both need the surface fluxes (wind stress, sensible and latent heat, net long-wave), computed
with the COARE 3.6 bulk algorithm [F03, E13], the scheme the cool skin of [F96b] was built in
and tuned with.

Why the COARE warm layer is the default. On clear tropical days (1000 W m-2 at noon; the
tests' cross-check) the two peak at 1 m s-1: Z&B 4.08 K, COARE 2.68 K; 3 m s-1: 2.36 vs 0.59
K; 5 m s-1: 1.03 vs 0.11 K; on the built-in Dalian summer day (4 m s-1) 2.98 vs 1.07 K.
Observed diurnal warming of the skin with strong sun at 3–5 m s-1 stays well under 1.5 K,
and more than 2 K needs winds below ~2 m s-1 ([K07]; Gentemann et al. 2009, J. Geophys.
Res. 114, C07017): Z&B as published warms too much at moderate winds — the documented
reason for the refinements of Takaya et al. (2010, J. Geophys. Res. 115, C06009: Langmuir
mixing, a stable stability function that saturates), which are not included here. The
COARE layer (its Ri_c "tuned for COARE" [C36]) reproduces its reference code on NOAA's
COARE 3.0b test case (TOGA COARE, R/V Moana Wave, 25–29 Nov 1992: ΔT to 0.005 K) and, run
here with our fluxes, the warming observed on that case between 6 m and 0.05 m (daily
peaks 0.24, 0.01, 1.73, 1.09 K, model within 0.25 K; daytime rms 0.20 K, Z&B 0.41 K).

What Z&B is for: the skin of the ECMWF model's analyses (IFS routine VOSKIN, "formulation
C", the scheme of [ZB05]), the met source a port background often comes from; it is a
differential equation valid at any instant and in any sequence of days, which decays by
itself at night without COARE's clock-based reset; and an upper bound of the warming
(a sensitivity case for low-wind sunny afternoons).

Interpretation of the bulk SST: the temperature at 3 m depth (ASSUMPTION; ``depth=``),
the base of the [ZB05] layer, ``T(−d)``; for COARE the depth of the "sensor" below which its
linear warm-layer profile is not seen: ``ΔT_warm = ΔT min(1, 3 m / D)`` of the layer's full
warming ΔT. A buoy thermistor at 1 m already carries part of the warm layer (by the [ZB05]
profile ``1 − (z/d)^ν``, 28 % of ``ΔT_warm`` at 1 m).

Constants carry one of the labels of the code base: SOURCED (copied from the cited source),
DERIVED (computed from sourced numbers by a stated method), ASSUMPTION (our choice).

Temperatures in K, heat fluxes in W m-2 (the sign is stated per quantity), pressure in Pa,
speeds in m s-1.

Sources
-------
[F96a] Fairall, C. W., Bradley, E. F., Rogers, D. P., Edson, J. B. & Young, G. S. (1996),
       "Bulk parameterization of air–sea fluxes for Tropical Ocean–Global Atmosphere Coupled
       Ocean–Atmosphere Response Experiment", J. Geophys. Res. 101(C2), 3747–3764.
[F96b] Fairall, C. W., Bradley, E. F., Godfrey, J. S., Wick, G. A., Edson, J. B. & Young,
       G. S. (1996), "Cool-skin and warm-layer effects on sea surface temperature", J.
       Geophys. Res. 101(C1), 1295–1308.
[F03]  Fairall, C. W., Bradley, E. F., Hare, J. E., Grachev, A. A. & Edson, J. B. (2003),
       "Bulk parameterization of air–sea fluxes: updates and verification for the COARE
       algorithm", J. Climate 16, 571–591.
[E13]  Edson, J. B. et al. (2013), "On the exchange of momentum over the open ocean", J.
       Phys. Oceanogr. 43, 1589–1610 (COARE 3.5: wind-speed-dependent Charnock parameter).
[C36]  NOAA PSL COARE 3.6 algorithm (Fairall, Edson, Bariteau, Blomquist, Thompson), the
       reference code of [F03, E13]: the constants of water and air below and the salinity
       terms of 3.6; its warm layer, routine ``coare36vnWarm_et`` (MATLAB and Python,
       github.com/NOAA-PSL/COARE-algorithm).
[C30]  NOAA PSL COARE 3.0b Fortran (Bradley & Fairall, 2005), ``cor3_0bf.for``, with its
       test case (``test3_0.txt`` in, ``tst3_0bf.out`` out: R/V Moana Wave, TOGA COARE,
       25–29 Nov 1992; same repository), the warm layer of [F96b] as first coded.
[G00]  Grachev, A. A., Fairall, C. W. & Bradley, E. F. (2000), "Convective profile
       constants revisited", Boundary-Layer Meteorol. 94, 495–515.
[BH91] Beljaars, A. C. M. & Holtslag, A. A. M. (1991), "Flux parameterization over land
       surfaces for atmospheric models", J. Appl. Meteorol. 30, 327–341.
[B81]  Buck, A. L. (1981), "New equations for computing vapor pressure and enhancement
       factor", J. Appl. Meteorol. 20, 1527–1532.
[S67]  Saunders, P. M. (1967), "The temperature at the ocean–air interface", J. Atmos. Sci.
       24, 269–273.
[ZB05] Zeng, X. & Beljaars, A. (2005), "A prognostic scheme of sea surface skin temperature
       for modeling and data assimilation", Geophys. Res. Lett. 32, L14605.
[S82]  Soloviev, A. V. (1982), "On the vertical structure of the ocean thin surface layer at
       light wind", Dokl. Acad. Sci. USSR, Earth Sci. Sect. 18, 751–760 (the three-band
       solar absorption profile [ZB05] use).
[L94]  Large, W. G., McWilliams, J. C. & Doney, S. C. (1994), "Oceanic vertical mixing: a
       review and a model with a nonlocal boundary layer parameterization", Rev. Geophys.
       32, 363–403 (the stability function [ZB05] take).
[K07]  Kawai, Y. & Wada, A. (2007), "Diurnal sea surface temperature variation and its
       impact on the atmosphere and ocean: a review", J. Oceanogr. 63, 721–744.
[WGS]  NIMA TR8350.2 (2000), "Department of Defense World Geodetic System 1984", 3rd ed.,
       eq. 4-1 (Somigliana's normal gravity) and Table 3.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from shipthermal.errors import InputError, check_range, require
from shipthermal.units import SIGMA, ZERO_CELSIUS

__all__ = [
    "VON_KARMAN", "GUSTINESS_BETA", "BOUNDARY_LAYER_HEIGHT", "COARE_EMISSIVITY",
    "COARE_ALBEDO", "WATER_DENSITY", "WATER_HEAT_CAPACITY", "WATER_VISCOSITY",
    "WATER_CONDUCTIVITY", "SAUNDERS_LAMBDA", "SALINITY", "SKIN_THICKNESS_MAX",
    "WARM_LAYER_DEPTH", "WARM_LAYER_NU", "SOLOVIEV_FRACTIONS", "SOLOVIEV_ATTENUATION",
    "STANDARD_PRESSURE", "COARE_CRITICAL_RICHARDSON", "COARE_MAX_DEPTH", "COARE_ONSET_FLUX",
    "COARE_MIN_STRESS", "COARE_SOLAR_DEPTHS", "COARE_START_FRACTION", "COARE_WIPED_FRACTION",
    "COARE_FIRST_START_HOUR", "WARM_LAYER_MODELS", "DEFAULT_WARM_LAYER",
    "normal_gravity", "saturation_vapour_pressure_buck", "specific_humidity_sea",
    "specific_humidity_air", "thermal_expansion_seawater", "psi_wind", "psi_temperature",
    "cool_skin_solar_fraction", "cool_skin", "BulkFluxes", "bulk_fluxes",
    "warm_layer_solar_fraction", "warm_layer_stability", "warm_layer_rates",
    "warm_layer_step", "warm_layer_equilibrium", "warm_layer_series",
    "coare_solar_fraction", "CoareWarmLayer", "coare_warm_layer", "coare_warm_layer_series",
    "SeaSkin", "warm_layer_model", "sea_skin_temperature",
]

# ---------------------------------------------------------------------------------------
# Constants
# ---------------------------------------------------------------------------------------
VON_KARMAN = 0.4
"""Von Kármán constant [-] (SOURCED: [F03], [C36])."""
GUSTINESS_BETA = 1.2
"""Convective gustiness coefficient β of ``u_g = β (B_f z_i)^(1/3)`` [-] (SOURCED: [F03],
[C36]); 0.2 m s-1 of gustiness when the buoyancy flux is downward ([C36])."""
BOUNDARY_LAYER_HEIGHT = 600.0
"""Height z_i of the atmospheric boundary layer [m] (SOURCED: the default of [F96a], [C36];
an ASSUMPTION for any given site: it enters only through the gustiness, as z_i^(1/3))."""
COARE_EMISSIVITY = 0.97
"""Broadband sea emissivity of the surface energy balance [-] (SOURCED: [F96a], [C36]). The
broadband measurement 0.984 (Konda et al. 1994, ``parameters.SEA_EMISSIVITY``) would change
the net long-wave by ~0.014 (σT⁴ − L_down) ≈ 1–2 W m-2; COARE's value is kept so that the
fluxes are those the cool-skin constants were fitted with."""
COARE_ALBEDO = 0.055
"""Sea albedo for the solar net flux when none is given [-] (SOURCED: [C36] 3.5:
``R_ns = 0.945 R_s``). :class:`~shipthermal.environment.Environment` passes its own albedo
(Taylor et al. 1996 for the direct beam, Payne 1972 for diffuse light)."""
STANDARD_PRESSURE = 101325.0
"""Sea-level pressure where none is measured [Pa] (ASSUMPTION: ICAO standard atmosphere;
±20 hPa changes the sea's saturation humidity by ±2 % and ΔT_cool by < 0.01 K)."""

WATER_DENSITY = 1022.0
"""Sea water density ρ_w [kg m-3] (SOURCED: [C36], the value of the cool skin's
constants)."""
WATER_HEAT_CAPACITY = 4000.0
"""Sea water specific heat c_w [J kg-1 K-1] (SOURCED: [C36])."""
WATER_VISCOSITY = 1.0e-6
"""Kinematic viscosity of sea water ν_w [m2 s-1] (SOURCED: [C36], [F96b])."""
WATER_CONDUCTIVITY = 0.6
"""Thermal conductivity of sea water k_w [W m-1 K-1] (SOURCED: [C36], [F96b])."""
SAUNDERS_LAMBDA = 6.0
"""Saunders' constant λ of the cool-skin thickness δ = λ ν_w / u*_w [-] (SOURCED: [F96b],
after [S67]; the value COARE uses)."""
SALINITY = 35.0
"""Practical salinity S [psu] (ASSUMPTION: open-ocean value; coastal water of 30 psu would
raise the sea's saturation humidity by 0.3 %)."""
_SALINE_CONTRACTION_S = 0.026
"""β S, the saline contraction coefficient times salinity [-] of the cool skin's buoyancy
flux (SOURCED: [F96b], [C36] ``be``)."""
SKIN_THICKNESS_MAX = 0.01
"""Upper bound of the cool-skin thickness [m] (SOURCED: [C36]; reached only at u*_w < 6e-4
m s-1, i.e. calm air without gustiness)."""

WARM_LAYER_DEPTH = 3.0
"""Depth d of the warm layer's base, where the bulk SST is taken [m] (SOURCED: [ZB05]'s d;
the depth of the bulk SST an ASSUMPTION, for the COARE warm layer too: see the module)."""
WARM_LAYER_NU = 0.3
"""Exponent ν of the warm-layer temperature profile ``T(z) = T_{-δ} − ((z+δ)/(δ−d))^ν ΔT``
[-] (SOURCED: [ZB05]; also ECMWF's implementation, IFS VOSKIN ``ZAN = 0.3``)."""
SOLOVIEV_FRACTIONS = (0.28, 0.27, 0.45)
"""Fractions a_i of net solar radiation in the three bands of [S82] [-] (SOURCED: [S82] as
used by [ZB05])."""
SOLOVIEV_ATTENUATION = (71.5, 2.8, 0.07)
"""Attenuation coefficients b_i of the three bands [m-1] (SOURCED: [S82] via [ZB05]):
``R(−z) = R_s Σ a_i exp(−b_i z)``."""

COARE_CRITICAL_RICHARDSON = 0.65
"""Critical bulk Richardson number Ri_c of the COARE warm layer [-] (SOURCED: [F96b]; [C30],
[C36] ``rich = .65``, "critical Richardson number tuned for COARE")."""
COARE_MAX_DEPTH = 19.0
"""Greatest depth D of the COARE warm layer [m] (SOURCED: [C30], [C36] ``max_pwp = 19``, the
depth also assumed at each midnight reset)."""
COARE_ONSET_FLUX = 50.0
"""Heating of the layer ``f_x R_ns − Q_out`` [W m-2] from which, each morning, COARE starts
accumulating heat and stress (SOURCED: [C30], [C36] ``q_pwp >= 50``)."""
COARE_MIN_STRESS = 0.002
"""Least wind stress the COARE warm layer accumulates [N m-2] (SOURCED: [C30], [C36]
``max(.002, tau_old)``)."""
COARE_SOLAR_DEPTHS = (0.014, 0.357, 12.82)
"""e-folding depths γ_i [m] of the three solar bands (fractions :data:`SOLOVIEV_FRACTIONS`)
in the COARE warm layer's absorbed fraction (SOURCED: [F96b], [C30], [C36]; [S82]'s bands,
close to the attenuations 1/γ = 71.4, 2.80, 0.078 m-1 against [ZB05]'s 71.5, 2.8, 0.07)."""
COARE_START_FRACTION = 0.5
"""Absorbed solar fraction f_x assumed at each reset, before the layer's depth is known [-]
(SOURCED: [C30], [C36] ``fxp = .5``: a shallow heating layer to start the morning)."""
COARE_WIPED_FRACTION = 0.75
"""f_x while the accumulated heat is not positive (no layer, D = :data:`COARE_MAX_DEPTH`)
[-] (SOURCED: [C30], [C36] ``fxp = .75``, "warm layer wiped out")."""
COARE_FIRST_START_HOUR = 6.0
"""A record's first day: the warm layer integrates from its first sample at or before this
local solar hour [h], later than that it waits for the next night (SOURCED: [C36],
``newtime <= 21600``: "6 am too late to start on first day", [C30])."""

_R_DRY = 287.1          # gas constant of dry air [J kg-1 K-1] (SOURCED: [C36])
_CP_AIR = 1004.67       # specific heat of dry air [J kg-1 K-1] (SOURCED: [C36])
_CHARNOCK_A1, _CHARNOCK_A2, _CHARNOCK_UMAX = 0.0017, -0.0050, 19.0   # [E13], [C36]
_SMOOTH = 0.11          # smooth-flow roughness z0 = 0.11 ν_a / u* (SOURCED: [F03])
_ZETA_CAP = 50.0        # [C36]: exponent cap and the very-stable first-guess branch
_DT_PROBE = 0.05        # [K] finite difference of the flux response to the warm layer


# ---------------------------------------------------------------------------------------
# Thermodynamic helpers
# ---------------------------------------------------------------------------------------
def normal_gravity(latitude):
    """Normal gravity on the WGS 84 ellipsoid [m s-2] at ``latitude`` [deg] ([WGS] eq. 4-1,
    Somigliana's formula; 9.7803 at the equator, 9.8322 at the poles)."""
    phi = np.radians(np.asarray(latitude, dtype=float))
    e2 = 6.69437999014e-3          # first eccentricity squared [WGS Table 3.3]
    k = 1.931852652458e-3          # Somigliana's constant [WGS Table 3.3]
    s2 = np.sin(phi) ** 2
    return 9.7803253359 * (1.0 + k * s2) / np.sqrt(1.0 - e2 * s2)


def saturation_vapour_pressure_buck(temp, pressure):
    """Saturation vapour pressure over pure water in moist air [Pa] ([B81]).

    Parameters
    ----------
    temp : array_like
        Temperature [K].
    pressure : array_like
        Air pressure [Pa].

    Notes
    -----
    [B81]: ``e_w = 6.1121 exp(17.502 T / (240.97 + T))`` hPa (T in °C) times his
    enhancement factor for moist air ``f = 1.0007 + 3.46e-6 P`` (P in hPa), the form of
    [C36].
    """
    t = np.asarray(temp, dtype=float) - ZERO_CELSIUS
    p_hpa = np.asarray(pressure, dtype=float) / 100.0
    return 611.21 * np.exp(17.502 * t / (240.97 + t)) * (1.0007 + 3.46e-6 * p_hpa)


def specific_humidity_sea(temp_sea, pressure, salinity=SALINITY):
    """Saturation specific humidity at the sea surface [kg kg-1].

    The vapour pressure of [B81] lowered by the salt, ``e = (1 − 0.02 S/35) e_w`` (0.98 at
    35 psu; [C36] 3.6, the 2 % reduction of [F96a]), then ``q = 0.622 e / (P − 0.378 e)``.
    """
    es = (1.0 - 0.02 * np.asarray(salinity, dtype=float) / 35.0) * \
        saturation_vapour_pressure_buck(temp_sea, pressure)
    p = np.asarray(pressure, dtype=float)
    return 0.622 * es / (p - 0.378 * es)


def specific_humidity_air(temp_air, relative_humidity, pressure):
    """Specific humidity of air [kg kg-1] from temperature [K], relative humidity [%] and
    pressure [Pa] ([B81] saturation, ``q = 0.62197 e / (P − 0.378 e)``, [C36])."""
    e = np.asarray(relative_humidity, dtype=float) / 100.0 * \
        saturation_vapour_pressure_buck(temp_air, pressure)
    p = np.asarray(pressure, dtype=float)
    return 0.62197 * e / (p - 0.378 * e)


def thermal_expansion_seawater(temp_sea):
    """Thermal expansion coefficient of sea water at 35 psu [K-1].

    ``α = 2.1e-5 (T + 3.2)^0.79`` with T in °C (SOURCED: [C36], the fit COARE's cool skin
    uses; 2.7e-4 at 22 °C, 1.1e-4 at 5 °C). Clipped at −3.2 °C (below sea water's freezing
    point the fit is undefined).
    """
    t = np.maximum(np.asarray(temp_sea, dtype=float) - ZERO_CELSIUS + 3.2, 0.0)
    return 2.1e-5 * t ** 0.79


def _psi_blend(zeta, kansas, convective):
    f = zeta * zeta / (1.0 + zeta * zeta)
    return (1.0 - f) * kansas + f * convective


def _psi_convective(x):
    return (1.5 * np.log((x * x + x + 1.0) / 3.0) - math.sqrt(3.0)
            * np.arctan((2.0 * x + 1.0) / math.sqrt(3.0)) + math.pi / math.sqrt(3.0))


def psi_wind(zeta, stable_a=0.7, kansas=15.0, convective=10.15):
    """Integrated stability function of wind speed ψ_u(ζ) [-], ζ = z/L.

    Parameters
    ----------
    zeta : array_like
        Stability parameter z/L [-].
    stable_a, kansas, convective : float
        The coefficient a of the stable form and the Kansas and free-convection constants of
        the unstable form (defaults: COARE 3.5/3.6, [C36]; the COARE first guess uses
        a = 1, 18, 10).

    Notes
    -----
    Unstable (ζ < 0): the Kansas form with ``x = (1 − 15ζ)^(1/4)`` blended with the
    free-convection form with ``y = (1 − 10.15ζ)^(1/3)`` by ``ζ²/(1 + ζ²)`` ([F96a], [G00]).
    Stable: ``−(a ζ + b (ζ − c/d) exp(−d ζ) + b c/d)``, b = 3/4, c = 5, d = 0.35 ([BH91],
    whose a = 1 COARE 3.5/3.6 lowers to 0.7, [C36]); d ζ capped at 50.
    """
    z = np.asarray(zeta, dtype=float)
    zs = np.maximum(z, 0.0)
    dz = np.minimum(0.35 * zs, _ZETA_CAP)
    stable = -(stable_a * zs + 0.75 * (zs - 5.0 / 0.35) * np.exp(-dz) + 0.75 * 5.0 / 0.35)
    zu = np.minimum(z, 0.0)
    x = (1.0 - kansas * zu) ** 0.25
    psik = 2.0 * np.log((1.0 + x) / 2.0) + np.log((1.0 + x * x) / 2.0) - 2.0 * np.arctan(x) \
        + 0.5 * math.pi
    psic = _psi_convective((1.0 - convective * zu) ** (1.0 / 3.0))
    return np.where(z < 0.0, _psi_blend(zu, psik, psic), stable)


def psi_temperature(zeta):
    """Integrated stability function of temperature and humidity ψ_t(ζ) [-], ζ = z/L.

    Notes
    -----
    Unstable: Kansas ``2 ln((1 + x)/2)``, ``x = (1 − 15ζ)^(1/2)``, blended with the
    free-convection form, ``y = (1 − 34.15ζ)^(1/3)``, by ``ζ²/(1 + ζ²)`` ([F96a], [G00]).
    Stable: ``−((1 + 2/3 a ζ)^(3/2) + b (ζ − c/d) exp(−d ζ) + b c/d − 1)``, a = 1, b = 2/3,
    c = 5, d = 0.35 ([BH91]); as [C36].
    """
    z = np.asarray(zeta, dtype=float)
    zs = np.maximum(z, 0.0)
    dz = np.minimum(0.35 * zs, _ZETA_CAP)
    b = 2.0 / 3.0
    stable = -((1.0 + 2.0 / 3.0 * zs) ** 1.5 + b * (zs - 5.0 / 0.35) * np.exp(-dz)
               + b * 5.0 / 0.35 - 1.0)
    zu = np.minimum(z, 0.0)
    psik = 2.0 * np.log((1.0 + np.sqrt(1.0 - 15.0 * zu)) / 2.0)
    psic = _psi_convective((1.0 - 34.15 * zu) ** (1.0 / 3.0))
    return np.where(z < 0.0, _psi_blend(zu, psik, psic), stable)


# ---------------------------------------------------------------------------------------
# Cool skin
# ---------------------------------------------------------------------------------------
def cool_skin_solar_fraction(thickness):
    """Fraction of the net solar flux absorbed in the cool skin [-].

    Parameters
    ----------
    thickness : array_like
        Cool-skin thickness δ [m].

    Returns
    -------
    numpy.ndarray
        ``f_s = 0.065 + 11 δ − 6.6e-5/δ (1 − exp(−δ / 8e-4))`` ([F96b]; [ZB05] eq. 5):
        0.009, 0.029, 0.057 at δ = 0.5, 1, 2 mm. Negative below δ ≈ 0.31 mm (gales, u*_w
        > 0.02 m s-1), where the fit leaves its range; kept as published, as COARE does.
    """
    d = np.asarray(thickness, dtype=float)
    return 0.065 + 11.0 * d - 6.6e-5 / d * (1.0 - np.exp(-d / 8.0e-4))


def cool_skin(heat_loss, latent_heat_flux, shortwave_net, ustar_water, temp_sea, thickness,
              latent_heat=None, gravity=9.80665):
    """Temperature drop across the cool skin and its thickness (one fixed-point update).

    Parameters
    ----------
    heat_loss : array_like
        Surface heat loss ``H_s + H_l + LW_net`` (sensible, latent and net long-wave, positive
        upward) [W m-2].
    latent_heat_flux : array_like
        Latent heat flux, positive upward [W m-2] (its salt flux adds buoyancy).
    shortwave_net : array_like
        Net solar flux into the sea [W m-2].
    ustar_water : array_like
        Friction velocity in the water ``u*_w = u* (ρ_a/ρ_w)^(1/2)`` [m s-1].
    temp_sea : array_like
        Water temperature below the skin [K] (for the expansion coefficient and the latent
        heat).
    thickness : array_like
        Previous estimate of the skin thickness δ [m] (sets the solar fraction).
    latent_heat : array_like, optional
        Latent heat of vaporisation [J kg-1]; default ``(2.501 − 0.00237 T[°C]) 1e6``
        ([C36]).
    gravity : float
        [m s-2].

    Returns
    -------
    delta_cool : numpy.ndarray
        ``ΔT_cool = T(−δ) − T_skin = Q δ / k_w`` [K] with ``Q = heat_loss − f_s(δ) R_ns``
        (positive: the skin is cooler).
    thickness : numpy.ndarray
        The new δ [m].

    Notes
    -----
    [F96b] (their eqs. 12 and 14; [ZB05] eqs. 4–6): ``δ = λ ν_w / u*_w`` with Saunders'
    ``λ = 6`` [S67] reduced by free convection when the skin's buoyancy flux is upward,
    ``λ = 6 [1 + (16 g c_w ρ_w ν_w³ B / (k_w² u*_w⁴))^(3/4)]^(−1/3)``,
    ``B = α Q + β S c_w H_l / L_e`` (the salt left by evaporation makes the skin heavier).
    δ is bounded by :data:`SKIN_THICKNESS_MAX`. Called in the bulk iteration (the heat loss
    depends on the skin temperature, the solar fraction on δ) until both settle.
    """
    q_loss = np.asarray(heat_loss, dtype=float)
    hl = np.asarray(latent_heat_flux, dtype=float)
    rns = np.asarray(shortwave_net, dtype=float)
    usw = np.asarray(ustar_water, dtype=float)
    ts_c = np.asarray(temp_sea, dtype=float) - ZERO_CELSIUS
    lv = (2.501 - 0.00237 * ts_c) * 1e6 if latent_heat is None else np.asarray(latent_heat)
    q = q_loss - cool_skin_solar_fraction(thickness) * rns
    alpha = thermal_expansion_seawater(temp_sea)
    buoy = alpha * q + _SALINE_CONTRACTION_S * hl * WATER_HEAT_CAPACITY / lv
    big_c = 16.0 * gravity * WATER_HEAT_CAPACITY * WATER_DENSITY * WATER_VISCOSITY ** 3 \
        / WATER_CONDUCTIVITY ** 2
    ratio = np.maximum(big_c * buoy / usw ** 4, 0.0)
    lam = SAUNDERS_LAMBDA / (1.0 + ratio ** 0.75) ** (1.0 / 3.0)
    delta = np.minimum(lam * WATER_VISCOSITY / usw, SKIN_THICKNESS_MAX)
    return q * delta / WATER_CONDUCTIVITY, delta


# ---------------------------------------------------------------------------------------
# COARE 3.6 bulk fluxes
# ---------------------------------------------------------------------------------------
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
    ts = np.asarray(temp_sea, dtype=float)
    u = np.asarray(wind_speed, dtype=float)
    ta_k = np.asarray(temp_air, dtype=float)
    rh = np.asarray(relative_humidity, dtype=float)
    rns = np.asarray(shortwave_net, dtype=float)
    rl = np.asarray(longwave_down, dtype=float)
    p = np.asarray(pressure, dtype=float)
    ts, u, ta_k, rh, rns, rl, p = np.broadcast_arrays(ts, u, ta_k, rh, rns, rl, p)
    shape = ts.shape
    ts, u, ta_k, rh, rns, rl, p = (np.array(a, dtype=float).ravel()
                                   for a in (ts, u, ta_k, rh, rns, rl, p))
    zu, zt = float(height_wind), float(height_temp)
    zq = zt if height_humidity is None else float(height_humidity)
    zi = float(boundary_layer_height)
    jcool = 1.0 if cool_skin_on else 0.0
    kap = VON_KARMAN
    grav = float(normal_gravity(latitude))

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

    du = u
    dt = ts - ta_k - grav / _CP_AIR * zt
    dq = qs - q
    ta = ta_k
    ug = 0.5
    dter = 0.3 * np.ones_like(ts)
    rnl = emissivity * (SIGMA * (ts - dter * jcool) ** 4 - rl)

    # --- first guess (COARE): neutral coefficients and the bulk Richardson number --------
    ut = np.sqrt(du ** 2 + ug ** 2)
    u10 = ut * np.log(10.0 / 1e-4) / np.log(zu / 1e-4)
    usr = 0.035 * u10
    zo10 = 0.011 * usr ** 2 / grav + _SMOOTH * visa / usr
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
    qsr = -(dq - wetc * dter * jcool) * kap / (np.log(zq / zot10) - psi_temperature(zq / obl))
    tkt = 0.001 * np.ones_like(ts)
    charn = np.where(u10 > _CHARNOCK_UMAX, _CHARNOCK_A1 * _CHARNOCK_UMAX + _CHARNOCK_A2,
                     _CHARNOCK_A1 * u10 + _CHARNOCK_A2)

    first = None
    for it in range(max(int(iterations), 1)):
        zet = kap * grav * zu / ta * (tsr + 0.61 * ta * qsr) / usr ** 2
        obl = zu / zet
        zo = charn * usr ** 2 / grav + _SMOOTH * visa / usr
        rr = zo * usr / visa
        zot = np.minimum(1.6e-4, 5.8e-5 / rr ** 0.72)
        usr = ut * kap / (np.log(zu / zo) - psi_wind(zu / obl))
        qsr = -(dq - wetc * dter * jcool) * kap / (np.log(zq / zot) - psi_temperature(zq / obl))
        tsr = -(dt - dter * jcool) * kap / (np.log(zt / zot) - psi_temperature(zt / obl))
        tvsr = tsr * (1.0 + 0.61 * q) + 0.61 * ta * qsr
        bf = -grav / ta * usr * tvsr
        ug = np.where(bf > 0.0, GUSTINESS_BETA * np.cbrt(np.maximum(bf, 0.0) * zi), 0.2)
        ut = np.sqrt(du ** 2 + ug ** 2)
        gf = np.divide(ut, du, out=np.full_like(ut, np.inf), where=du != 0.0)
        hsb = -rhoa * _CP_AIR * usr * tsr
        hlb = -rhoa * lv * usr * qsr
        if cool_skin_on:
            dter, tkt = cool_skin(rnl + hsb + hlb, hlb, rns, usr * rho_ratio, ts, tkt, lv, grav)
        else:
            dter = np.zeros_like(ts)
        rnl = emissivity * (SIGMA * (ts - dter * jcool) ** 4 - rl)
        if it == 0:
            first = (usr.copy(), tsr.copy(), qsr.copy(), obl.copy(), dter.copy(), tkt.copy())
        u10n = usr / kap / gf * np.log(10.0 / zo)
        charn = np.where(u10n > _CHARNOCK_UMAX, _CHARNOCK_A1 * _CHARNOCK_UMAX + _CHARNOCK_A2,
                         _CHARNOCK_A1 * u10n + _CHARNOCK_A2)
    if k50.any():
        for arr, val in zip((usr, tsr, qsr, obl, dter, tkt), first):
            arr[k50] = val[k50]
        rnl = emissivity * (SIGMA * (ts - dter * jcool) ** 4 - rl)
    hsb = -rhoa * _CP_AIR * usr * tsr
    hlb = -rhoa * lv * usr * qsr
    tau = rhoa * usr ** 2 / gf
    return BulkFluxes(*(a.reshape(shape) for a in (
        tau, usr, usr * rho_ratio, hsb, hlb, rnl, rns, dter * jcool, tkt,
        ts - dter * jcool, obl, rhoa)))


# ---------------------------------------------------------------------------------------
# Diurnal warm layer (Zeng & Beljaars 2005)
# ---------------------------------------------------------------------------------------
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


# ---------------------------------------------------------------------------------------
# Diurnal warm layer (COARE: Fairall et al. 1996b)
# ---------------------------------------------------------------------------------------
WARM_LAYER_MODELS = ("fairall_coare", "zeng_beljaars")
"""The warm-layer models of :func:`sea_skin_temperature` by name."""
DEFAULT_WARM_LAYER = "fairall_coare"
"""The warm layer when none is named (why: the module's docstring)."""


def coare_solar_fraction(depth):
    """Solar fraction the COARE warm layer keeps, f_x(D) [-] ([F96b]; [C30], [C36] ``fxp``).

    ``f_x = 1 − Σ a_i γ_i (1 − exp(−D/γ_i)) / D`` with the three bands a_i =
    :data:`SOLOVIEV_FRACTIONS`, γ_i = :data:`COARE_SOLAR_DEPTHS`: 0.37 at D = 0.35 m, 0.57 at
    3 m, 0.76 at 19 m. This is 1 minus the solar flux averaged over the layer's depth, not 1
    minus the flux at its base (the absorbed fraction, 0.64 at 3 m:
    :func:`warm_layer_solar_fraction`). The reference code [C36] notes as much in a comment,
    and that the form "has been used in this scheme since 1996 without making bad
    predictions"; Ri_c = 0.65 is tuned with it. Kept as the reference has it.
    """
    d = np.maximum(np.asarray(depth, dtype=float), 1e-12)
    return 1.0 - sum(a * g * -np.expm1(-d / g) for a, g in zip(SOLOVIEV_FRACTIONS,
                                                              COARE_SOLAR_DEPTHS)) / d


def _coare_fraction(d):
    a, g = SOLOVIEV_FRACTIONS, COARE_SOLAR_DEPTHS
    return 1.0 - (a[0] * g[0] * -math.expm1(-d / g[0]) + a[1] * g[1] * -math.expm1(-d / g[1])
                  + a[2] * g[2] * -math.expm1(-d / g[2])) / d


class CoareWarmLayer(NamedTuple):
    """State of the COARE warm layer at the samples (:func:`coare_warm_layer`)."""

    delta: np.ndarray           #: ΔT, warming from the layer's base to its top [K]
    depth: np.ndarray           #: D, the layer's depth [m]
    heat: np.ndarray            #: Q_ac, heat accumulated since the onset [J m-2]
    stress: np.ndarray          #: τ_ac, stress accumulated since the onset [N s m-2]
    solar_fraction: np.ndarray  #: f_x, the solar fraction the layer keeps [-]
    on: np.ndarray              #: the day's accumulation has started (bool)


def coare_warm_layer(step, solar_hours, shortwave_net, heat_loss, tau, temp_sea, *,
                     gravity=9.80665, started=False, max_depth=COARE_MAX_DEPTH,
                     critical_richardson=COARE_CRITICAL_RICHARDSON) -> CoareWarmLayer:
    """The COARE warm layer over a sequence of steps ([F96b], the logic of [C30], [C36]).

    Parameters
    ----------
    step : array_like
        ``step[k]``: duration of the step from sample k−1 to sample k [s] (``step[0]``
        unused).
    solar_hours : array_like
        Local solar time of the samples [h, 0–24]: the layer is reset at the first sample
        after midnight (where it decreases).
    shortwave_net : array_like
        ``shortwave_net[k]``: net solar flux into the sea over step k, R_ns [W m-2].
    heat_loss : array_like
        ``heat_loss[k]``: the surface's heat loss over step k, ``Q_out = LW_net + H_s + H_l``
        (positive upward; the reference adds the rain's heat flux) [W m-2].
    tau : array_like
        ``tau[k]``: wind stress over step k [N m-2].
    temp_sea : array_like
        Water temperature at the samples [K] (the expansion coefficient α of step k from
        ``temp_sea[k]``).
    gravity : float
        [m s-2].
    started : bool
        False (a record): the first sample is taken as the reference's first line — nothing
        is integrated before a sample at or before :data:`COARE_FIRST_START_HOUR` (a day
        joined after 6 am is skipped, its morning missing). True: the series starts at a
        reset (a periodic day rolled to its midnight).
    max_depth, critical_richardson : float
        D_max [m], Ri_c [-].

    Returns
    -------
    CoareWarmLayer
        At each sample.

    Notes
    -----
    Per step k of duration Δt, after the morning onset — the first step whose heating of
    the layer ``q = f_x R_ns − Q_out`` reaches :data:`COARE_ONSET_FLUX`, f_x the previous
    step's fraction — [F96b]'s integrals (ρ_w, c_w = :data:`WATER_DENSITY`,
    :data:`WATER_HEAT_CAPACITY`)::

        τ_ac += max(τ, 0.002) Δt
        Q_ac += (f_x(D) R_ns − Q_out) Δt
        D  = min(D_max, (2 Ri_c c_w / (α g ρ_w))^(1/2) τ_ac / Q_ac^(1/2))
        ΔT = (2 α g / (Ri_c ρ_w))^(1/2) Q_ac^(3/2) / (c_w^(3/2) τ_ac)    (0 if Q_ac ≤ 0)

    f_x(D) (:func:`coare_solar_fraction`) and D solved together by five fixed-point passes
    from the previous step's D, as the reference does. The two are a linear profile's: the
    heat ρ_w c_w ΔT D / 2 = Q_ac and the current Δu = 2 τ_ac / (ρ_w D) of the momentum put in
    since the onset, at the bulk Richardson number ``g α ΔT D / Δu² = Ri_c`` (PWP, Price et
    al. 1986, J. Geophys. Res. 91, 8411). While the accumulated heat is not positive the
    layer is wiped out (D = D_max, f_x = :data:`COARE_WIPED_FRACTION`) and the integrals go
    on: it reappears the first time the heat integral turns positive again. At the first
    sample after local midnight every quantity is reset (ΔT = 0, Q_ac = τ_ac = 0, D =
    D_max, f_x = :data:`COARE_START_FRACTION`; the step across midnight is not integrated)
    and the next onset awaited.

    Sequential by nature (each step needs the last one's D, f_x and sums): a plain loop over
    the steps, the inputs vectorised by the caller. ``heat_loss`` and ``tau`` are whatever the
    caller takes for the step: the reference uses the previous sample's (explicit), R_ns at
    the current one; :func:`coare_warm_layer_series` the step's means. Given the
    reference's own forcing this reproduces its output (tests: NOAA's COARE 3.0b test case,
    ΔT to 0.005 K and D to 0.006 m, its printed precision).

    The reference's clock: local solar time, UTC + longitude/15 h [C30] (COARE 3.6 adds
    half an hour, ``(lon + 7.5)/15``, moving the nightly reset to 23:30); its first-day rule
    that of 3.6 (3.0 also stops a first day begun before 6 am at 6 am, until its first
    midnight).
    """
    n = np.size(step)
    dts, hrs, rns, qout, taus = (np.broadcast_to(np.asarray(x, dtype=float), (n,)).tolist()
                                 for x in (step, solar_hours, shortwave_net, heat_loss, tau))
    alpha = np.broadcast_to(thermal_expansion_seawater(temp_sea), (n,)).tolist()
    out = np.zeros((5, n))
    on_out = np.zeros(n, dtype=bool)
    c1_k = math.sqrt(2.0 * critical_richardson * WATER_HEAT_CAPACITY / (gravity * WATER_DENSITY))
    c2_k = math.sqrt(2.0 * gravity / (critical_richardson * WATER_DENSITY)) \
        / WATER_HEAT_CAPACITY ** 1.5
    d_max = float(max_depth)
    on, fx, depth, tau_ac, q_ac, delta = False, COARE_START_FRACTION, d_max, 0.0, 0.0, 0.0
    go = bool(started)
    out[1, 0], out[4, 0] = depth, fx
    for k in range(1, n):
        if not go and hrs[k] <= COARE_FIRST_START_HOUR:
            go = True
        if go:
            if hrs[k] < hrs[k - 1]:                 # local midnight: reset
                on, fx, depth, tau_ac, q_ac, delta = (False, COARE_START_FRACTION, d_max,
                                                      0.0, 0.0, 0.0)
            else:
                dt, r, qo = dts[k], rns[k], qout[k]
                if on or fx * r - qo >= COARE_ONSET_FLUX:
                    on = True
                    al = max(alpha[k], 1e-12)
                    c1, c2 = c1_k / math.sqrt(al), c2_k * math.sqrt(al)
                    tau_ac += max(COARE_MIN_STRESS, taus[k]) * dt
                    if q_ac + (fx * r - qo) * dt > 0.0:
                        for _ in range(5):
                            fx = _coare_fraction(depth)
                            qj = (fx * r - qo) * dt
                            if q_ac + qj > 0.0:
                                depth = min(d_max, c1 * tau_ac / math.sqrt(q_ac + qj))
                    else:                           # the layer is wiped out
                        fx, depth = COARE_WIPED_FRACTION, d_max
                        qj = (fx * r - qo) * dt
                    q_ac += qj
                    delta = c2 * q_ac ** 1.5 / tau_ac if q_ac > 0.0 else 0.0
        out[:, k] = delta, depth, q_ac, tau_ac, fx
        on_out[k] = on
    return CoareWarmLayer(out[0], out[1], out[2], out[3], out[4], on_out)


def coare_warm_layer_series(seconds, solar_hours, shortwave_net, heat_loss, tau, temp_sea, *,
                            heat_loss_end=None, tau_end=None, period=None, gravity=9.80665,
                            max_depth=COARE_MAX_DEPTH,
                            critical_richardson=COARE_CRITICAL_RICHARDSON) -> CoareWarmLayer:
    """The COARE warm layer over a time series of samples (forcing linear between them).

    Parameters
    ----------
    seconds : array_like
        Increasing sample times [s].
    solar_hours : array_like
        Local solar time of the samples [h] (midnight resets the layer).
    shortwave_net, heat_loss, tau, temp_sea : array_like
        At the samples: R_ns [W m-2], ``Q_out = LW_net + H_s + H_l`` (up) [W m-2], wind
        stress [N m-2], water temperature [K] (:func:`coare_warm_layer`).
    heat_loss_end, tau_end : array_like, optional
        Q_out and τ at the samples as the end of the step that arrives there, where they
        differ from ``heat_loss``, ``tau`` (the step's start values): the coupling of
        :func:`sea_skin_temperature` evaluates both ends of a step with the warm layer at
        its start. Default: the same values.
    period : float, optional
        The samples are one period ``[t0, t0 + period)`` of a repeating day: the day is
        integrated once from its reset (the sample after local midnight) round to it; it
        must hold exactly one midnight. None: a record, from its first sample
        (``started=False``).
    gravity, max_depth, critical_richardson : float
        As :func:`coare_warm_layer`.

    Returns
    -------
    CoareWarmLayer
        At the samples.

    Notes
    -----
    Each step takes the mean of its two ends' forcing (the trapezoidal rule for the
    integrals of heat and stress): the reference code's own time integration takes the
    solar flux at the step's end and the fluxes at its start, first order in the step.
    The morning onset, where the heating ``f_x R_ns − Q_out`` (f_x = 0.5 then) first reaches
    :data:`COARE_ONSET_FLUX`, falls between two samples: an extra sample is inserted at the
    crossing (the forcing linear over the step) so that the accumulation starts there, not
    at the grid's next sample — right after the onset ΔT grows as the square root of the
    time since it (a constant heating Q and stress τ give ``ΔT ∝ Q^(3/2) t^(1/2) / τ``): on
    the clear tropical day at 1 m s-1 a 10 min grid's onset, 6 min late, put 0.07 K on the
    first samples and 0.02 K on the rest of the day. What remains of the step's size: the
    midnight reset falls on a sample, and D, f_x are solved once a step. Measured against a
    1 min step on clear tropical days (tests): 10 min within 0.015 K (1 m s-1, peak 2.7 K),
    0.006, 0.003, 0.0006 K at 2, 3, 5 m s-1; hourly 0.09, 0.03, 0.012, 0.003 K — 3.5 to 8
    times closer than the reference's own integration on the same grids.
    """
    t = np.asarray(seconds, dtype=float).ravel()
    n = t.size
    h, r, q, ta, ts = (np.broadcast_to(np.asarray(x, dtype=float), (n,)).astype(float)
                       for x in (solar_hours, shortwave_net, heat_loss, tau, temp_sea))
    q_end, ta_end = (x if y is None else
                     np.broadcast_to(np.asarray(y, dtype=float), (n,)).astype(float)
                     for x, y in ((q, heat_loss_end), (ta, tau_end)))
    h = np.mod(h, 24.0)
    kw = dict(gravity=gravity, max_depth=max_depth, critical_richardson=critical_richardson)
    if period is None:
        order, tt, started = np.arange(n), t, False
    else:
        wraps = np.flatnonzero(h < np.roll(h, 1))
        require(wraps.size == 1, "solar_hours", h[:3].tolist(),
                "must pass local midnight exactly once over a periodic day "
                f"(found {wraps.size} times)")
        first = int(wraps[0])
        order = (first + np.arange(n)) % n
        tt = t[order] + float(period) * (order < first)
        started = True
    hh = h[order]
    # each field at the samples as a step's start (a) and as the previous step's end (b)
    a = [x[order] for x in (r, q, ta, ts)]
    b = [x[order] for x in (r, q_end, ta_end, ts)]
    # the morning onset between two samples: where the heating at the start fraction,
    # linear over the step, reaches the threshold, a sample is inserted
    qa = COARE_START_FRACTION * a[0][:-1] - a[1][:-1]
    qb = COARE_START_FRACTION * b[0][1:] - b[1][1:]
    cross = np.flatnonzero((qa < COARE_ONSET_FLUX) & (qb > COARE_ONSET_FLUX)
                           & (hh[1:] >= hh[:-1])) + 1
    if cross.size:
        phi = (COARE_ONSET_FLUX - qa[cross - 1]) / (qb[cross - 1] - qa[cross - 1])
        mid = [x[cross - 1] + phi * (y[cross] - x[cross - 1]) for x, y in zip(a, b)]
        dt_c = phi * (tt[cross] - tt[cross - 1])
        a = [np.insert(x, cross, m) for x, m in zip(a, mid)]
        b = [np.insert(y, cross, m) for y, m in zip(b, mid)]
        hh = np.insert(hh, cross, np.mod(hh[cross - 1] + dt_c / 3600.0, 24.0))
        tt = np.insert(tt, cross, tt[cross - 1] + dt_c)
    keep = np.arange(n) + np.searchsorted(cross, np.arange(n), side="right")
    means = [np.concatenate(([x[0]], 0.5 * (x[:-1] + y[1:]))) for x, y in zip(a, b)]
    res = coare_warm_layer(np.diff(tt, prepend=tt[0]), hh, *means, started=started, **kw)
    back = np.empty(n, dtype=int)
    back[order] = np.arange(n)
    return CoareWarmLayer(*(np.asarray(x)[keep][back] for x in res))


# ---------------------------------------------------------------------------------------
# Skin temperature over a time series
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SeaSkin:
    """Skin temperature over a time series (:func:`sea_skin_temperature`).

    Attributes
    ----------
    seconds : numpy.ndarray
        Sample times [s].
    temp_bulk, temp_skin : numpy.ndarray
        Bulk SST (at ``depth``) and skin temperature [K];
        ``temp_skin = temp_bulk + delta_warm − delta_cool``.
    delta_warm, delta_cool : numpy.ndarray
        ΔT_warm ≥ 0, the warming between the bulk's depth and the surface, and ΔT_cool [K].
    fluxes : BulkFluxes
        Surface fluxes at the skin temperature.
    heat_flux_warm_layer : numpy.ndarray
        Heat flux into the warm layer [W m-2]: the non-solar flux into the sea plus the
        solar flux the layer keeps (Z&B: above d; COARE: f_x(D) of it).
    periodic : bool
    spinup_days : int
        Periodic forcing: days integrated (Z&B: until the warm layer repeated; COARE: 1,
        from its midnight reset); 0 for a record.
    day_change : float
        Periodic forcing [K]: Z&B: ΔT_warm at the end of the last day minus at its start;
        COARE: the ΔT_warm left at local midnight, which the reset discards.
    coupling_passes : int
        Passes of the flux / warm-layer coupling until it settled.
    warm_layer : str
        The warm-layer model (:data:`WARM_LAYER_MODELS`), or ``'none'``.
    layer_warming, layer_depth : numpy.ndarray
        The whole layer's warming [K] and depth [m]: COARE's ΔT and D (``delta_warm =
        ΔT min(1, depth / D)``); Z&B's ΔT_warm and d.
    """

    seconds: np.ndarray
    temp_bulk: np.ndarray
    temp_skin: np.ndarray
    delta_warm: np.ndarray
    delta_cool: np.ndarray
    fluxes: BulkFluxes
    heat_flux_warm_layer: np.ndarray
    periodic: bool
    spinup_days: int
    day_change: float
    coupling_passes: int
    warm_layer: str
    layer_warming: np.ndarray
    layer_depth: np.ndarray


def warm_layer_model(value) -> str:
    """The warm-layer model's name from a name or a switch (True: :data:`DEFAULT_WARM_LAYER`,
    False or None: ``'none'``)."""
    if value is True:
        return DEFAULT_WARM_LAYER
    if value is False or value is None:
        return "none"
    require(value in WARM_LAYER_MODELS + ("none",), "warm_layer", value,
            "must be " + ", ".join(repr(m) for m in WARM_LAYER_MODELS + ("none",))
            + " (or a bool)")
    return str(value)


def sea_skin_temperature(seconds, temp_bulk, wind_speed, temp_air, relative_humidity,
                         shortwave_down, longwave_down, albedo=COARE_ALBEDO,
                         pressure=STANDARD_PRESSURE, *, period=None, latitude=45.0,
                         height_wind=10.0, height_temp=2.0, depth=WARM_LAYER_DEPTH,
                         nu=WARM_LAYER_NU, warm_layer=DEFAULT_WARM_LAYER, solar_hours=None,
                         cool_skin_on=True, initial_warm=0.0, tolerance=1e-4, max_days=60,
                         max_passes=30) -> SeaSkin:
    """Skin temperature of the sea over a time series: bulk fluxes, cool skin, warm layer.

    Parameters
    ----------
    seconds : array_like
        Increasing sample times [s] (a step of ≤ 10 min keeps the time error of the warm
        layer to a few hundredths of a kelvin or less; see the tests).
    temp_bulk : array_like
        Bulk sea temperature at ``depth`` [K].
    wind_speed : array_like
        True wind at ``height_wind`` [m s-1].
    temp_air : array_like
        Air temperature at ``height_temp`` [K].
    relative_humidity : array_like
        [%] (at ``height_temp``).
    shortwave_down : array_like
        Downwelling solar irradiance on the horizontal (global horizontal) [W m-2].
    longwave_down : array_like
        Downwelling long-wave [W m-2].
    albedo : array_like
        Sea albedo for ``shortwave_down`` [-].
    pressure : array_like
        Surface pressure [Pa].
    period : float, optional
        The series is one period of a repeating cycle (a design day, ``seconds`` covering
        ``[t0, t0 + period)``): Z&B is spun up over repeated periods until it repeats to
        ``tolerance``; COARE integrates the day once from its midnight reset. None: a
        record, integrated from its first sample (Z&B from ``initial_warm``; COARE by the
        reference's rule for a first day, :func:`coare_warm_layer`).
    latitude : float
        [deg].
    height_wind, height_temp : float
        Measurement heights [m] (ASSUMPTION for weather records without them: 10 m wind,
        2 m screen-height air temperature and humidity).
    depth : float
        Depth of ``temp_bulk`` [m]: Z&B's layer base d; for COARE, where its linear profile
        is read.
    nu : float
        Z&B's profile exponent ν [-].
    warm_layer : {'fairall_coare', 'zeng_beljaars', 'none'} or bool
        The warm-layer model (True: the default, ``'fairall_coare'``; False or ``'none'``:
        ΔT_warm = 0).
    solar_hours : array_like, optional
        Local solar time of the samples [h] (COARE's midnight reset); default: the
        samples' own clock, ``seconds / 3600`` modulo 24 (seconds after local solar
        midnight).
    cool_skin_on : bool
        Switch the cool skin off (ΔT_cool = 0).
    initial_warm : float
        Z&B, record: ΔT_warm at the first sample [K].
    tolerance : float
        [K]: end-of-day repetition of a spun-up periodic day (Z&B), and the change between
        two passes of the flux / warm-layer coupling.
    max_days, max_passes : int
        Caps of the spin-up and of the coupling.

    Returns
    -------
    SeaSkin

    Notes
    -----
    The bulk fluxes depend on the skin temperature and the warm layer on the fluxes: the
    coupling is iterated — fluxes (:func:`bulk_fluxes`, vectorised over all samples) at
    ``T_bulk + ΔT_warm``, then the warm layer over the series — until ΔT_warm changes by
    less than ``tolerance``. Z&B (:func:`warm_layer_series`) with the layer's heat flux
    ``Q = −(H_s + H_l + LW_net) + f_d(d) R_ns`` (:func:`warm_layer_solar_fraction`), u*_w
    and the flux's linearised response to ΔT_warm (the fluxes respond with ~20–40 W m-2
    K-1 against the layer's heat capacity ρ_w c_w d ν/(ν+1) = 2.8 MJ m-2 K-1); COARE
    (:func:`coare_warm_layer_series`) with ``Q_out = H_s + H_l + LW_net`` (no rain heat
    flux: the weather carries no rain), R_ns and the stress, both ends of each step
    evaluated with the warm layer at the step's start: the layer's feedback on the fluxes
    explicit, as in the reference code (which takes the fluxes of the step before), so that
    the morning onset (a threshold) depends only on the past and the passes settle; the
    forcing itself integrated to second order. All the fluxes are those of the skin over
    the warm layer (the reference's COARE 3.6 version takes its net long-wave from the bulk
    temperature without the warm layer: 6 W m-2 less loss per kelvin of warming).
    """
    model = warm_layer_model(warm_layer)
    t = np.asarray(seconds, dtype=float).ravel()
    n = t.size
    require(n >= 2 and bool(np.all(np.diff(t) > 0)), "seconds", t[:3].tolist(),
            "must hold >= 2 increasing times [s]")

    def arr(x, name):
        a = np.broadcast_to(np.asarray(x, dtype=float), (n,)).astype(float)
        if not np.all(np.isfinite(a)):
            raise InputError(name, a, "must be finite")
        return a

    tb = arr(temp_bulk, "temp_bulk")
    check_range("temp_bulk", tb, 268.0, 315.0, "K")
    u = np.maximum(arr(wind_speed, "wind_speed"), 0.0)
    ta = arr(temp_air, "temp_air")
    rh = np.clip(arr(relative_humidity, "relative_humidity"), 1.0, 100.0)
    rs = np.maximum(arr(shortwave_down, "shortwave_down"), 0.0)
    rl = arr(longwave_down, "longwave_down")
    alb = arr(albedo, "albedo")
    check_range("albedo", alb, 0.0, 1.0)
    p = arr(pressure, "pressure")
    hours = np.mod(t / 3600.0 if solar_hours is None else arr(solar_hours, "solar_hours"),
                   24.0)
    rns = (1.0 - alb) * rs
    if period is not None:
        period = float(period)
        require(period > t[-1] - t[0], "period", period,
                f"must exceed the span of the samples ({t[-1] - t[0]:g} s)")
    gravity = float(normal_gravity(latitude))
    f_d = float(warm_layer_solar_fraction(depth))

    def fluxes_at(dtw):
        return bulk_fluxes(tb + dtw, u, ta, rh, rns, rl, p, height_wind=height_wind,
                           height_temp=height_temp, latitude=latitude,
                           cool_skin_on=cool_skin_on)

    dtw = np.zeros(n)
    fl = fluxes_at(dtw)
    q_warm = fl.heat_flux_nonsolar + f_d * rns
    layer_dt, layer_d = np.zeros(n), np.full(n, float(depth))
    passes, days, change = 0, 0, 0.0
    start = float(initial_warm)
    if model == "zeng_beljaars":
        for passes in range(1, max_passes + 1):
            # the surface flux's response to the warm layer, linearised around this pass
            slope = (fluxes_at(dtw + _DT_PROBE).heat_flux_nonsolar
                     - fl.heat_flux_nonsolar) / _DT_PROBE

            def integrate(initial, per=None):
                return warm_layer_series(t, q_warm, fl.ustar_water, tb, initial, depth, nu,
                                         per, slope, dtw)

            if period is None:
                new = integrate(start)
            else:
                for days in range(1, max_days + 1):
                    full = integrate(start, period)
                    change = float(full[-1] - full[0])
                    start = float(full[-1])
                    if abs(change) <= tolerance:
                        break
                new = full[:-1]
            diff = float(np.max(np.abs(new - dtw)))
            dtw = new
            fl = fluxes_at(dtw)
            q_warm = fl.heat_flux_nonsolar + f_d * rns
            if diff <= tolerance:
                break
        layer_dt = dtw
    elif model == "fairall_coare":
        days = 0 if period is None else 1
        end = fl
        for passes in range(1, max_passes + 1):
            wl = coare_warm_layer_series(t, hours, rns, -fl.heat_flux_nonsolar, fl.tau, tb,
                                         heat_loss_end=-end.heat_flux_nonsolar,
                                         tau_end=end.tau, period=period, gravity=gravity)
            new = wl.delta * np.minimum(1.0, float(depth) / wl.depth)
            diff = float(np.max(np.abs(new - dtw)))
            dtw = new
            fl = fluxes_at(dtw)
            # each step's end with the warm layer at its start (explicit in the layer's
            # feedback on the fluxes, as the reference; the passes converge step by step)
            end = fluxes_at(np.roll(dtw, 1) if period is not None
                            else np.concatenate((dtw[:1], dtw[:-1])))
            if diff <= tolerance:
                break
        q_warm = fl.heat_flux_nonsolar + wl.solar_fraction * rns
        layer_dt, layer_d = wl.delta, wl.depth
        if period is not None:
            last = int(np.flatnonzero(hours < np.roll(hours, 1))[0]) - 1
            change = float(dtw[last])
    return SeaSkin(seconds=t, temp_bulk=tb, temp_skin=tb + dtw - fl.delta_cool,
                   delta_warm=dtw, delta_cool=fl.delta_cool, fluxes=fl,
                   heat_flux_warm_layer=q_warm, periodic=period is not None,
                   spinup_days=days, day_change=change, coupling_passes=passes,
                   warm_layer=model, layer_warming=layer_dt, layer_depth=layer_d)
