"""The constants of the sea's skin: water and air, COARE's bulk algorithm, the two warm layers.

Each carries one of the labels of the code base: SOURCED (copied from the cited source),
DERIVED (computed from sourced numbers by a stated method), ASSUMPTION (our choice).
References in brackets: :mod:`shipthermal.environment.sea_skin`.
"""

from __future__ import annotations

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
the depth of the bulk SST an ASSUMPTION, for the COARE warm layer too: see
:mod:`shipthermal.environment.sea_skin`)."""
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
