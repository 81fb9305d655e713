"""Named parameter sets: every default of the surface physics, written once with its source.

In the spirit of pvlib's ``TEMPERATURE_MODEL_PARAMETERS``: literature values are named data
that the thermal stage (:mod:`shipthermal.forcing`), the scenario and the imaging
(:mod:`imaging.radiometry`, :mod:`imaging.atmosphere`) read from here, so the two stages can
never disagree on a number. The module imports nothing heavier than :mod:`shipthermal.errors`
(the scenario loads it without numpy-heavy imports and the imaging uses it as a lower
layer).

The other named sets live next to the code that gives them meaning, each written once as
well: materials in :data:`shipthermal.materials.MATERIALS`, plate layups and compartment
temperatures in :mod:`shipthermal.geometry.layups`, the built-in design days in
:mod:`shipthermal.environment.climatology`, the convection correlations in
:data:`shipthermal.environment.convection.CONVECTION_MODELS`.

Parts are the main parts of :mod:`shipthermal.geometry.parts` (``hull`` stands for both
``hull_wetted`` and ``hull_dry``).
"""

from __future__ import annotations

import math
import re

from .errors import InputError, check_range

__all__ = [
    "BAND_EMISSIVITY", "LONGWAVE_EMISSIVITY", "SOLAR_ABSORPTIVITY", "SEA_EMISSIVITY",
    "BANDS", "BAND_ALIASES", "ATMOSPHERE_WAVELENGTH_UM", "parse_band",
    "WIND_SPEED_MAX", "check_wind_speed", "DEFAULT_CONVECTION_MODEL",
    "CONVECTION_MODEL_SOURCES", "CONVECTION_ROUGHNESS", "ROUGHNESS_CLASSES", "CLEAR_SKY_MODEL_NAMES", "CLOUD_MODEL_NAMES", "DECOMPOSITIONS",
    "SEA_SKIN_MODEL_NAMES", "DEFAULT_SEA_SKIN_MODEL",
    "STATION_FORMATS", "STATION_SUFFIXES", "MAX_GAP_HOURS", "TEMP_UNITS", "CLOUD_COVER_SCALE",
    "AIR_SEA_DIFFERENCE_K", "AIR_SEA_WARN_K", "HUMIDITY_FRACTION_MAX", "WIND_SPEED_WARN",
    "MAX_SITE_DISTANCE_KM",
    "SEASONS", "DALIAN", "DESIGN_DAY_DATES", "season_of_date", "LATITUDE_MAX", "SHIP_SPEED_MAX",
]

# ---------------------------------------------------------------------------------------
# Surface optics of the ship, per main part
# ---------------------------------------------------------------------------------------
BAND_EMISSIVITY: dict[str, dict[str, float]] = {
    "hull": {"3-5": 0.85, "8-14": 0.90},
    "deck": {"3-5": 0.90, "8-14": 0.95},
    "superstructure": {"3-5": 0.78, "8-14": 0.88},
}
"""Band emissivity per main part and sensor band [-]: the paper's §5 values (3–5 µm: hull
0.85, deck 0.90, superstructure 0.78; 8–14 µm: 0.90, 0.95, 0.88)."""

LONGWAVE_EMISSIVITY: dict[str, float] = {p: v["8-14"] for p, v in BAND_EMISSIVITY.items()}
"""Broadband (thermal, ~4–50 µm) hemispherical emissivity per main part [-] of the thermal
stage: the paper's §5 8–14 µm value of the part (hull 0.90, deck 0.95, superstructure 0.88).

The 8–14 µm window holds the peak of ~300 K emission (about a third of it); outside it the
paints are near-black (Incropera et al., 6th ed., Table A.11: 0.90–0.98 for paints of all
colours, and ISO 6946:2017 Annex C's 0.90 for painted surfaces sits inside that range), so
the band value is the best broadband estimate the sources give per part, and the thermal and
imaging stages use one emissivity per part where they overlap. Kirchhoff: the same value
absorbs the incident long-wave."""

SOLAR_ABSORPTIVITY: dict[str, float] = {"hull": 0.70, "deck": 0.85, "superstructure": 0.70}
"""Solar (short-wave) absorptivity per main part [-].

ASSUMPTION bracketed by a source: ASHRAE Handbook — Fundamentals (2017), ch. 18, sol-air
temperature, takes α/h_o = 0.026 m² K W-1 for light-coloured and 0.052 for dark surfaces
with h_o = 17 W m-2 K-1, i.e. α ≈ 0.45 (light) and α ≈ 0.9 (dark). Naval haze-grey topside
paint is a medium grey: 0.70 (the hull below the waterline never sees the sun; its value is
unused). Weather decks carry a dark-grey epoxy non-skid covering: 0.85, near the dark end.
Fixed before any comparison with the paper's reference deck temperatures (and part of the
validation's ±0.05 sensitivity table); override per part when paint data are known."""


SEA_EMISSIVITY = 0.984
"""Broadband hemispherical emissivity of the sea surface [-]: Konda, Imasato, Nishi & Toda
(1994), J. Oceanogr. 50, 17–30, measured 0.984 ± 0.004 (the commonly used ≈ 0.98)."""

# ---------------------------------------------------------------------------------------
# Sensor bands
# ---------------------------------------------------------------------------------------
BANDS: dict[str, tuple[float, float]] = {"3-5": (3.0, 5.0), "8-14": (8.0, 14.0)}
"""The paper's rectangular sensor bands [µm] (§5)."""
BAND_ALIASES = {"mwir": "3-5", "3-5um": "3-5", "lwir": "8-14", "8-14um": "8-14"}
"""Other names of :data:`BANDS` (lower case, no spaces, µm written ``um``)."""
ATMOSPHERE_WAVELENGTH_UM = (2.9, 14.5)
"""Wavelength range [µm] of the embedded atmosphere tables: every band must lie inside."""


def parse_band(band) -> tuple[str, tuple[float, float]]:
    """Canonical name and limits [µm] of a band.

    Accepts ``"3-5"``, ``"8-14"``, ``"mwir"``, ``"lwir"``, any ``"lo-hi"`` string in µm
    (``"3.7-4.8"``) or a ``(lo, hi)`` pair, inside :data:`ATMOSPHERE_WAVELENGTH_UM`. A band
    equal to a named one gets its name.
    """
    lo_lim, hi_lim = ATMOSPHERE_WAVELENGTH_UM
    allowed = (f"must be {', '.join(repr(b) for b in BANDS)}, 'mwir', 'lwir' or 'lo-hi' in "
               f"µm with {lo_lim:g} <= lo < hi <= {hi_lim:g} (the atmosphere tables' range)")
    if isinstance(band, str):
        key = band.strip().lower().replace(" ", "").replace("µm", "um")
        key = BAND_ALIASES.get(key, key)
        if key in BANDS:
            return key, BANDS[key]
        m = re.match(r"^(\d+(?:\.\d*)?)-(\d+(?:\.\d*)?)(?:um)?$", key)
        if not m:
            raise InputError("band", band, allowed)
        lo, hi = float(m.group(1)), float(m.group(2))
    else:
        try:
            items = list(band)
        except TypeError:
            raise InputError("band", band, allowed) from None
        if len(items) != 2 or any(isinstance(b, (bool, str)) for b in items):
            raise InputError("band", band, allowed)
        try:
            lo, hi = float(items[0]), float(items[1])
        except (TypeError, ValueError):
            raise InputError("band", band, allowed) from None
    if not (lo_lim <= lo < hi <= hi_lim):
        raise InputError("band", band, allowed)
    for name, lim in BANDS.items():
        if math.isclose(lim[0], lo) and math.isclose(lim[1], hi):
            return name, lim
    return f"{lo:g}-{hi:g}", (lo, hi)


# ---------------------------------------------------------------------------------------
# Model choices
# ---------------------------------------------------------------------------------------
CONVECTION_MODEL_SOURCES: dict[str, dict[str, str]] = {
    "flat_plate_mixed": {
        "source": "forced: flat plate, laminar to Re_c = 5e5 then turbulent (Incropera et al., "
                  "6th ed., eq. 7.38); natural: Churchill & Chu (1975) vertical, Lloyd & Moran "
                  "(1974) / 0.52 Ra^1/5 horizontal with Walton's (1983) stable floor, tilt by "
                  "Raithby & Hollands (1998); combined by Churchill (1977), n = 3",
        "validity": "smooth plates with a sharp leading edge in a uniform stream (wind tunnel "
                    "data), 0.6 <= Pr <= 60, Re_L <= 1e8; natural convection all Ra"},
    "flat_plate_turbulent": {
        "source": "forced: flat plate tripped at the leading edge, 0.037 Re^0.8 Pr^1/3 "
                  "(Incropera et al., 6th ed., eq. 7.41); natural and blending as "
                  "flat_plate_mixed. Large-plate evidence: measured on the flat roofs of two "
                  "commercial buildings, the turbulent flat-plate forced term plus natural "
                  "convection explained about 90 % of the variance (Clear, Gartland & "
                  "Winkelmann 2003, Energy Build. 35, 797-811)",
        "validity": "0.6 <= Pr <= 60, 5e5 <= Re_L <= 1e8 (real large plates: edges, fittings, "
                    "a gusty wind disturb the leading edge); roofs tens of metres across "
                    "(Clear et al. 2003); smooth surfaces (no roughness multiplier)"},
    "doe2": {
        "source": "DOE-2.1E (LBL 1994) as in EnergyPlus (its default outside convection): "
                  "h = h_n + R_f ((h_n^2 + (a V^b)^2)^1/2 - h_n), MoWiTT forced a V^b "
                  "(Yazdanian & Klems 1994: windward 3.26 V^0.89, leeward 3.55 V^0.617), "
                  "Walton's (1983) natural h_n, roughness multiplier R_f (Walton 1981)",
        "validity": "low-rise building surfaces; MoWiTT measured on window glass of a "
                    "full-scale outdoor test facility; no size dependence"},
    "tarp": {
        "source": "TARP (Walton 1983, NBSIR 83-2655) as in EnergyPlus: h = 2.537 W_f R_f "
                  "(P V / A)^1/2 (Sparrow, Ramsey & Mass 1979; W_f 1 windward, 0.5 leeward) "
                  "+ Walton's natural h_n",
        "validity": "building facades and roofs; Sparrow et al. measured small plates in a "
                    "wind tunnel, extended by P/A of the whole facade"},
    "mowitt": {
        "source": "MoWiTT (Yazdanian & Klems 1994, ASHRAE Trans. 100(1)): h = ((0.84 "
                  "|dT|^1/3)^2 + (a V^b)^2)^1/2, windward 3.26 V^0.89, leeward 3.55 V^0.617",
        "validity": "very smooth vertical surfaces (window glass) of low-rise buildings"},
    "mcadams": {
        "source": "McAdams (1954) h = 5.7 + 3.8 V as cast in SI by Palyvos (2008, Appl. "
                  "Therm. Eng. 28, 801-808), a convective coefficient as in EnergyPlus's "
                  "adaptive algorithm",
        "validity": "a small vertical plate in a wind tunnel; the constant is read as natural "
                    "convection; some authors read the whole as convection plus radiation"},
    "iso6946": {
        "source": "ISO 6946:2017 Annex C, eq. C.2: h_ce = 4 + 4 v (v wind speed at the surface)",
        "validity": "building envelopes; the standard's design values use v = 4 m/s "
                    "(h_ce = 20 W m-2 K-1)"},
}
"""Exterior (air-side) convection models by name, with their source and validity; the
functions are :data:`shipthermal.environment.convection.CONVECTION_MODELS`. The names are
what a scenario may choose, for the whole ship or per part."""

DEFAULT_CONVECTION_MODEL = "flat_plate_turbulent"
"""Exterior convection model of the air faces when none is chosen: the flat plate with its
boundary layer turbulent from the leading edge, combined with natural convection (Churchill
1977). Chosen by the evidence on large plates outdoors (docs/CONVECTION.md): on the flat
roofs of two commercial buildings the turbulent flat-plate forced term with natural
convection explained about 90 % of the measured variance (Clear, Gartland & Winkelmann
2003); a deck's edges, bulwarks and fittings in a gusty wind trip its boundary layer as a
roof's parapets do, where the laminar start of ``flat_plate_mixed`` needs a sharp, smooth
leading edge in a uniform stream. No measurements on ship decks were found to choose by."""

ROUGHNESS_CLASSES = ("very_rough", "rough", "medium_rough", "medium_smooth", "smooth",
                     "very_smooth")
"""Walton's (1981) six surface roughness classes, roughest first (their multipliers:
:data:`shipthermal.environment.convection.ROUGHNESS_MULTIPLIERS`)."""

CONVECTION_ROUGHNESS = {"hull": "smooth", "deck": "medium_rough", "superstructure": "smooth"}
"""Roughness class per main part for the roughness multiplier R_f of DOE-2 and TARP
(:data:`shipthermal.environment.convection.ROUGHNESS_MULTIPLIERS`). ASSUMPTION by analogy
with Walton's example materials: painted steel plate is as smooth as smooth plaster
(``smooth``, R_f 1.11); a grit-filled epoxy non-skid deck covering is like a concrete
finish (``medium_rough``, 1.52). Unused by the flat-plate, MoWiTT, McAdams and ISO
models."""

CLEAR_SKY_MODEL_NAMES = ("brutsaert", "prata", "swinbank")
"""Clear-sky emissivity models by name; the functions (with their sources) are
:data:`shipthermal.environment.sky.CLEAR_SKY_MODELS`."""

CLOUD_MODEL_NAMES = ("unsworth_monteith", "crawford_duchon")
"""Cloud corrections of the sky emissivity by name; the functions (with their sources) are
:data:`shipthermal.environment.sky.CLOUD_MODELS`."""

SEA_SKIN_MODEL_NAMES = ("fairall_coare", "zeng_beljaars", "none")
"""Models of the sea's skin temperature by name, bulk SST + diurnal warm layer − cool skin of
Fairall et al. (1996b) with COARE 3.6 fluxes (:mod:`shipthermal.environment.sea_skin`), the
warm layer either ``fairall_coare`` (Fairall et al. 1996b, as the COARE 3.x code runs it) or
``zeng_beljaars`` (Zeng & Beljaars 2005, the ECMWF model's skin scheme); or ``none`` (the skin
is the bulk SST)."""

DEFAULT_SEA_SKIN_MODEL = "fairall_coare"
"""Sea skin model when none is chosen: the COARE warm layer, whose daily warming stays within
what is observed at moderate winds (Z&B's is 4–9 times larger at 3–5 m/s; the reasons with
the numbers: :mod:`shipthermal.environment.sea_skin`)."""

DECOMPOSITIONS = ("erbs", "dirint")
"""Splits of global horizontal irradiance into direct and diffuse that
:class:`shipthermal.environment.Environment` accepts (pvlib's ``erbs`` and ``dirint``)."""

# ---------------------------------------------------------------------------------------
# Weather input
# ---------------------------------------------------------------------------------------
STATION_FORMATS = ("csv", "epw", "tmy2", "tmy3", "ndbc")
"""Weather file formats :func:`shipthermal.environment.station.read_station` reads."""

STATION_SUFFIXES = {".csv": "csv", ".epw": "epw", ".tm2": "tmy2", ".txt": "ndbc"}
"""Weather format by file name ending (lower case). TMY3 files end in .csv too: their format
must be named."""

MAX_GAP_HOURS = 6.0
"""Default longest time between two valid observations that is bridged by linear
interpolation [h]. A quarter of the diurnal cycle: linear interpolation of a daily
sinusoid across 6 h misses at most 1 − cos(π/4) ≈ 29 % of its amplitude at the gap's
centre (1.7 % across 1 h); longer gaps would invent a day's weather."""

TEMP_UNITS = ("C", "K", "F")
"""Temperature units of a weather CSV (degrees Celsius, kelvin or degrees Fahrenheit)."""

AIR_SEA_DIFFERENCE_K = (-30.0, 15.0)
"""Refused daily-mean air minus sea surface temperature [K] beyond these bounds.
ASSUMPTION from the marine boundary layer's extremes: in cold-air outbreaks off sea ice the
air is 20-30 K colder than the open water (Brümmer 1996, Boundary-Layer Meteorol. 80,
109-125: up to about 30 K); warm air over cold water (advection fog) is a few kelvin warmer,
rarely 10 K. A day outside is a unit mistake (degF read as degC: +40 K over a 10 degC sea),
a wrong column or a station far inland."""

AIR_SEA_WARN_K = (-20.0, 10.0)
"""Daily-mean air minus sea temperature [K] beyond which a run is warned (a real but rare
day: check the record)."""

HUMIDITY_FRACTION_MAX = 1.5
"""A span whose largest relative humidity is at most this [%] is refused as a fraction
written instead of percent (0.86 for 86 %). ASSUMPTION: the marine air's relative
humidity does not stay below 1.5 % for a day (the driest offshore desert winds keep
10-20 %)."""

WIND_SPEED_WARN = 25.0
"""Daily-mean wind speed [m s-1] above which a run is warned (storm force 10: km/h or knots
read as m/s?)."""

MAX_SITE_DISTANCE_KM = 150.0
"""Default largest distance between a typical-year file's station (its header) and
``[location]`` [km]: about the spacing of the typical-year stations along a coast, so the
nearest one is accepted and a file of another city is not."""

CLOUD_COVER_SCALE = {"fraction": 1.0, "percent": 100.0, "tenths": 10.0, "oktas": 8.0}
"""Cloud cover units of a weather CSV, each with the value that means overcast."""

# ---------------------------------------------------------------------------------------
# Built-in climatology
# ---------------------------------------------------------------------------------------
SEASONS = ("summer", "winter")
"""Seasons of the built-in design days, the atmosphere (mid-latitude summer and winter) and
the synthetic port."""

DALIAN = dict(name="Dalian", latitude=38.91, longitude=121.63, altitude=92.0,
              tz="Etc/GMT-8")
"""Dalian station 54662 (38°54' N, 121°38' E, 92 m; UTC+8), the site of the built-in
design days (:mod:`shipthermal.environment.climatology`). The ship floats at sea level:
altitude is used only for the clear-sky air mass (negligible effect)."""

DESIGN_DAY_DATES = {"summer": "2023-07-15", "winter": "2023-01-15"}
"""Dates of the built-in design days at :data:`DALIAN`: mid-July and mid-January, the
months of the climate normals they are built from."""


def season_of_date(month: int, latitude: float) -> str:
    """The half of the year a month falls in at a latitude: ``"summer"`` for April to
    September in the northern hemisphere and October to March in the southern, else
    ``"winter"``. It picks the season defaults (compartment air, map and image times) of a
    scenario whose weather comes from a file; the physics follows the weather itself."""
    warm_north = 4 <= int(month) <= 9
    return "summer" if warm_north == (float(latitude) >= 0.0) else "winter"

# ---------------------------------------------------------------------------------------
# Time stepping of a diurnal run
# ---------------------------------------------------------------------------------------
DAY_STEP = 300.0
"""Time step of a diurnal run [s] (``solver.time_step``; the night's is
:data:`NIGHT_STEP`). Measured on the built-in frigate at 2 m over three June days of San
Francisco (TMY3), every face at every half-hourly output against steps of 100 s (solver
time 17.7 s; BDF2, Newton's rule then at 1e-6 K):

=========  ==============  =============  ===========  =================
day step   max |ΔT| [K]    99th pct [K]   RMS [K]      solver time [s]
=========  ==============  =============  ===========  =================
300 s      0.18            0.043          0.008        7.0
600 s      0.63            0.16           0.031        5.0
900 s      2.3             0.59           0.12         3.1
=========  ==============  =============  ===========  =================

The step's error is spread over the whole daylight, largest around noon (each half hour's
largest face error at 300 s: 0.01–0.07 K in the morning and evening, 0.1–0.22 K at midday;
the same June days, against 100 s steps). A step chosen by an error estimate therefore
gains little: even told in advance which half hours kept their error below 0.05 K at 300 s
(and given 600 s steps there: 47 of the 97 half hours of day steps), the 3 recorded days
took 535 steps instead of 676 (21 % fewer) for the same largest error (0.22 K) and twice the
RMS (0.017 K). Crank–Nicolson (``scheme``) at 300 s halves BDF2's error (0.098 K) but took
1.7× its time (its periodic spin-up needed more days: 1600 steps in all against 925); at 600
s it reached 0.49 K.
"""

OUTPUT_INTERVAL = 1800.0
"""Interval of the thermal outputs [s] (``time.output_interval``): half-hourly, twice the
resolution of hourly weather records."""

SPINUP_TOLERANCE = 0.01
"""A periodic day is spun up when no cell temperature changes more than this over a day,
end against start [K] (``solver.spinup_tolerance``): a tenth of the 0.1 K NETD of the
thermal sensors the product models."""

SPINUP_MAX_DAYS = 10
"""Most days of a periodic day's spin-up (``solver.spinup_max_days``); the frigate's days
repeat within :data:`SPINUP_TOLERANCE` after 2–3 (the plates' time constants are tens of
minutes; the lead-in starts them near the day's mean air)."""

SUN_SAMPLES_PER_FACE = 16
"""Sample points per face of the sun-lit fraction (``solver.samples_per_face``), stratified
over the triangle and the same for every sun direction: a face crossed by a shadow edge is
resolved to about 1/16 of its area."""

VIEW_RAYS_PER_FACE = 256
"""Hemisphere rays per face of the view factors (``solver.rays_per_face``): a face's sky,
sea and ship fractions to a standard error of at most 0.5/16 = 0.031 (binomial), reciprocity
then imposed over the whole ship."""

NIGHT_STEP = 900.0
"""Time step of the night [s] (:func:`shipthermal.diurnal.night_steps`): where no face has
absorbed short-wave for :data:`NIGHT_SETTLE` (sunset's fast cooling over), the plates follow
slowly varying air, sky and wind, and BDF2 takes steps of this length (reached from the
day's step through doubling steps, back to it before the first short-wave of the morning).
A 900 s step costs ~1.3 of a 300 s one (27.6 vs 20.5 PCG iterations, 4.0 vs 4.1 Newton
passes). Measured on the built-in frigate at 0.5 m, 300 s day steps, 1800 s recording, every
face at every recording time against uniform 300 s steps (steps: lead-in + day):

==============  ======  =====  ==============================
night, settle   season  steps  max |ΔT| faces / part means [K]
==============  ======  =====  ==============================
900 s, 0.5 h    summer  245    0.017 / 0.0067
900 s, 0.5 h    winter  205    0.051 / 0.016
900 s, 1 h      winter  209    0.020 / 0.0078
600 s, 1 h      winter  234    0.012 / 0.0048
900 s, 1.5 h    summer  253    0.0036 / 0.0018
900 s, 1.5 h    winter  213    0.0089 / 0.0040
uniform 300 s   both    312    —
==============  ======  =====  ==============================
"""

NEWTON_TOLERANCE = 1e-3
"""Newton's stopping rule in a diurnal run: the estimated correction left [K] (with
:data:`NEWTON_ENERGY_TOLERANCE` and :data:`NEWTON_SURFACE_TOLERANCE`); a tenth of the
spin-up's periodicity tolerance, a 50th of the time step's own error. The solver's own
rule (1e-9 K, 1e-12, 1e-11: round-off, kept for the verification cases) took a step three
to four Newton passes, two to three linear solves; its corrections run ~1e-2, 2e-5, 1e-8 K
(the chord Jacobian and the lagged face-to-face exchange converge linearly), and the
second solve and the check after it bought changes far below what the step's length
already costs (:data:`DAY_STEP`). Measured against the solver's own rule, every face at
every output:

=====================================  ============  ==========  =======  =============
run                                    max |ΔT| [K]  99.9 % [K]  RMS [K]  solves a step
=====================================  ============  ==========  =======  =============
frigate 0.5 m, built-in summer day     0.0042        4.1e-4      3.5e-5   3.17 → 1.18
frigate 2 m, 3 June days of SF (TMY3)  0.012         1.1e-3      1.1e-4   3.32 → 1.11
=====================================  ============  ==========  =======  =============

(Newton passes a step 4.17 → 2.18 and 4.32 → 2.11; the day step itself costs 0.18 K at
most, 0.008 K RMS on the 2 m days.) Loosening one of the three rules alone bought little:
with 1e-3 K and the energy at 1e-8 the 0.5 m day took 2.3 solves a step, with 1e-4 K, 1e-5
and 1e-6 1.87."""

NEWTON_ENERGY_TOLERANCE = 1e-5
"""Newton's stopping rule in a diurnal run: the step's energy residual
``Δt |Σ_i R_i|`` relative to its gross boundary heat [-] (see :data:`NEWTON_TOLERANCE`);
it bounds the energy log's imbalance of every step, and so of the whole run."""

NEWTON_SURFACE_TOLERANCE = 1e-5
"""Newton's stopping rule in a diurnal run: the surface temperatures' fixed point (each
face's balance with the face-to-face exchange received at the last pass's temperatures)
counts as converged when its last sweep changed no face by more than this fraction of the
largest surface temperature [-] (3 mK at 300 K; see :data:`NEWTON_TOLERANCE`)."""

RECORD_SEGMENT_WARM_DAYS = 2
"""Days a segment of a weather record split over processes (``solver.jobs``) runs before
its first recorded day [d]: spun up on the record's day this many days earlier (repeated),
then the record as it is to the segment's first day, where the segment before it ends.
The plates forget where they started within hours (steel with 20–30 W m-2 K-1 at its
surface: time constants of ~20 min). Measured against the record run in one piece, every
face at every output: the frigate at 2 m over 28 days of San Francisco in two segments
within 6.4e-3 K (the two runs take different paths to Newton's rule,
:data:`NEWTON_TOLERANCE`; with the rule at 1e-6 K: within 1.3e-6 K, and over 8 days equal
in float32); the patrol boat over 5 days of buoy 44009 in 1800 s steps in three segments
equal to the last bit (0 K)."""

NIGHT_SETTLE = 5400.0
"""Darkness before the night step [s] (see :data:`NIGHT_STEP`): the first 1.5 h after the
last short-wave, where the plates cool fastest, keep the day's step."""


# ---------------------------------------------------------------------------------------
# Ranges accepted at the interfaces
# ---------------------------------------------------------------------------------------
LATITUDE_MAX = 66.0
"""Largest site latitude accepted, north or south [deg]: inside the polar circles
(66.56°), whose polar day and night the daily cycle of the forcing does not support."""

SHIP_SPEED_MAX = 30.0
"""Largest ship speed over ground accepted [m s-1] (58 kn, beyond fast naval craft)."""

WIND_SPEED_MAX = 40.0
"""Largest wind speed accepted [m s-1]: above hurricane force (Beaufort 12 starts at 32.7
m/s, WMO-No. 8); the sea-surface fits (Cox & Munk 1954: 1–14 m/s) are extrapolated well
before that."""


def check_wind_speed(field: str, value) -> None:
    """Raise :class:`InputError` unless every ``value`` is in [0, :data:`WIND_SPEED_MAX`]
    m/s."""
    check_range(field, value, 0.0, WIND_SPEED_MAX, "m/s")
