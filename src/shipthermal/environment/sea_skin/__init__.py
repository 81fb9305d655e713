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

Modules: :mod:`.constants` (water, air, COARE and the warm layers' numbers),
:mod:`.thermodynamics` (saturation humidity, expansion, gravity), :mod:`.stability`
(Monin–Obukhov functions), :mod:`.cool_layer` (the cool skin), :mod:`.bulk` (the COARE 3.6
fluxes), :mod:`.zeng_beljaars` and :mod:`.coare_warm` (the two warm layers),
:mod:`.temperature` (the coupling over a time series, :func:`sea_skin_temperature`).

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

from .bulk import BulkFluxes, bulk_fluxes
from .coare_warm import (CoareWarmLayer, coare_solar_fraction, coare_warm_layer,
                         coare_warm_layer_series)
from .constants import (BOUNDARY_LAYER_HEIGHT, COARE_ALBEDO, COARE_CRITICAL_RICHARDSON,
                        COARE_EMISSIVITY, COARE_FIRST_START_HOUR, COARE_MAX_DEPTH,
                        COARE_MIN_STRESS, COARE_ONSET_FLUX, COARE_SOLAR_DEPTHS,
                        COARE_START_FRACTION, COARE_WIPED_FRACTION, GUSTINESS_BETA, SALINITY,
                        SAUNDERS_LAMBDA, SKIN_THICKNESS_MAX, SOLOVIEV_ATTENUATION,
                        SOLOVIEV_FRACTIONS, STANDARD_PRESSURE, VON_KARMAN, WARM_LAYER_DEPTH,
                        WARM_LAYER_NU, WATER_CONDUCTIVITY, WATER_DENSITY, WATER_HEAT_CAPACITY,
                        WATER_VISCOSITY)
from .cool_layer import cool_skin, cool_skin_solar_fraction
from .stability import psi_temperature, psi_wind
from .temperature import (DEFAULT_WARM_LAYER, WARM_LAYER_MODELS, SeaSkin, sea_skin_temperature,
                          warm_layer_model)
from .thermodynamics import (normal_gravity, saturation_vapour_pressure_buck,
                             specific_humidity_air, specific_humidity_sea,
                             thermal_expansion_seawater)
from .zeng_beljaars import (warm_layer_equilibrium, warm_layer_rates, warm_layer_series,
                            warm_layer_solar_fraction, warm_layer_stability, warm_layer_step)

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
