"""The imaged scene: background grid, ship placement, view and sun geometry, surface optics.

Coordinates
-----------
*Scene coordinates* are metres east (``x``) and north (``y``) of the south-west corner of
the background grid, with ``z`` up and ``z = 0`` the sea surface (the ship's waterline).
Pixel ``(row, col)`` of the background grid (row 0 = north edge, like the GeoTIFFs) covers
``x in [col res, (col + 1) res]``, ``y in [(ny - 1 - row) res, (ny - row) res]``.

Directions are East-North-Up unit vectors; azimuths are clockwise from north (pvlib's sun
azimuth convention, also :func:`imaging.sensor.view_direction`).

Surface optics
--------------
* Ship paint: Cook-Torrance (paper eq. 19,
  :func:`shipthermal.optics.brdf.cook_torrance_brdf_vectors`)
  with exact Fresnel for a binder of index :attr:`ShipPaint.refractive_index` and a Lambertian
  part ``kd = 1 - eps - F0`` so that the reflectance is ``1 - eps`` near normal incidence
  (Kirchhoff for an opaque surface).
* Sea: Cox-Munk (eq. 7) with Smith shadowing and the band-mean water index of Hale &
  Querry; directional emissivity one minus the directional albedo of that same BRDF at the
  scene's wind speed (:func:`shipthermal.optics.sea.rough_sea_emissivity`), so emission and
  reflection close (Kirchhoff) at every view angle.
* Land classes: RPV (eq. 8) with the shapes of :data:`RPV_SHAPE`; the amplitude ``rho0`` is
  solved so that the directional-hemispherical reflectance from the view direction equals
  ``1 - eps`` (Kirchhoff + reciprocity).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from shipthermal.errors import InputError, check_finite, check_positive, check_range, require
from shipthermal.optics import brdf as B
from shipthermal.optics.responses import thermal_band_key
from shipthermal.optics.sea import sea_emissivity, water_band_mean_index
from shipthermal.parameters import check_wind_speed

from .parameters import CLASS_NAMES
from .radiometry import background_emissivity

__all__ = [
    "ShipPlacement", "GriddedBackground", "as_scene_background", "default_mooring",
    "SYNTHETIC_MOORING_UV", "ShipPaint", "RPV_SHAPE", "rpv_rho0", "enu_direction",
    "compass_to_math_azimuth", "BackgroundOptics", "background_optics",
]


# ---------------------------------------------------------------------------------------
# Directions
# ---------------------------------------------------------------------------------------
def enu_direction(zenith_deg, azimuth_deg) -> np.ndarray:
    """Unit vector(s) East-North-Up [-] for a zenith [deg] and compass azimuth [deg]."""
    z = np.radians(np.asarray(zenith_deg, dtype=float))
    a = np.radians(np.asarray(azimuth_deg, dtype=float))
    sz = np.sin(z)
    return np.stack(np.broadcast_arrays(sz * np.sin(a), sz * np.cos(a), np.cos(z)), axis=-1)


def compass_to_math_azimuth(azimuth_deg):
    """Compass azimuth (clockwise from north) [deg] -> mathematical azimuth (counter-clockwise
    from east) [deg], the ``phi`` of :func:`shipthermal.optics.brdf.direction`."""
    return 90.0 - np.asarray(azimuth_deg, dtype=float)


# ---------------------------------------------------------------------------------------
# Ship placement
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ShipPlacement:
    """Where the ship lies in the scene.

    Attributes
    ----------
    x_m, y_m : float
        Scene position of the ship-frame origin (amidships on the waterline) [m]
        (east and north of the grid's south-west corner).
    heading_deg : float
        Compass direction of the bow [deg] (0 north, 90 east).
    """

    x_m: float
    y_m: float
    heading_deg: float = 0.0

    def __post_init__(self):
        check_finite("placement.x_m", self.x_m)
        check_finite("placement.y_m", self.y_m)
        check_finite("placement.heading_deg", self.heading_deg)

    def rotation(self) -> np.ndarray:
        """3 x 3 matrix taking ship-frame vectors (x forward, y port, z up) to ENU [-]."""
        h = math.radians(self.heading_deg)
        bow = np.array([math.sin(h), math.cos(h), 0.0])
        port = np.array([-math.cos(h), math.sin(h), 0.0])   # bow turned 90 deg to the left
        return np.column_stack([bow, port, [0.0, 0.0, 1.0]])

    def to_scene(self, points) -> np.ndarray:
        """Ship-frame points [m] (..., 3) -> scene coordinates [m]."""
        p = np.asarray(points, dtype=float)
        return p @ self.rotation().T + np.array([self.x_m, self.y_m, 0.0])


SYNTHETIC_MOORING_UV = (0.53, 0.49)
"""Default mooring in scene-normalised coordinates (u east, v south of the north-west corner):
the middle of the water between the first two piers of the built-in synthetic port
(:mod:`imaging.background.synthetic`: piers at u = 0.48-0.50 and 0.56-0.58, v = 0.40-0.58),
so the local-SCR window (twice the ship) is harbour water."""


def default_mooring(background, heading_deg: float = 0.0) -> ShipPlacement:
    """The default ship position in ``background``: :data:`SYNTHETIC_MOORING_UV`, bow north.

    Raises :class:`InputError` when that point is not water (a user background): give a
    :class:`ShipPlacement` then.
    """
    bg = as_scene_background(background)
    ny, nx = bg.shape
    u, v = SYNTHETIC_MOORING_UV
    place = ShipPlacement(u * nx * bg.resolution_m, (1.0 - v) * ny * bg.resolution_m,
                          heading_deg)
    row, col = int(v * ny), int(u * nx)
    require(int(bg.class_map[row, col]) == 1, "placement", "default mooring",
            f"the default position (row {row}, col {col}) is class "
            f"{CLASS_NAMES.get(int(bg.class_map[row, col]), 'fill')}, not water",
            "Pass placement=ShipPlacement(x_m, y_m, heading_deg) for this background")
    return place


# ---------------------------------------------------------------------------------------
# Background on a grid
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class GriddedBackground:
    """Background classes and temperatures on the image grid.

    Attributes
    ----------
    class_map : (ny, nx) uint8
        1 water, 2 vegetation, 3 land, 4 building.
    hours_local : (nh,) float
        Local clock hours of the temperature layers [h], increasing, within one day.
    temperature : (nh, ny, nx) float
        Surface temperature per layer [K] (periodic over 24 h, linear in between).
    resolution_m : float
        Pixel size [m] (square pixels).
    grid : SceneGrid or None
        Georeferencing for GeoTIFF/NetCDF (``imaging.background.SceneGrid``); None: a local
        grid with the origin at the south-west corner and no CRS.
    source : object or None
        A background that computes its temperatures itself (``source.temperature_at(hour)``,
        e.g. :class:`imaging.background.physical.PhysicalBackground`, whose hours run on
        past one day for a weather record); ``hours_local`` / ``temperature`` then hold its
        first hour only.
    """

    class_map: np.ndarray
    hours_local: np.ndarray
    temperature: np.ndarray
    resolution_m: float = 30.0
    grid: object = None
    source: object = None

    def __post_init__(self):
        cm = np.asarray(self.class_map)
        temp = np.asarray(self.temperature, dtype=float)
        hrs = np.asarray(self.hours_local, dtype=float).reshape(-1)
        require(cm.ndim == 2, "background.class_map", cm.shape, "must be 2-D (rows, cols)")
        require(bool(np.isin(cm, (1, 2, 3, 4)).all()), "background.class_map",
                np.unique(cm), "codes must be 1 water, 2 vegetation, 3 land, 4 building",
                "Fill unclassified pixels (code 0) or crop them away")
        require(temp.shape == (hrs.size, *cm.shape), "background.temperature", temp.shape,
                f"must be (n_hours, rows, cols) = ({hrs.size}, {cm.shape[0]}, {cm.shape[1]})")
        require(hrs.size >= 1 and bool(np.all(np.diff(hrs) > 0)) and hrs[-1] - hrs[0] < 24.0,
                "background.hours_local", hrs, "must increase within one day [h]")
        check_range("background.temperature", temp, 100.0, 400.0, "K")
        check_positive("background.resolution_m", self.resolution_m, "m")
        if self.grid is None:
            # deferred: the background package loads scikit-learn, pykrige and scipy.stats
            # (2 s, measured); a gridded background without a grid is the only user
            from .background.landsat.grid import SceneGrid, north_up_transform

            ny, nx = cm.shape
            object.__setattr__(self, "grid", SceneGrid(
                north_up_transform(0.0, ny * self.resolution_m, self.resolution_m), None,
                (ny, nx)))
        object.__setattr__(self, "class_map", cm.astype(np.uint8, copy=False))
        object.__setattr__(self, "hours_local", hrs)

    @property
    def shape(self) -> tuple:
        return tuple(self.class_map.shape)

    def temperature_at(self, hour_local: float) -> np.ndarray:
        """Background temperature [K] at a local clock hour [h], linear, 24-h periodic (or
        the :attr:`source`'s own, hours after local midnight of its first day)."""
        if self.source is not None:
            return self.source.temperature_at(hour_local)
        hrs = self.hours_local
        temp = np.asarray(self.temperature)
        if hrs.size == 1:
            return np.asarray(temp[0], dtype=float)
        h = hrs[0] + (float(hour_local) - hrs[0]) % 24.0
        k = int(np.searchsorted(hrs, h, side="right") - 1)
        k1 = (k + 1) % hrs.size
        span = (hrs[k1] - hrs[k]) % 24.0 or 24.0
        w = (h - hrs[k]) / span
        return (1.0 - w) * temp[k] + w * temp[k1]

    @classmethod
    def uniform(cls, shape, class_code: int = 1, temp: float = 290.0,
                resolution_m: float = 30.0) -> "GriddedBackground":
        """A single-class, constant-temperature background (tests, calibration)."""
        cm = np.full(shape, class_code, dtype=np.uint8)
        return cls(cm, np.array([0.0]), np.full((1, *cm.shape), float(temp)), resolution_m)


def as_scene_background(background) -> GriddedBackground:
    """A :class:`GriddedBackground` from itself, from an
    :class:`imaging.background.PortBackground` (arrays shared, not copied) or from a
    background that computes its temperatures (:class:`imaging.background.physical.
    PhysicalBackground`: kept as the ``source``)."""
    if isinstance(background, GriddedBackground):
        return background
    if hasattr(background, "column_temperature"):
        return GriddedBackground(background.class_map, np.array([0.0]),
                                 background.temperature_at(0.0)[None],
                                 background.grid.resolution, background.grid, source=background)
    needed = ("class_map", "hours_local", "temperature", "grid")
    if not all(hasattr(background, a) for a in needed):
        raise InputError("background", type(background).__name__,
                         "must be a PortBackground or a GriddedBackground",
                         "Build one with imaging.background.build_port_background(season)")
    return GriddedBackground(background.class_map, background.hours_local,
                             background.temperature, background.grid.resolution,
                             background.grid)


# ---------------------------------------------------------------------------------------
# Surface optics
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ShipPaint:
    """Reflection of the ship's paint (Cook-Torrance, paper eq. 19).

    Attributes
    ----------
    roughness : float
        Beckmann rms facet slope [-]. ASSUMPTION: 0.3, a semi-gloss naval paint (no IR
        BRDF measurement of ship paint at hand).
    refractive_index : complex
        Binder's complex index for the Fresnel term [-]. ASSUMPTION: 1.5 (polymer binders,
        thermal IR), normal-incidence Fresnel 0.04.
    """

    roughness: float = 0.3
    refractive_index: complex = 1.5 + 0.0j

    def __post_init__(self):
        check_positive("paint.roughness", self.roughness)

    @property
    def f0(self) -> float:
        """Normal-incidence Fresnel reflectance [-]."""
        return float(B.fresnel_normal_reflectance(self.refractive_index))

    def brdf(self, normal, to_sun, to_view, emissivity):
        """BRDF [sr-1] for unit normals (..., 3), sun and view directions and emissivity [-].

        Specular lobe ``ks = min(1, (1 - eps)/F0)`` with exact Fresnel, Lambertian part
        ``kd = 1 - eps - ks F0``: the near-normal reflectance is ``1 - eps`` (Kirchhoff), also
        for a nearly black paint (eps > 1 - F0).
        """
        eps = np.asarray(emissivity, dtype=float)
        ks = np.clip((1.0 - eps) / self.f0, 0.0, 1.0)
        kd = np.clip(1.0 - eps - ks * self.f0, 0.0, 1.0)
        n = np.asarray(normal, dtype=float)
        s = np.broadcast_to(np.asarray(to_sun, dtype=float), n.shape)
        v = np.broadcast_to(np.asarray(to_view, dtype=float), n.shape)
        spec = B.cook_torrance_brdf_vectors(n, s, v, self.roughness, 0.0, 1.0,
                                            refractive_index=self.refractive_index)
        up = (np.sum(n * s, -1) > 0) & (np.sum(n * v, -1) > 0)
        return ks * spec + np.where(up, kd / math.pi, 0.0)


RPV_SHAPE = {
    # class: (k [-], b [-]) of the exponential-phase RPV (paper eq. 8)
    "vegetation": (0.70, -0.10),
    "land": (0.80, -0.15),
    "building": (0.85, -0.05),
}
"""RPV shape parameters per land class. ASSUMPTION: inside the ranges of the RPV fits of
Rahman, Pinty & Verstraete (1993, JGR 98:20791) for vegetation and soils (k 0.6-0.9, mild
backscatter); those fits are visible/near-IR and are assumed to keep their shape in the
thermal IR. The amplitude ``rho0`` is not assumed: :func:`rpv_rho0` sets it by Kirchhoff."""


def rpv_rho0(emissivity: float, view_zenith_deg: float, k: float, b: float,
             iterations: int = 4) -> float:
    """RPV amplitude ``rho0`` [-] whose directional-hemispherical reflectance from the view
    direction equals ``1 - emissivity`` (Kirchhoff; by reciprocity it is then also the
    reflectance *toward* the viewer of isotropic light).

    Parameters
    ----------
    emissivity : float
        Band emissivity [-].
    view_zenith_deg : float
        View zenith angle [deg].
    k, b : float
        RPV shape parameters [-] (:data:`RPV_SHAPE`).
    iterations : int
        Fixed-point steps for the hot-spot term (``rho_c = rho0``) [-].
    """
    check_range("emissivity", emissivity, 0.0, 1.0)
    target = 1.0 - float(emissivity)
    theta_deg = min(float(view_zenith_deg), 89.0)
    rho0 = target
    for _ in range(int(iterations)):
        unit = B.directional_albedo(B.rpv_brdf, theta_deg, 0.0, n_mu=64, n_phi=128, rho0=1.0,
                                    k=k, b=b, rho_c=rho0)
        rho0 = target / unit
    return float(rho0)


@dataclass(frozen=True, eq=False)
class BackgroundOptics:
    """Per-class directional emissivity and sun BRDF for one band and view geometry.

    Attributes
    ----------
    band : str
    view_zenith_deg, view_azimuth_deg : float
        Sensor direction seen from the ground [deg] (compass azimuth).
    wind_speed : float
        Wind speed of the Cox-Munk slopes [m s-1].
    emissivity : (5,) float
        Directional emissivity toward the sensor per class code 0..4 (0 unused) [-].
    rpv : dict
        ``{class code: (rho0, k, b)}`` of the land classes [-].
    water_sun_scale : float
        Factor on the Cox-Munk BRDF [-]: 1, or ``(1 - eps_override) / (1 - eps_rough)``
        when the water emissivity is overridden (keeps reflectance = 1 - emissivity).
    """

    band: str
    view_zenith_deg: float
    view_azimuth_deg: float
    wind_speed: float
    emissivity: np.ndarray
    rpv: dict
    water_sun_scale: float = 1.0

    def sun_brdf(self, sun_zenith_deg: float, sun_azimuth_deg: float) -> np.ndarray:
        """BRDF for (sun, view) per class code 0..4 [sr-1]; zeros when the sun is down.

        Sun zenith and compass azimuth in [deg]. Water: Cox-Munk (eq. 7) with Smith
        shadowing and the band-mean index of water; land: RPV (eq. 8).
        """
        f_sun = np.zeros(5)
        if sun_zenith_deg >= 90.0:
            return f_sun
        th_v, th_s = self.view_zenith_deg, sun_zenith_deg
        phi_v = float(compass_to_math_azimuth(self.view_azimuth_deg))
        phi_s = float(compass_to_math_azimuth(sun_azimuth_deg))
        f_sun[1] = self.water_sun_scale * float(B.cox_munk_brdf(
            th_s, phi_s, th_v, phi_v, self.wind_speed, water_band_mean_index(self.band),
            shadowing=True))
        for code, (rho0, k, b) in self.rpv.items():
            f_sun[code] = float(B.rpv_brdf(th_s, phi_s, th_v, phi_v, rho0, k, b))
        return f_sun


def background_optics(band: str, view_zenith_deg: float, view_azimuth_deg: float,
                      wind_speed: float, emissivity_override: dict | None = None,
                      rpv_shape: dict | None = None) -> BackgroundOptics:
    """Class emissivities and BRDF parameters for a band and a view direction.

    Parameters
    ----------
    band : str
        A named band (``"3-5"``, ``"8-14"``, a sensor's band): water from the band's
        response, land classes from the emissivity table of the paper band holding it.
    view_zenith_deg, view_azimuth_deg : float
        Sensor direction seen from the ground [deg] (compass azimuth).
    wind_speed : float
        Wind speed for the Cox-Munk slopes [m s-1].
    emissivity_override : dict or None
        ``{class name: emissivity}`` replacing :data:`imaging.parameters.BACKGROUND_EMISSIVITY`
        (for water: a constant replacing the rough-sea angular emissivity).
    rpv_shape : dict or None
        Replaces :data:`RPV_SHAPE` entries.

    Returns
    -------
    BackgroundOptics

    Notes
    -----
    Water: ``eps(theta_v) = 1 - a(theta_v)``, ``a`` the directional albedo of the
    shadowed Cox-Munk BRDF at ``wind_speed`` with the band-mean index (Kirchhoff +
    reciprocity, :func:`shipthermal.optics.sea.rough_sea_emissivity`); land classes: emissivity
    tables and RPV amplitude from :func:`rpv_rho0`.
    """
    check_range("view_zenith_deg", view_zenith_deg, 0.0, 85.0, "deg")
    check_wind_speed("wind_speed", wind_speed)
    override = dict(emissivity_override or {})
    unknown = sorted(set(override) - set(CLASS_NAMES.values()))
    require(not unknown, "emissivity_override", unknown,
            f"keys must be class names {sorted(CLASS_NAMES.values())}")
    shapes = {**RPV_SHAPE, **(rpv_shape or {})}
    eps = np.zeros(5)
    rpv = {}
    scale = 1.0
    for code, name in CLASS_NAMES.items():
        if name == "water":
            rough = float(sea_emissivity(view_zenith_deg, band, wind_speed=wind_speed))
            eps[code] = override.get("water", rough)
            scale = (1.0 - eps[code]) / (1.0 - rough)
        else:
            eps[code] = override.get(name, background_emissivity(name, thermal_band_key(band)))
            k, b = shapes[name]
            rpv[code] = (rpv_rho0(eps[code], view_zenith_deg, k, b), k, b)
    check_range("emissivity_override", eps[1:], 0.0, 1.0)
    eps.setflags(write=False)
    return BackgroundOptics(band, float(view_zenith_deg), float(view_azimuth_deg),
                            float(wind_speed), eps, rpv, float(scale))
