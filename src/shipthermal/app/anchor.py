"""An independent physics anchor: the ASHRAE sol-air temperature of a sunlit dark surface.

The sol-air temperature (ASHRAE Handbook — Fundamentals, chapter "Nonresidential cooling
and heating load calculations", 1997/2001 editions) is the air temperature that, without
radiation, would drive the same heat into a surface as the actual sun, sky and air::

    t_e = t_o + α I_t / h_o − ε ΔR / h_o

with the handbook's constants: ``h_o`` = 17 W m⁻² K⁻¹ (3.0 Btu h⁻¹ ft⁻² °F⁻¹, about
3.4 m/s of wind); ``α / h_o`` = 0.30 h ft² °F Btu⁻¹ for a dark surface, i.e. α = 0.90;
``ε ΔR / h_o`` = 7 °F = 3.9 K for a horizontal surface (long-wave loss to the sky) and 0
for a vertical one. It is the steady temperature of a surface that loses no heat inwards,
an upper bound for a plate whose back faces a cooler compartment.

:func:`sol_air_anchor` runs the summer design day under a clear sky with dark (α = 0.90)
deck and hull through the full model (ray-traced sun, sky and sea exchange, convection,
conduction through the plates) and compares, at the moments of strongest sun, the mean
outer temperature of fully sunlit horizontal deck triangles (12:00) and of fully sunlit
east-facing hull triangles (09:00) with ``t_e`` computed from the same air temperature and
the irradiance on the same plane (pvlib, isotropic sky, sea albedo from the model's
reflected short-wave). The difference, in K, says how far the model's surface balance is
from the handbook's lumped one; nothing is fitted.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pvlib

from ..environment import to_ship_frame
from ..environment.climatology import climate_day
from ..geometry import main_part
from .calibration.model import CALIBRATION_SETTINGS
from .scenario import default_scenario
from .thermal import run_scenario_thermal

__all__ = ["ASHRAE_H_O", "ASHRAE_ALPHA_DARK", "ASHRAE_LW_HORIZONTAL_K", "sol_air",
           "sol_air_anchor"]

#: ASHRAE outer surface coefficient h_o = 3.0 Btu/(h ft² °F) [W m-2 K-1]
ASHRAE_H_O = 3.0 * 5.678263
#: ASHRAE dark surface: α/h_o = 0.30 (h ft² °F/Btu) → α = 0.30 · 3.0 [-]
ASHRAE_ALPHA_DARK = 0.30 * 3.0
#: ASHRAE long-wave term ε ΔR / h_o for a horizontal surface: 7 °F [K]
ASHRAE_LW_HORIZONTAL_K = 7.0 * 5.0 / 9.0


#: Inside surface film coefficient of a plate facing still compartment air, natural
#: convection plus radiation [W m-2 K-1] (ASSUMPTION: the usual 2.5–8 span of building
#: inside-surface coefficients, heat flow down to up)
INSIDE_FILM_RANGE = (2.5, 8.0)


def sol_air(temp_air, irradiance, alpha=ASHRAE_ALPHA_DARK, h_o=ASHRAE_H_O,
            horizontal: bool = True):
    """ASHRAE sol-air temperature [K] from air temperature [K] and the irradiance on the
    surface's plane [W m-2]."""
    return (np.asarray(temp_air, float) + alpha * np.asarray(irradiance, float) / h_o
            - (ASHRAE_LW_HORIZONTAL_K if horizontal else 0.0))


def sol_air_anchor(settings: dict | None = None, season: str = "summer") -> pd.DataFrame:
    """Model vs ASHRAE sol-air for a sunlit dark horizontal deck (12:00) and an east-facing
    wall (09:00) on the clear-sky design day; one row per surface."""
    c0 = climate_day(season).cloud_cover
    changes = dict(CALIBRATION_SETTINGS if settings is None else settings)
    changes.update({"weather.cloud_cover_offset": -c0,
                    "ship.solar_absorptivity.deck": ASHRAE_ALPHA_DARK,
                    "ship.solar_absorptivity.hull": ASHRAE_ALPHA_DARK,
                    "ship.solar_absorptivity.superstructure": ASHRAE_ALPHA_DARK})
    sc = default_scenario(season).updated(changes)
    ship = sc.ship()
    res = run_scenario_thermal(sc, ship=ship, progress=False)
    traced = res.forcing.traced
    normals = ship.face_normals
    mains = np.array([main_part(ship.part_names[k]) for k in ship.face_part])
    rows = []
    for surface, hour, want, horizontal in (("horizontal deck", 12.0, (0.0, 0.0, 1.0), True),
                                            ("east-facing hull (vertical)", 9.0,
                                             (1.0, 0.0, 0.0), False)):
        t = hour * 3600.0
        lit = np.zeros(ship.n_faces)
        lit[np.asarray(traced.receivers)] = res.forcing.lit_fraction(t)
        parts = ("deck",) if horizontal else ("hull_dry", "hull", "superstructure")
        facing = to_ship_frame(np.array(want), sc.ship.heading)     # East-North-Up → ship
        sel = (np.isin(mains, parts) & (normals @ facing > (0.98 if horizontal else 0.9))
               & (lit > 0.99))
        env = res.environment.at(np.array([t]))
        albedo = float(env.sea_shortwave_up[0] / env.ghi[0]) if env.ghi[0] > 0 else 0.06
        poa = pvlib.irradiance.get_total_irradiance(
            0.0 if horizontal else 90.0, 90.0, env.zenith, env.azimuth, env.dni, env.ghi,
            env.dhi, albedo=albedo, model="isotropic")["poa_global"]
        te = float(sol_air(env.temp_air, np.asarray(poa), horizontal=horizontal)[0])
        model = float(np.mean(res.face_temperature_at(hour)[sel])) if sel.any() else np.nan
        # a plate whose back loses heat to the compartment through an inside film h_i
        # settles at (h_o t_e + h_i t_c) / (h_o + h_i) (steel: no conduction resistance
        # to speak of): below t_e by h_i (t_e − t_c) / (h_o + h_i)
        tc = float(sc.ship.compartment_temperature_of(str(mains[sel][0]) if sel.any() else parts[0]))
        drop = [h_i * (te - tc) / (ASHRAE_H_O + h_i) for h_i in INSIDE_FILM_RANGE]
        rows.append({"surface": surface, "time": f"{int(hour):02d}:00", "faces": int(sel.sum()),
                     "air_K": float(env.temp_air[0]), "irradiance_W_m2": float(np.asarray(poa)[0]),
                     "wind_m_s": float(env.wind_speed[0]), "sol_air_K": te, "model_K": model,
                     "model_minus_sol_air_K": model - te, "compartment_K": tc,
                     "expected_low_K": -drop[1], "expected_high_K": -drop[0]})
    return pd.DataFrame(rows)
