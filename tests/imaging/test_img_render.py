"""Tests for imaging.render: sub-pixel mixing, shadows, projection, Kirchhoff closure, backends."""

import math

import numpy as np
import pytest
from matplotlib.path import Path
from scipy.spatial import ConvexHull

from shipthermal.optics.brdf import cox_munk_brdf
from imaging.metrics import local_scr
from imaging.radiometry import band_radiance, sea_emissivity, water_band_mean_index
from imaging.render import BandConditions, SceneRenderer
from imaging.scene import GriddedBackground, ShipPaint, ShipPlacement, compass_to_math_azimuth
from imaging.thermal_history import ShipThermalHistory
from shipthermal.errors import InputError
from shipthermal.parameters import BAND_EMISSIVITY
from shipthermal.raytrace.scenes import box

RES = 30.0
S = 16                   # samples per pixel axis: sub-cells of 30/16 = 1.875 m
SCENE = ShipPlacement(0.0, 0.0, 90.0)   # heading east: ship frame (x fwd, y port) = (east, north)
WIND_SPEED = 5.0         # m/s: the sea's Cox-Munk slopes in these scenes


@pytest.fixture(scope="module")
def frigate_coarse():
    from shipthermal.geometry import frigate

    return frigate(edge_length=2.0)         # ~4.8k triangles: the real shape, cheap to trace


def _history(vertices, faces, temp=300.0, part="deck"):
    m = len(faces)
    return ShipThermalHistory(vertices, faces, np.zeros(m, int), (part,), [0.0, 3600.0],
                              np.full((2, m), temp))


def _water(ny=6, nx=6, temp=295.0):
    return GriddedBackground.uniform((ny, nx), 1, temp, RES)


def _pixel(row_y_low, col_x_low, ny):
    """(row, col) of the pixel whose south-west corner is at scene (x, y) [m]."""
    return ny - 1 - int(row_y_low // RES), int(col_x_low // RES)


def test_box_covering_half_a_pixel_gives_the_half_mixed_radiance():
    ny = nx = 6
    # top face x in [30, 45] (the west half of column 1), y in [60, 90] (one whole row):
    # 45 m falls between sub-cell centres 44.06 and 45.94, so exactly 8 of 16 columns
    V, F = box([30.0, 60.0, -2.0], [45.0, 90.0, 5.0])
    hist = _history(V, F, temp=310.0)
    r = SceneRenderer(hist, _water(ny, nx), SCENE, samples_per_pixel=S, wind_speed=WIND_SPEED)
    cond = BandConditions.simple("8-14", transmittance=0.6, path_radiance=2.0)
    fr = r.render(cond, hist.at(0.0), np.full((ny, nx), 295.0))
    row, col = _pixel(60.0, 30.0, ny)
    assert fr.coverage[row, col] == 0.5
    assert fr.coverage.sum() == 0.5          # nothing else is touched (nadir view)
    eps_ship = BAND_EMISSIVITY["deck"]["8-14"]   # paper §5
    l_ship = eps_ship * band_radiance(310.0, "8-14")
    l_water = float(sea_emissivity(0.0, "8-14", wind_speed=WIND_SPEED)) * \
        band_radiance(295.0, "8-14")
    # float32 images: 1e-6 relative is ~8 ulp
    assert fr.leaving[row, col] == pytest.approx(0.5 * l_ship + 0.5 * l_water, rel=1e-6)
    assert fr.radiance[row, col] == pytest.approx(0.6 * (0.5 * l_ship + 0.5 * l_water) + 2.0,
                                                  rel=1e-6)
    assert fr.radiance[0, 0] == pytest.approx(0.6 * l_water + 2.0, rel=1e-6)


def test_nadir_coverage_of_a_rotated_box_equals_its_footprint_area():
    # 40 m x 12 m deck at 30 deg heading: the sampled coverage (area fraction per pixel)
    # must add up to the footprint area; regular sampling errs by at most about one
    # sub-cell (1.875 m)^2 per boundary sub-cell: perimeter 104 m / 1.875 m ~ 56 cells
    V, F = box([-20.0, -6.0, -1.0], [20.0, 6.0, 4.0])
    hist = _history(V, F)
    r = SceneRenderer(hist, _water(8, 8), ShipPlacement(120.0, 120.0, 30.0), samples_per_pixel=S,
                      wind_speed=WIND_SPEED)
    area = r.coverage.sum() * RES * RES
    assert abs(area - 480.0) < 56 * 1.875**2 / 4, area
    with pytest.raises(InputError, match="placement"):
        SceneRenderer(hist, _water(8, 8), ShipPlacement(5000.0, 120.0, 0.0), wind_speed=WIND_SPEED)


def _points_in_polygon(points, polygon):
    return Path(polygon).contains_points(points)


def _enu(zenith, azimuth):
    z, a = math.radians(zenith), math.radians(azimuth)
    return np.array([math.sin(z) * math.sin(a), math.sin(z) * math.cos(a), math.cos(z)])


def _ground_hull(top, foot, d):
    """Convex hull of the box seen along direction d: top corners moved along -d to z = 0."""
    proj = np.vstack([top[:, :2] - (top[:, 2] / d[2])[:, None] * d[:2], foot])
    return proj[ConvexHull(proj).vertices]


# nadir view with the sun in the east (shadow edges on sub-cell boundaries: exact area), and
# an oblique view near the sun's specular direction (strong glint, layover hides some shadow)
@pytest.mark.parametrize("sun_zenith, sun_azimuth, view_zenith, view_azimuth, exact",
                         [(45.0, 90.0, 0.0, 0.0, True), (40.0, 130.0, 35.0, 310.0, False)])
def test_box_shadow_on_water_removes_reflected_sun_on_the_right_samples(
        sun_zenith, sun_azimuth, view_zenith, view_azimuth, exact):
    ny = nx = 8
    lo, hi = np.array([75.0, 90.0, -1.0]), np.array([105.0, 120.0, 7.5])
    V, F = box(lo, hi)
    hist = _history(V, F)
    r = SceneRenderer(hist, _water(ny, nx), SCENE, view_zenith_deg=view_zenith,
                      view_azimuth_deg=view_azimuth, samples_per_pixel=S, wind_speed=WIND_SPEED)
    cond = BandConditions.simple("3-5", sun_zenith_deg=sun_zenith, sun_azimuth_deg=sun_azimuth,
                                 solar_irradiance=10.0, sky_radiance=0.5)
    fr = r.render(cond, hist.at(0.0), np.full((ny, nx), 295.0))

    # independent geometry: a ground sample is in visible shadow when it lies inside the
    # box's shadow polygon (convex hull projected along the sun) and outside the box as seen
    # by the sensor (convex hull projected along the view); test every sample point
    top = V[V[:, 2] > 0]
    foot = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    sun_hull = _ground_hull(top, foot, _enu(sun_zenith, sun_azimuth))
    view_hull = _ground_hull(top, foot, _enu(view_zenith, view_azimuth))
    expected = np.zeros((ny, nx))
    sub = (np.arange(S) + 0.5) * RES / S
    for row in range(ny):
        for col in range(nx):
            xs, ys = np.meshgrid(col * RES + sub, (ny - 1 - row) * RES + sub)
            pts = np.column_stack([xs.ravel(), ys.ravel()])
            shade = _points_in_polygon(pts, sun_hull) & ~_points_in_polygon(pts, view_hull)
            expected[row, col] = shade.mean()
    np.testing.assert_array_equal(fr.shadow, expected.astype(np.float32))
    assert fr.shadow.sum() > 0.2
    if exact:
        # shadow 7.5 m long (H tan 45 deg) west of x = 75 m: 4 sub-cell columns of pixel
        # column 2, i.e. exactly a quarter of it, and the continuous area 7.5 x 30 m2
        row, col = _pixel(90.0, 60.0, ny)
        assert expected[row, col] == 0.25 and fr.shadow.sum() * RES * RES == 225.0

    # radiance: water pixel = emitted + sky + (lit share) * sun glint (Cox-Munk, eq. 7)
    th_v = view_zenith
    eps_w = float(sea_emissivity(th_v, "3-5", wind_speed=WIND_SPEED))  # rough sea (the scene's)
    f_sun = float(cox_munk_brdf(sun_zenith,
                                float(compass_to_math_azimuth(sun_azimuth)), th_v,
                                float(compass_to_math_azimuth(view_azimuth)), 5.0,
                                water_band_mean_index("3-5"), shadowing=True))
    sun_term = 10.0 * math.cos(math.radians(sun_zenith)) * f_sun
    l_bg = eps_w * band_radiance(295.0, "3-5") + (1 - eps_w) * 0.5
    open_water = (fr.coverage == 0)
    want = l_bg + (1.0 - fr.shadow) * sun_term
    np.testing.assert_allclose(fr.leaving[open_water], want[open_water], rtol=2e-6)
    if not exact:
        assert sun_term > 0.05 * l_bg       # near-specular glint: the check is not vacuous


def test_box_top_reflects_the_sun_by_cook_torrance_and_is_not_self_shadowed():
    ny = nx = 6
    V, F = box([30.0, 60.0, -1.0], [60.0, 90.0, 5.0])     # fills pixel column 1 exactly
    hist = _history(V, F, temp=300.0)
    paint = ShipPaint(roughness=0.3)
    r = SceneRenderer(hist, _water(ny, nx), SCENE, samples_per_pixel=S, paint=paint,
                      wind_speed=WIND_SPEED)
    cond = BandConditions.simple("3-5", sun_zenith_deg=30.0, sun_azimuth_deg=180.0,
                                 solar_irradiance=8.0, sky_radiance=0.7)
    fr = r.render(cond, hist.at(0.0), np.full((ny, nx), 295.0))
    row, col = _pixel(60.0, 30.0, ny)
    assert fr.coverage[row, col] == 1.0
    eps = 0.90                                              # deck, 3-5 um (paper §5)
    s = np.array([0.0, -math.sin(math.radians(30.0)), math.cos(math.radians(30.0))])
    f = float(paint.brdf(np.array([0, 0, 1.0]), s, np.array([0, 0, 1.0]), eps))
    want = eps * band_radiance(300.0, "3-5") + (1 - eps) * 0.7 + 8.0 * s[2] * f
    assert fr.leaving[row, col] == pytest.approx(want, rel=1e-6)
    assert r.sun_geometry(s).ship_lit.all()


def test_off_nadir_view_shows_layover_and_the_wall_facing_the_sensor():
    # a 30 m cube on pixel column 3; sensor in the east at 45 deg: the top projects 30 m
    # west (onto column 2), the east wall fills column 3 as seen from the sensor
    ny = nx = 6
    V, F = box([90.0, 60.0, 0.0], [120.0, 90.0, 30.0], n=2)
    hist = _history(V, F)
    r = SceneRenderer(hist, _water(ny, nx), SCENE, view_zenith_deg=45.0, view_azimuth_deg=90.0,
                      samples_per_pixel=S, wind_speed=WIND_SPEED)
    row = _pixel(60.0, 0.0, ny)[0]
    np.testing.assert_allclose(r.coverage[row], [0, 0, 1, 1, 0, 0], atol=1e-12)
    assert r.coverage.sum() == 2.0
    nrm = r.ship_normals
    top = nrm[:, 2] > 0.99
    east = nrm[:, 0] > 0.99
    assert (top | east).all()
    x = r.ship_points[:, 0]
    assert (x[top] < 90.0 + 1e-3).sum() == 0 and np.all(r.ship_pixel[top] % nx == 2)
    assert np.all(r.ship_pixel[east] % nx == 3)


@pytest.mark.parametrize("band", ["3-5", "8-14"])
def test_isothermal_blackbody_surroundings_give_zero_contrast(frigate_coarse, band):
    # Kirchhoff closure: ship, sea, sky and sea seen by the hull all at T: every pixel,
    # mixed or not, must be B(T) whatever the emissivities (eq. 2 with eps + rho = 1)
    temp = 291.0
    bb = band_radiance(temp, band)
    hist = _history(frigate_coarse.vertices, frigate_coarse.faces, temp)
    hist = ShipThermalHistory(frigate_coarse.vertices, frigate_coarse.faces,
                              frigate_coarse.face_part, frigate_coarse.part_names, [0.0, 1.0],
                              np.full((2, frigate_coarse.n_faces), temp))
    bg = _water(12, 12)
    r = SceneRenderer(hist, bg, ShipPlacement(180.0, 180.0, 35.0), samples_per_pixel=S,
                      wind_speed=WIND_SPEED)
    cond = BandConditions.simple(band, sky_radiance=bb)
    fr = r.render(cond, hist.at(0.0), np.full(bg.shape, temp), temp_sea=temp)
    mixed = (fr.coverage > 0) & (fr.coverage < 1)
    assert mixed.sum() >= 4
    np.testing.assert_allclose(fr.leaving, bb, rtol=2e-6)
    m = local_scr(fr.radiance.astype(float), fr.target_mask)
    assert abs(m.contrast) < 2e-6 * bb


def test_black_ship_on_black_water_in_sun_and_sky_gives_zero_contrast(frigate_coarse):
    # emissivity 1 for ship and water (equal on purpose): nothing is reflected
    # (Kirchhoff: the BRDFs scale to 1 - eps = 0), so sun, sky and sea add no radiance and
    # every pixel is tau B(T) + path, mixed or not
    temp = 283.0
    one = {"hull": 1.0, "deck": 1.0, "superstructure": 1.0}
    hist = ShipThermalHistory(frigate_coarse.vertices, frigate_coarse.faces,
                              frigate_coarse.face_part, frigate_coarse.part_names, [0.0, 1.0],
                              np.full((2, frigate_coarse.n_faces), temp))
    r = SceneRenderer(hist, _water(12, 12), ShipPlacement(180.0, 180.0, 20.0),
                      view_zenith_deg=30.0, view_azimuth_deg=200.0, samples_per_pixel=S,
                      ship_emissivity={"3-5": one}, background_emissivity={"3-5": {"water": 1.0}},
                      wind_speed=WIND_SPEED)
    cond = BandConditions.simple("3-5", sun_zenith_deg=50.0, sun_azimuth_deg=110.0,
                                 solar_irradiance=12.0, sky_radiance=0.8, transmittance=0.5,
                                 path_radiance=0.3)
    fr = r.render(cond, hist.at(0.0), np.full((12, 12), temp))
    assert fr.shadow.sum() > 0.2 and ((fr.coverage > 0) & (fr.coverage < 1)).sum() >= 4
    want = 0.5 * band_radiance(temp, "3-5") + 0.3
    np.testing.assert_allclose(fr.radiance, want, rtol=2e-6)
    # and a 1 K warmer ship is seen: the check above is not vacuous
    fr2 = r.render(cond, hist.at(0.0) + 1.0, np.full((12, 12), temp))
    assert local_scr(fr2.radiance.astype(float), fr2.target_mask).contrast > 1e-3


def test_embree_and_numba_renders_agree(frigate_coarse):
    hist = ShipThermalHistory(frigate_coarse.vertices, frigate_coarse.faces,
                              frigate_coarse.face_part, frigate_coarse.part_names, [0.0, 1.0],
                              np.linspace(285.0, 315.0, 2 * frigate_coarse.n_faces)
                              .reshape(2, -1))
    cond = BandConditions.simple("3-5", sun_zenith_deg=50.0, sun_azimuth_deg=140.0,
                                 solar_irradiance=9.0, sky_radiance=0.6, transmittance=0.4,
                                 path_radiance=0.3)
    frames, rend = [], []
    for backend in ("embree", "numba"):
        r = SceneRenderer(hist, _water(14, 14), ShipPlacement(210.0, 200.0, 60.0),
                          view_zenith_deg=20.0, view_azimuth_deg=250.0, samples_per_pixel=S,
                          backend=backend, wind_speed=WIND_SPEED)
        rend.append(r)
        frames.append(r.render(cond, hist.at(0.5), np.full((14, 14), 296.0)))
    e, n = frames
    # the float32 (Embree) and float64 (numba) tracers may disagree only on rays grazing a
    # triangle edge: allow 1 sample in 2000 to land on a different face / miss (measured
    # here: identical faces, coverage, shadows and radiance)
    same_face = np.mean(rend[0].ship_face[:min(len(rend[0].ship_face), len(rend[1].ship_face))]
                        == rend[1].ship_face[:min(len(rend[0].ship_face),
                                                  len(rend[1].ship_face))])
    assert abs(len(rend[0].ship_face) - len(rend[1].ship_face)) <= rend[0].n_view_rays / 2000
    assert same_face > 0.99
    assert np.max(np.abs(e.coverage - n.coverage)) <= 2.0 / S**2
    # a sample is 1/256 of a pixel; ship/water radiance differences are < 30 %: the pixel
    # radiance may differ by ~2 samples x 30 % / 256 = 2.3e-3 relative at most
    np.testing.assert_allclose(e.radiance, n.radiance, rtol=2.5e-3)
    np.testing.assert_array_less(np.abs(e.shadow - n.shadow), 3.0 / S**2 + 1e-7)


def test_render_rejects_bad_inputs(frigate_coarse):
    V, F = box([30.0, 60.0, -1.0], [60.0, 90.0, 5.0])
    hist = _history(V, F)
    r = SceneRenderer(hist, _water(), SCENE, samples_per_pixel=4, wind_speed=WIND_SPEED)
    cond = BandConditions.simple("8-14")
    with pytest.raises(InputError, match="face_temperature"):
        r.render(cond, np.full(3, 300.0), np.full((6, 6), 295.0))
    with pytest.raises(InputError, match="background_temperature"):
        r.render(cond, hist.at(0.0), np.full((5, 6), 295.0))
    with pytest.raises(InputError, match="samples_per_pixel"):
        SceneRenderer(hist, _water(), SCENE, samples_per_pixel=0, wind_speed=WIND_SPEED)
    with pytest.raises(InputError, match="view_zenith_deg"):
        SceneRenderer(hist, _water(), SCENE, view_zenith_deg=85.0, wind_speed=WIND_SPEED)
    under = _history(*box([30.0, 60.0, -5.0], [60.0, 90.0, -1.0]))
    with pytest.raises(InputError, match="waterline"):
        SceneRenderer(under, _water(), SCENE, wind_speed=WIND_SPEED)


def test_sensor_chain_camera_equation_psf_noise_and_quantisation():
    ny = nx = 16
    V, F = box([210.0, 210.0, -1.0], [270.0, 240.0, 6.0])
    hist = _history(V, F, temp=305.0)
    r = SceneRenderer(hist, _water(ny, nx), SCENE, samples_per_pixel=4, wind_speed=WIND_SPEED)
    cond = BandConditions.simple("8-14", transmittance=0.5, path_radiance=15.0)
    clean = r.render(cond, hist.at(0.0), np.full((ny, nx), 295.0))
    # camera equation of the paper's sensor: E = tau_o pi L / (4 N^2), N = 2, tau_o = 0.7
    np.testing.assert_allclose(clean.irradiance, 0.7 * math.pi / 16.0 * clean.radiance,
                               rtol=1e-6)
    from imaging.render import SensorOptions

    blur = r.render(cond, hist.at(0.0), np.full((ny, nx), 295.0),
                    sensor_options=SensorOptions(psf=True))
    # the Airy PSF moves energy out of the target but keeps the image mean (OTF(0) = 1) up
    # to the Airy wings beyond the 8-pixel reflect padding (< 0.5 % of the target's excess,
    # sensor.apply_psf): target excess ~0.3 % of the image mean -> < 1.5e-5; measured 1.0e-5
    assert blur.radiance.mean() == pytest.approx(clean.radiance.mean(), rel=3e-5)
    assert blur.radiance.max() < clean.radiance.max()
    noisy = r.render(cond, hist.at(0.0), np.full((ny, nx), 295.0),
                     sensor_options=SensorOptions(netd_k=0.05, bits=14, radiance_range=(20., 60.)))
    assert noisy.dn.dtype == np.uint16 and noisy.dn.max() < 2**14
    from imaging.radiometry import band_radiance_dt

    # white noise of NETD x tau dB/dT(300 K) (+ quantisation step 40/16383 / sqrt 12, 3 %
    # of it in quadrature); 256 pixels estimate a std within 4.4 % (1 sigma): allow 20 %
    sigma = math.hypot(0.05 * 0.5 * band_radiance_dt(300.0, "8-14"), 40.0 / 16383 / 12**0.5)
    diff = (noisy.radiance - clean.radiance).astype(float)
    assert diff.std() == pytest.approx(sigma, rel=0.2)
    assert abs(diff.mean()) < 4 * sigma / 16           # no bias (4 standard errors)


def test_default_mooring_is_in_the_harbour_water_with_a_water_scr_window():
    from imaging.background import build_port_background
    from imaging.metrics import background_window
    from imaging.scene import default_mooring

    bg = build_port_background("winter")
    place = default_mooring(bg)
    V, F = box([-66.0, -7.5, -4.0], [66.0, 7.5, 8.0])          # frigate-sized box
    r = SceneRenderer(_history(V, F), bg, place, samples_per_pixel=4, wind_speed=WIND_SPEED)
    r0, r1, c0, c1 = background_window(r.coverage > 0, 2.0)
    assert np.all(bg.class_map[r0:r1, c0:c1] == 1)
