"""Render the ship onto the port background as the orbiting sensor sees it (paper §3.1, eqs. 1-2, 19).

Projection
----------
The sensor is 795 km up. With the ray direction of a parallel projection taken as the line
of sight *at the ship's centre*, every point of a ship up to 150 m long (<= 75 m from the
centre) lies within ``75 m / 795 km = 9.4e-5 rad`` (< 1e-4 rad) of its true line of sight;
a point 25 m above the water is displaced by <= 25 m x 9.4e-5 = 2.4 mm, ~800 times below the
1.9 m sample spacing at 16 x 16 samples per 30 m pixel. The parallel projection is therefore
exact for the ship. It is *not* exact to 1e-4 rad across a whole 10 km scene: there the
line of sight turns by up to ``5 km / 795 km = 6.3e-3 rad`` (0.36 deg) from the centre; the
flat background only needs the view angles for its BRDFs and directional emissivity, and
the one view geometry of the ship is used for every pixel (near nadir the Fresnel
emissivity of water changes by < 1e-4 over 0.36 deg). The image lives on the background's
ground grid (an orthorectified product): pixel ``(row, col)`` is the 30 m ground cell of the
background (the paper's sensor has a 30.0 m nadir GSD,
:func:`imaging.sensor.ground_sample_distance`).

Sampling
--------
Each pixel that the ship's projection (along the view) or its shadow (along the sun) can
touch gets ``s x s`` samples on its ground footprint (regular grid at the sub-cell centres,
or stratified jitter). A sample's view ray runs from the sensor side toward the ground
point; the first ship triangle it meets above the water is what the sensor sees there,
otherwise the ground point itself. Each pixel is the area-weighted mix of what its samples
see (the detector integrates flux: radiances mix linearly by area, paper §3.1). Pixels the
ship cannot touch get no samples (sparse sampling); which pixels can be touched is decided
conservatively from the union of the projected triangles' bounding boxes.

Shadows: a ground sample whose ray toward the sun hits the ship loses the reflected-sun
term; a ship sample whose ray toward the sun hits the ship (self-shadowing) too.

Radiance (paper eq. 2 and eq. 1)
--------------------------------
Ship face: ``eps B(T_f) + (1 - eps)[F_sky L_sky + (1 - F_sky) L_sea] + E_sun max(n.s, 0)
f_CT`` with ``F_sky = (1 + n_z)/2`` and ``L_sea = eps_h B(T_sea) + (1 - eps_h) L_sky``
(``eps_h`` the rough sea's hemispherical emissivity); background pixel: ``eps_c B(T) +
rho_c L_sky + E_sun cos(theta_s) f_c`` (water: the rough-sea directional emissivity at
the view angle, its Cox-Munk glint and the sky from the specular direction). At the
aperture each term is attenuated with the transmittance weighted by its own spectrum
(emitted: Planck-weighted at the source temperature; reflected sun: sun-weighted; reflected
sky: sky-weighted, :class:`BandConditions`), plus the path radiance.

Neglected (second order here, stated): sky blocked by the ship for the water next to it and
the ship's own emission reflected by the water; ship self-view in the sky term; thermal
shadow (cooling) of the ground under the ship's shadow; multiple reflections.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from shipthermal.errors import InputError, check_finite, check_positive, check_range, require
from shipthermal.optics.planck import band_radiance_dt, band_radiance_table, standard_band
from shipthermal.optics.responses import thermal_band_key
from shipthermal.optics.sea import rough_sea_emissivity_hemispherical
from shipthermal.parameters import check_wind_speed

from .band_conditions import (BandConditions, atmosphere_state, conditions_from_atmosphere,
                              emitted_transmittance_table)
from .radiometry import SHIP_EMISSIVITY
from .scene import (GriddedBackground, ShipPaint, ShipPlacement, as_scene_background,
                    background_optics, default_mooring, enu_direction)
from .sensor import (PAPER_SENSOR, SensorSpec, add_netd_noise, apply_psf, dequantise,
                     focal_plane_irradiance, quantise)
from .thermal_history import emissivity_key

__all__ = ["BandConditions", "conditions_from_atmosphere", "emitted_transmittance_table",
           "SensorOptions", "Frame", "SunGeometry", "SceneRenderer", "atmosphere_state"]


# ---------------------------------------------------------------------------------------
# Sensor options and the frame
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SensorOptions:
    """Optional detector effects applied to the at-aperture radiance image.

    Attributes
    ----------
    psf : bool
        Blur with the diffraction PSF at the band's mean wavelength
        (:func:`imaging.sensor.apply_psf`, pixel-sampled approximation).
    netd_k : float or None
        Add white noise of this NETD [K] (responsivity: ``tau dB/dT`` at 300 K).
    bits : int or None
        Quantise to this many bits over ``radiance_range``.
    radiance_range : tuple or None
        ``(min, max)`` at-aperture radiance mapped to DN 0 and 2^bits - 1 [W m-2 sr-1].
    seed : int
        Noise seed.
    """

    psf: bool = False
    netd_k: float | None = None
    bits: int | None = None
    radiance_range: tuple | None = None
    seed: int = 0

    def __post_init__(self):
        if self.netd_k is not None:
            check_positive("sensor_options.netd_k", self.netd_k, "K")
        if self.bits is not None:
            require(self.radiance_range is not None, "sensor_options.radiance_range", None,
                    "must be given with bits", "e.g. radiance_range=(1.0, 12.0) [W m-2 sr-1]")

    @property
    def mixes_pixels(self) -> bool:
        """Whether a pixel's result depends on other pixels (PSF blur, NETD noise drawn over
        the image); quantisation does not."""
        return self.psf or self.netd_k is not None


@dataclass(frozen=True, eq=False)
class Frame:
    """One rendered image (arrays on the background grid, row 0 = north).

    Attributes
    ----------
    time_s : float
        [s after local midnight].
    band : str
    radiance : (ny, nx) float32
        At-aperture radiance [W m-2 sr-1] (eq. 1; after PSF/noise when requested).
    leaving : (ny, nx) float32
        Surface-leaving radiance ``L_t + L_b`` per pixel, area-mixed [W m-2 sr-1] (eq. 2).
    irradiance : (ny, nx) float32
        Focal-plane irradiance [W m-2] (camera equation on ``radiance``).
    coverage : (ny, nx) float32
        Fraction of each pixel's area where the sensor sees the ship [-].
    shadow : (ny, nx) float32
        Fraction of each pixel's area that is visible ground in the ship's sun shadow [-].
    dn : (ny, nx) uint or None
        Digital numbers when quantised.
    sun_zenith_deg, sun_azimuth_deg : float
    rays : dict
        Rays traced for this frame's sun geometry (``shadow``) and for the view (``view``).
    """

    time_s: float
    band: str
    radiance: np.ndarray
    leaving: np.ndarray
    irradiance: np.ndarray
    coverage: np.ndarray
    shadow: np.ndarray
    dn: np.ndarray | None
    sun_zenith_deg: float
    sun_azimuth_deg: float
    rays: dict = field(default_factory=dict)

    @property
    def target_mask(self) -> np.ndarray:
        """Pixels the ship covers at all (coverage > 0) [bool]."""
        return self.coverage > 0


@dataclass(frozen=True, eq=False)
class SunGeometry:
    """Sun visibility for one sun direction (shared by all bands of one moment).

    Attributes
    ----------
    sun_direction : (3,) float
        Toward the sun, ENU [-].
    ship_lit : (n_ship_samples,) bool
        Ship samples lit by the sun (facing it and not self-shadowed).
    shadow_pixels : (k,) int
        Flat indices of pixels with ship shadow on visible ground.
    shadow_fraction : (k,) float
        Their shadowed visible-ground area fraction [-].
    n_rays : int
        Rays traced (ship self-shadow + ground shadow).
    """

    sun_direction: np.ndarray
    ship_lit: np.ndarray
    shadow_pixels: np.ndarray
    shadow_fraction: np.ndarray
    n_rays: int


# ---------------------------------------------------------------------------------------
# Geometry helpers
# ---------------------------------------------------------------------------------------
def _project_to_ground(points, direction):
    """Points (..., 3) moved along ``-direction`` to z = 0 (parallel projection) -> (..., 2)."""
    d = np.asarray(direction, dtype=float)
    z = np.maximum(points[..., 2], 0.0)
    return points[..., :2] - (z / d[2])[..., None] * d[:2]


def _cover_mask(xy, faces, res, shape):
    """Pixels touched by the union of the triangles' bounding boxes (conservative) [bool].

    ``xy`` (N, 2) projected vertices in scene coordinates [m], ``faces`` (T, 3) triangles;
    ``res`` pixel size [m]; ``shape`` (ny, nx). A 2-D difference array marks every box in
    O(T + pixels).
    """
    ny, nx = shape
    a, b, c = xy[faces[:, 0]], xy[faces[:, 1]], xy[faces[:, 2]]
    lo = np.minimum(np.minimum(a, b), c)
    hi = np.maximum(np.maximum(a, b), c)
    c0 = np.floor(lo[:, 0] / res).astype(np.int64)
    c1 = np.floor(hi[:, 0] / res).astype(np.int64)
    r0 = ny - 1 - np.floor(hi[:, 1] / res).astype(np.int64)
    r1 = ny - 1 - np.floor(lo[:, 1] / res).astype(np.int64)
    keep = (c1 >= 0) & (c0 < nx) & (r1 >= 0) & (r0 < ny)
    if not keep.any():
        return np.zeros(shape, dtype=bool)
    c0, c1 = np.clip(c0[keep], 0, nx - 1), np.clip(c1[keep], 0, nx - 1)
    r0, r1 = np.clip(r0[keep], 0, ny - 1), np.clip(r1[keep], 0, ny - 1)
    # work inside the boxes' common window only (the ship is small in a big image)
    wr0, wr1, wc0, wc1 = r0.min(), r1.max() + 1, c0.min(), c1.max() + 1
    h, w = wr1 - wr0 + 1, wc1 - wc0 + 1
    r0, r1, c0, c1 = r0 - wr0, r1 + 1 - wr0, c0 - wc0, c1 + 1 - wc0
    idx = np.concatenate([r0 * w + c0, r0 * w + c1, r1 * w + c0, r1 * w + c1])
    wgt = np.concatenate([np.ones(len(r0)), -np.ones(len(r0)), -np.ones(len(r0)),
                          np.ones(len(r0))])
    diff = np.bincount(idx, wgt, minlength=h * w).reshape(h, w)
    count = diff.cumsum(axis=0).cumsum(axis=1)[:-1, :-1]
    mask = np.zeros(shape, dtype=bool)
    mask[wr0:wr1, wc0:wc1] = count > 0.5
    return mask


def _sample_offsets(s, n_pix, res, seed):
    """Sample positions inside a pixel (n_pix, s*s, 2) [m]: sub-cell centres or jittered."""
    i = np.arange(s * s)
    base = np.stack([(i % s), (i // s)], axis=-1).astype(float)
    if seed is None:
        off = np.broadcast_to(base + 0.5, (n_pix, s * s, 2))
    else:
        rng = np.random.default_rng(seed)
        off = base[None] + rng.random((n_pix, s * s, 2))
    return off * (res / s)


# ---------------------------------------------------------------------------------------
# The renderer
# ---------------------------------------------------------------------------------------
class SceneRenderer:
    """Ship + port background as seen by the sensor; geometry traced once, radiance per frame.

    Parameters
    ----------
    ship : ShipThermalHistory or ShipGeometry
        Anything with ``vertices`` (ship frame [m]), ``faces``, ``face_part``, ``part_names``.
    background : GriddedBackground or PortBackground
        Classes and temperatures on the image grid.
    placement : ShipPlacement or None
        Ship position and heading; default :func:`imaging.scene.default_mooring`.
    view_zenith_deg, view_azimuth_deg : float
        Sensor direction seen from the ship [deg] (compass azimuth).
    samples_per_pixel : int
        ``s``: ``s x s`` samples per pixel near the ship (>= 16 for the paper's mixing).
    backend : {"auto", "embree", "numba"}
        Ray tracer (:func:`shipthermal.raytrace.make_tracer`).
    wind_speed : float
        Wind speed for the sea's Cox-Munk slopes [m s-1] (required, keyword: the scene's
        weather, e.g. :attr:`imaging.experiment.ImagingScenario.wind_speed`).
    paint : ShipPaint
        Ship reflection parameters.
    ship_emissivity : dict or None
        Per band, either ``{"hull": e, "deck": e, "superstructure": e}`` replacing the
        paper's §5 values (:data:`imaging.radiometry.SHIP_EMISSIVITY`) for the main parts,
        or an array with one emissivity per face of ``ship`` (sub-parts with their own
        values, e.g. a funnel) [-].
    background_emissivity : dict or None
        ``{band: {class name: e}}`` overrides (see :func:`imaging.scene.background_optics`).
    sensor : SensorSpec
        Camera (focal-plane irradiance).
    min_sun_elevation_deg : float
        Below this sun elevation [deg] ground shadows are not traced (the reflected sun on
        level ground, ``E cos(theta_s) f``, is then negligible and the shadow would be
        kilometres long); ship faces keep their self-shadowing.
    jitter_seed : int or None
        None: samples at sub-cell centres (deterministic, exact area fractions for
        axis-aligned edges); an int: stratified jitter with this seed.
    """

    def __init__(self, ship, background, placement: ShipPlacement | None = None,
                 view_zenith_deg: float = 0.0, view_azimuth_deg: float = 0.0,
                 samples_per_pixel: int = 16, backend: str = "auto", *, wind_speed: float,
                 paint: ShipPaint | None = None, ship_emissivity: dict | None = None,
                 background_emissivity: dict | None = None, sensor: SensorSpec = PAPER_SENSOR,
                 min_sun_elevation_deg: float = 1.0, jitter_seed: int | None = None):
        # deferred: the ray tracers load numba (0.7 s over this module's imports, measured);
        # importing the renderer's types (SensorOptions, Frame) does not need them
        from shipthermal.raytrace import make_tracer

        self.background: GriddedBackground = as_scene_background(background)
        self.placement = placement if placement is not None else default_mooring(self.background)
        check_range("view_zenith_deg", view_zenith_deg, 0.0, 80.0, "deg")
        check_finite("view_azimuth_deg", view_azimuth_deg)
        s = int(samples_per_pixel)
        require(s >= 1 and s == samples_per_pixel, "samples_per_pixel", samples_per_pixel,
                "must be a positive integer (16 or more for the paper's sub-pixel mixing)")
        check_wind_speed("wind_speed", wind_speed)
        check_range("min_sun_elevation_deg", min_sun_elevation_deg, 0.0, 90.0, "deg")
        self.view_zenith_deg = float(view_zenith_deg)
        self.view_azimuth_deg = float(view_azimuth_deg)
        self.view_direction = enu_direction(view_zenith_deg, view_azimuth_deg)
        self.samples_per_pixel = s
        self.wind_speed = float(wind_speed)
        self.paint = paint or ShipPaint()
        self.sensor = sensor
        self.min_sun_elevation_deg = float(min_sun_elevation_deg)
        self.jitter_seed = jitter_seed
        self._ship_eps_override = dict(ship_emissivity or {})
        self._bg_eps_override = dict(background_emissivity or {})
        self._optics = {}
        self._planck = {}

        faces = np.asarray(ship.faces, dtype=np.int64)
        verts = self.placement.to_scene(np.asarray(ship.vertices, dtype=float))
        self.vertices = verts
        self.faces = faces
        keys = np.array([emissivity_key(p) for p in ship.part_names])
        self.face_key = keys[np.asarray(ship.face_part)]
        self._key_names, self._key_index = np.unique(self.face_key, return_inverse=True)
        self._ship_eps = {}
        tri = verts[faces]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        self.face_normals = n / np.linalg.norm(n, axis=1, keepdims=True)
        self.tracer = make_tracer(verts, faces, backend=backend)
        self.backend = type(self.tracer).__name__
        self.z_top = float(verts[:, 2].max())
        require(self.z_top > 0.0, "ship.vertices", self.z_top,
                "the ship must rise above the waterline z = 0")
        # only triangles with a part above the water can be seen or cast a shadow on it
        self._faces_above = faces[tri[:, :, 2].max(axis=1) > 0.0]
        self._trace_view()

    # ---- geometry -------------------------------------------------------------------------
    @property
    def shape(self) -> tuple:
        return self.background.shape

    @property
    def resolution_m(self) -> float:
        return self.background.resolution_m

    def _pixel_samples(self, pixels, seed_shift=0):
        """Ground sample points (n_pix * s*s, 2) [m] of flat pixel indices."""
        ny, nx = self.shape
        res = self.resolution_m
        rows, cols = np.divmod(pixels, nx)
        seed = None if self.jitter_seed is None else (self.jitter_seed, seed_shift)
        off = _sample_offsets(self.samples_per_pixel, len(pixels), res, seed)
        corner = np.stack([cols * res, (ny - 1 - rows) * res], axis=-1).astype(float)
        return (corner[:, None, :] + off).reshape(-1, 2)

    def _trace_view(self):
        v = self.view_direction
        cover = _cover_mask(_project_to_ground(self.vertices, v), self._faces_above,
                            self.resolution_m, self.shape)
        require(bool(cover.any()), "placement", self.placement,
                "puts the ship outside the image", "Give a position inside the scene [m]")
        pixels = np.flatnonzero(cover)
        pts = self._pixel_samples(pixels)
        # start above the ship's top, travel down along -v to the water plane z = 0
        dist = (self.z_top + 1.0) / v[2]
        origins = np.column_stack([pts, np.zeros(len(pts))]) + dist * v
        dirs = np.broadcast_to(-v, origins.shape)
        hit = self.tracer.intersects_first(origins, dirs, dist)
        ss = self.samples_per_pixel ** 2
        sample_pixel = np.repeat(pixels, ss)
        is_ship = hit >= 0
        f = hit[is_ship]
        nrm = self.face_normals[f]
        o = origins[is_ship]
        v0 = self.vertices[self.faces[f, 0]]
        denom = -(nrm @ v)
        # hit distance from the triangle's plane; grazing hits fall back to the centroid
        t_hit = np.where(np.abs(denom) > 1e-9,
                         np.sum(nrm * (v0 - o), axis=1) / np.where(np.abs(denom) > 1e-9,
                                                                     denom, 1.0), np.nan)
        points = o - t_hit[:, None] * v
        bad = ~np.isfinite(t_hit)
        points[bad] = self.vertices[self.faces[f[bad]]].mean(axis=1)
        sign = np.where(nrm @ v >= 0.0, 1.0, -1.0)
        self.view_pixels = pixels
        self.ship_pixel = sample_pixel[is_ship]
        self.ship_face = f
        self.ship_points = points
        self.ship_normals = nrm * sign[:, None]   # oriented toward the viewer
        self.ground_pixel_view = sample_pixel[~is_ship]
        self.ground_points_view = pts[~is_ship]
        cov = np.zeros(self.shape[0] * self.shape[1])
        np.add.at(cov, self.ship_pixel, 1.0)
        self.coverage = (cov / ss).reshape(self.shape)
        self.n_view_rays = int(len(origins))

    def sun_geometry(self, sun_direction) -> SunGeometry:
        """Trace ship self-shadowing and the ship's shadow on the ground for one sun.

        ``sun_direction``: unit vector toward the sun (ENU) [-].
        """
        s = np.asarray(sun_direction, dtype=float)
        s = s / np.linalg.norm(s)
        n_rays = 0
        empty = np.zeros(0, np.int64)
        if s[2] <= 0.0:
            return SunGeometry(s, np.zeros(len(self.ship_face), bool), empty, np.zeros(0), 0)
        off = self.tracer.offset
        facing = self.ship_normals @ s > 0.0
        lit = np.zeros(len(self.ship_face), bool)
        if facing.any():
            o = self.ship_points[facing] + off * self.ship_normals[facing]
            lit[facing] = ~self.tracer.any_hit(o, np.broadcast_to(s, o.shape))
            n_rays += int(facing.sum())
        if math.degrees(math.asin(min(s[2], 1.0))) < self.min_sun_elevation_deg:
            return SunGeometry(s, lit, empty, np.zeros(0), n_rays)
        cover = _cover_mask(_project_to_ground(self.vertices, s), self._faces_above,
                            self.resolution_m, self.shape)
        cover_flat = cover.ravel()
        # ground samples: the view pixels' misses inside the shadow cover + every sample of
        # shadow-cover pixels the ship cannot be seen in
        in_cover = cover_flat[self.ground_pixel_view]
        extra = np.setdiff1d(np.flatnonzero(cover_flat), self.view_pixels, assume_unique=True)
        pts = np.concatenate([self.ground_points_view[in_cover], self._pixel_samples(extra, 1)])
        pix = np.concatenate([self.ground_pixel_view[in_cover],
                              np.repeat(extra, self.samples_per_pixel ** 2)])
        if len(pts) == 0:
            return SunGeometry(s, lit, empty, np.zeros(0), n_rays)
        origins = np.column_stack([pts, np.full(len(pts), off)])
        blocked = self.tracer.any_hit(origins, np.broadcast_to(s, origins.shape))
        n_rays += int(len(pts))
        shadow_pix, counts = np.unique(pix[blocked], return_counts=True)
        return SunGeometry(s, lit, shadow_pix, counts / self.samples_per_pixel ** 2, n_rays)

    # ---- optics -----------------------------------------------------------------------------
    def background_optics(self, band: str):
        """Cached :class:`imaging.scene.BackgroundOptics` of ``band`` for this view."""
        if band not in self._optics:
            self._optics[band] = background_optics(
                band, self.view_zenith_deg, self.view_azimuth_deg, self.wind_speed,
                self._bg_eps_override.get(band))
        return self._optics[band]

    def _planck_table(self, band):
        if band not in self._planck:
            self._planck[band] = band_radiance_table(band, 150.0, 450.0, 0.5)
        return self._planck[band]

    def ship_emissivity(self, band: str) -> np.ndarray:
        """Emissivity of every ship face in ``band`` [-] (paper §5 unless overridden)."""
        if band in self._ship_eps:
            return self._ship_eps[band]
        if band not in self._ship_eps_override:
            try:
                thermal_band_key(band)
            except InputError:
                raise InputError("band", band, f"must be one of {sorted(SHIP_EMISSIVITY)} or a "
                                 "named sensor band (shipthermal.optics.responses)") from None
        given = self._ship_eps_override.get(band)
        if given is not None and not isinstance(given, Mapping):
            eps = np.array(given, dtype=float)
            require(eps.shape == (len(self.faces),), f"ship_emissivity[{band!r}]", eps.shape,
                    f"must hold one emissivity per ship face ({len(self.faces)})")
            check_range(f"ship_emissivity[{band!r}]", eps, 0.0, 1.0)
            eps.setflags(write=False)
            self._ship_eps[band] = eps
            return eps
        table = {**SHIP_EMISSIVITY.get(thermal_band_key(band), {}), **(given or {})}
        missing = sorted(set(self._key_names) - set(table))
        require(not missing, "ship_emissivity", sorted(table), f"needs values for {missing}")
        per_key = np.array([table[k] for k in self._key_names], dtype=float)
        check_range("ship_emissivity", per_key, 0.0, 1.0)
        eps = per_key[self._key_index]
        eps.setflags(write=False)
        self._ship_eps[band] = eps
        return eps

    # ---- radiance ---------------------------------------------------------------------------
    def render(self, conditions: BandConditions, face_temperature, background_temperature,
               temp_sea: float | None = None, sun: SunGeometry | None = None,
               sensor_options: SensorOptions | None = None, time_s: float = float("nan")
               ) -> Frame:
        """Render one frame.

        Parameters
        ----------
        conditions : BandConditions
            Band, sun, sky and atmosphere.
        face_temperature : (M,) array
            Ship face temperatures [K] (``ShipThermalHistory.at(t)``).
        background_temperature : (ny, nx) array
            Background surface temperature [K] (``background.temperature_at(hour)``).
        temp_sea : float or None
            Sea temperature the hull sides see [K]; default the mean water-pixel temperature.
        sun : SunGeometry or None
            Precomputed :meth:`sun_geometry` for this sun (computed if None).
        sensor_options : SensorOptions or None
            PSF / noise / quantisation.
        time_s : float
            Time stamp [s after local midnight] stored in the frame.

        Returns
        -------
        Frame
        """
        c = conditions
        band = c.band
        temp_f, temp_bg = self._checked_temperatures(face_temperature, background_temperature)
        if sun is None:
            sun = self.sun_geometry(c.sun_direction)
        planck = self._planck_table(band)
        temp_sea = self._sea_temperature(temp_bg, temp_sea)
        leave, ap, sun_bg = self._background_radiance(c, planck, temp_bg)
        smp_leave, smp_ap = self._ship_sample_radiance(c, sun, planck, temp_f, temp_sea)
        out_leave, out_ap, shadow = self._mix_pixels(c, sun, leave, ap, sun_bg, smp_leave,
                                                     smp_ap)
        radiance = out_ap.reshape(self.shape) + c.path_radiance
        radiance, dn = self._detector(c, radiance, sensor_options or SensorOptions())
        return Frame(
            time_s=float(time_s), band=band, radiance=radiance.astype(np.float32),
            leaving=out_leave.reshape(self.shape).astype(np.float32),
            irradiance=focal_plane_irradiance(radiance, self.sensor).astype(np.float32),
            coverage=self.coverage.astype(np.float32),
            shadow=shadow.reshape(self.shape).astype(np.float32), dn=dn,
            sun_zenith_deg=c.sun_zenith_deg, sun_azimuth_deg=c.sun_azimuth_deg,
            rays={"view": self.n_view_rays, "sun": sun.n_rays})

    def window_radiance(self, conditions: BandConditions, face_temperature,
                        background_temperature, window, temp_sea: float | None = None,
                        sun: SunGeometry | None = None,
                        sensor_options: SensorOptions | None = None) -> np.ndarray:
        """At-aperture radiance of the pixels ``window = (row0, row1, col0, col1)`` alone
        [W m-2 sr-1], float32: the values of :meth:`render`'s ``radiance[row0:row1,
        col0:col1]`` (every step of it is per pixel), for a series that needs only a window
        of each frame (the local SCR of a calendar's dense frames: the background's radiance
        over the whole image was a third of a frame's time). Arguments as :meth:`render`;
        the sensor options may quantise but not blur or add noise (both mix pixels: use
        :meth:`render`)."""
        c = conditions
        opts = sensor_options or SensorOptions()
        require(not opts.mixes_pixels, "sensor_options", opts,
                "a window of a frame has no PSF and no NETD noise (they mix pixels)",
                "render the whole frame (SceneRenderer.render)")
        r0, r1, c0, c1 = (int(v) for v in window)
        ny, nx = self.shape
        require(0 <= r0 < r1 <= ny and 0 <= c0 < c1 <= nx, "window", window,
                f"must be (row0, row1, col0, col1) inside the image {self.shape}")
        temp_f, temp_bg = self._checked_temperatures(face_temperature, background_temperature)
        if sun is None:
            sun = self.sun_geometry(c.sun_direction)
        planck = self._planck_table(c.band)
        temp_sea = self._sea_temperature(temp_bg, temp_sea)
        rows, cols = slice(r0, r1), slice(c0, c1)
        # the background outside the window is not computed (NaN: never read)
        full = [np.full(self.shape, np.nan) for _ in range(3)]
        for arr, part in zip(full, self._background_radiance(c, planck, temp_bg[rows, cols],
                                                             (rows, cols))):
            arr[rows, cols] = part
        smp_leave, smp_ap = self._ship_sample_radiance(c, sun, planck, temp_f, temp_sea)
        _, out_ap, _ = self._mix_pixels(c, sun, *full, smp_leave, smp_ap)
        radiance = out_ap.reshape(self.shape)[rows, cols] + c.path_radiance
        return self._detector(c, radiance, opts)[0].astype(np.float32)

    def _sea_temperature(self, temp_bg, temp_sea: float | None) -> float:
        """The sea temperature the hull sides see [K]: ``temp_sea``, or by default the mean
        of the background's water pixels (of all pixels without water)."""
        if temp_sea is not None:
            return temp_sea
        water = self.background.class_map == 1
        return float(temp_bg[water].mean()) if water.any() else float(temp_bg.mean())

    def _checked_temperatures(self, face_temperature, background_temperature) -> tuple:
        """Face and background temperatures as float arrays of the right shapes [K]."""
        temp_f = np.asarray(face_temperature, dtype=float)
        require(temp_f.shape == (len(self.faces),), "face_temperature", temp_f.shape,
                f"must hold one temperature per face ({len(self.faces)})")
        check_range("face_temperature", temp_f, 150.0, 450.0, "K")
        temp_bg = np.asarray(background_temperature, dtype=float)
        require(temp_bg.shape == self.shape, "background_temperature", temp_bg.shape,
                f"must be the image shape {self.shape}")
        check_range("background_temperature", temp_bg, 150.0, 450.0, "K")
        return temp_f, temp_bg

    def _background_radiance(self, c: BandConditions, planck, temp_bg, window=None) -> tuple:
        """Background pixels (eq. 2): surface-leaving and at-aperture radiance (ny, nx)
        [W m-2 sr-1], and the reflected sun's share of the leaving radiance (of the pixels
        ``window``, a pair of slices, alone when given: ``temp_bg`` is then the window's)."""
        optics = self.background_optics(c.band)
        cls = self.background.class_map if window is None else self.background.class_map[window]
        water = cls == 1
        cos_sun = max(float(c.sun_direction[2]), 0.0) if c.sun_up else 0.0
        eps_bg = optics.emissivity[cls]
        emit_bg = eps_bg * planck(temp_bg)
        sky_bg = (1.0 - eps_bg) * np.where(water, c.sky_radiance_specular, c.sky_radiance_mean)
        f_sun = optics.sun_brdf(c.sun_zenith_deg, c.sun_azimuth_deg) if c.sun_up else np.zeros(5)
        sun_bg = c.solar_irradiance * cos_sun * f_sun[cls]
        leave = emit_bg + sky_bg + sun_bg
        ap = (c.transmittance_emitted(temp_bg) * emit_bg
              + np.where(water, c.transmittance_sky, c.transmittance_sky_mean) * sky_bg
              + c.transmittance_sun * sun_bg)
        return leave, ap, sun_bg

    def _ship_sample_radiance(self, c: BandConditions, sun: SunGeometry, planck, temp_f,
                              temp_sea: float) -> tuple:
        """Ship samples (eqs. 2 and 19): surface-leaving and at-aperture radiance of every
        view sample that hits the ship [W m-2 sr-1]."""
        s_dir = c.sun_direction
        eps_f = self.ship_emissivity(c.band)
        emit_f = eps_f * planck(temp_f)
        f_up = 0.5 * (1.0 + self.face_normals[:, 2])
        # the sea the hull sides see: hemispherical emissivity of the same rough sea
        eps_w = rough_sea_emissivity_hemispherical(c.band, self.wind_speed)
        l_sea = eps_w * float(planck(temp_sea)) + (1.0 - eps_w) * c.sky_radiance_mean
        sky_f = (1.0 - eps_f) * (f_up * c.sky_radiance_mean + (1.0 - f_up) * l_sea)
        # per sample: the sun term uses the normal oriented toward the viewer
        fs = self.ship_face
        if c.sun_up and sun.ship_lit.any():
            lit = sun.ship_lit
            n_l = self.ship_normals[lit]
            mu = n_l @ s_dir
            brdf = self.paint.brdf(n_l, s_dir, self.view_direction, eps_f[fs[lit]])
            sun_s = np.zeros(len(fs))
            sun_s[lit] = c.solar_irradiance * np.maximum(mu, 0.0) * brdf
        else:
            sun_s = np.zeros(len(fs))
        base_leave = emit_f + sky_f
        base_ap = c.transmittance_emitted(temp_f) * emit_f + c.transmittance_sky_mean * sky_f
        smp_leave = base_leave[fs] + sun_s
        smp_ap = base_ap[fs] + c.transmittance_sun * sun_s
        return smp_leave, smp_ap

    def _mix_pixels(self, c: BandConditions, sun: SunGeometry, leave, ap, sun_bg, smp_leave,
                    smp_ap) -> tuple:
        """Each pixel the area-weighted mix of what its samples see, the reflected sun taken
        off the shadowed ground: flat leaving and at-aperture radiance and the shadow
        fraction."""
        ny, nx = self.shape
        ss = float(self.samples_per_pixel ** 2)
        cov = self.coverage.ravel()
        vp = self.view_pixels
        out_leave = leave.ravel().copy()
        out_ap = ap.ravel().copy()
        ship_leave = np.bincount(self.ship_pixel, smp_leave, minlength=ny * nx)[vp] / ss
        ship_ap = np.bincount(self.ship_pixel, smp_ap, minlength=ny * nx)[vp] / ss
        out_leave[vp] = ship_leave + (1.0 - cov[vp]) * out_leave[vp]
        out_ap[vp] = ship_ap + (1.0 - cov[vp]) * out_ap[vp]
        shadow = np.zeros(ny * nx)
        if len(sun.shadow_pixels):
            sp, g = sun.shadow_pixels, sun.shadow_fraction
            shadow[sp] = g
            out_leave[sp] -= g * sun_bg.ravel()[sp]
            out_ap[sp] -= g * c.transmittance_sun * sun_bg.ravel()[sp]
        return out_leave, out_ap, shadow

    def _detector(self, c: BandConditions, radiance, opts: SensorOptions) -> tuple:
        """The detector effects of ``opts`` on the at-aperture image: PSF, NETD noise,
        quantisation; the radiance and the digital numbers (None unquantised)."""
        band = c.band
        dn = None
        if opts.psf:
            # the image grid may be finer than the detector's footprint (a resampled product,
            # e.g. Landsat TIRS 99 m on 30 m): then the detector box blurs too
            ratio = self.sensor.nadir_gsd_m / self.resolution_m
            fine = ratio > 1.01
            radiance = apply_psf(radiance, standard_band(band).mean_wavelength_um, self.sensor,
                                 samples_per_pixel=ratio if fine else 1,
                                 include_detector=fine)
        if opts.netd_k is not None:
            resp = float(c.transmittance_emitted(300.0) * band_radiance_dt(300.0, band))
            radiance = add_netd_noise(radiance, opts.netd_k, resp, seed=opts.seed)
        if opts.bits is not None:
            dn = quantise(radiance, opts.bits, *opts.radiance_range)
            radiance = dequantise(dn, opts.bits, *opts.radiance_range)
        return radiance, dn
