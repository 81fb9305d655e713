"""Solar loading of the forcing against closed forms and conservation.

Scenes are tiny "ships" made of analytic plates and boxes (raytrace.scenes) so the expected
irradiance is known in closed form; the patrol boat (2 m edges) checks the energy sanity of
a real ship. Every build uses float64 tables so comparisons are not limited by storage.
"""

import numpy as np
import pytest

from shipthermal.environment import Environment, climate_day
from shipthermal.forcing import ForcingSettings, build_ship_forcing
from shipthermal.geometry import ShipGeometry, build_ship_mesh, patrol_boat
from shipthermal.geometry.layups import compartment_temperatures, default_layups, outer_media
from shipthermal.raytrace import ReceiverPlane, shadow_area_on_plane
from shipthermal.raytrace.analytic import convex_shadow_area
from shipthermal.raytrace.scenes import box, combine, rectangle

TIMES = np.arange(0.0, 86400.0, 1800.0)


@pytest.fixture(scope="module")
def summer():
    return Environment.from_climate_day(climate_day("summer"), ship_heading=0.0)


def scene_ship(meshes, parts):
    """A ShipGeometry from (vertices, faces) pairs, one part name per pair."""
    v, f = combine(*meshes)
    names = tuple(dict.fromkeys(parts))
    face_part = np.concatenate([np.full(len(m[1]), names.index(p)) for m, p in zip(meshes, parts)])
    span = np.ptp(v, axis=0)
    return ShipGeometry(vertices=v, faces=f, face_part=face_part, part_names=names,
                        layups=default_layups(names),
                        compartment_temperature=compartment_temperatures(names),
                        outer_medium=outer_media(names), length=float(span[0]),
                        beam=float(span[1]), draught=1.0, freeboard=1.0, name="scene")


def forcing_of(ship, env, times=TIMES, **settings):
    graph, _ = build_ship_mesh(ship)
    settings.setdefault("dtype", np.float64)
    return build_ship_forcing(ship, env, graph, ForcingSettings(**settings), times=times,
                              progress=False), graph


def test_open_horizontal_face_gets_alpha_dni_cos_plus_dhi(summer):
    # A lone upward plate above the sea: nothing can shade it (lit fraction exactly 1), all
    # its cosine-weighted rays escape upward (F_sky exactly 1, F_sea 0, no ship faces), so
    # q = α (DNI cos Z + DHI) with no Monte-Carlo error at all: only round-off remains.
    ship = scene_ship([rectangle([0, 0, 1.0], [10, 0, 0], [0, 10, 0], 3, 3)], ["deck"])
    f, graph = forcing_of(ship, summer, absorptivity=0.8)
    state = summer.at(TIMES)
    assert np.all(f.F_sky == 1.0) and np.all(f.F_sea == 0.0)
    cos_z = np.clip(np.cos(np.radians(state.zenith)), 0.0, None)
    expected = 0.8 * (state.dni * cos_z + state.dhi)
    cond = f.conditions()["deck:outer"]
    got = np.array([cond.absorbed_shortwave(t) for t in TIMES])      # (n_t, faces)
    assert got.shape == (len(TIMES), len(graph.patch_faces("deck:outer")))
    np.testing.assert_allclose(got, np.repeat(expected[:, None], got.shape[1], 1),
                               rtol=1e-12, atol=1e-9)
    assert expected.max() > 500.0  # the check ran with a real midday sun


def test_box_shadow_on_a_deck_matches_the_projected_footprint(summer):
    # A 10 m x 10 m deck (800 triangles) at z = 1 m and a 2 m cube hovering 3 m above it.
    # With the ship's reflection off, the direct part of the deck's absorbed power is
    # α DNI s_z (A_deck − A_shadow) with A_shadow the cube's convex shadow on z = 1
    # (closed form: analytic.convex_shadow_area). Only triangles cut by the shadow's edge
    # (the partly lit ones, 0 < lit < 1) carry sampling error: a lit indicator over 16
    # samples has SE ≤ 0.5/√16 = 1/8 of the face, independent between faces (one random
    # shift each), so the shadow area has SE ≤ √N_partial · A_tri / 8; tolerance 4 SE
    # (≈ 5 % of the shadow here; a missing shadow would be off by 100 %).
    deck = rectangle([0, 0, 1.0], [10, 0, 0], [0, 10, 0], 20, 20)
    cube = box([4.0, 4.0, 4.0], [6.0, 6.0, 6.0], 2)
    ship = scene_ship([deck, cube], ["deck", "superstructure"])
    f, graph = forcing_of(ship, summer, absorptivity=0.8, ship_reflection=False)
    state = summer.at(TIMES)
    k = int(np.argmin(np.abs(TIMES - 12 * 3600.0)))
    s = f.sun_ship[k]
    assert s[2] > 0.8
    cols = f.patches["deck:outer"].cols
    area = f.traced.areas[cols]
    q = f.conditions()["deck:outer"].absorbed_shortwave(TIMES[k])
    diffuse = 0.8 * (state.dhi[k] * f.F_sky[cols] + state.sea_shortwave_up[k] * f.F_sea[cols])
    direct_power = float(area @ (q - diffuse))
    cube_v, _ = cube
    shadow = convex_shadow_area(cube_v, s, plane_z=1.0)
    expected = 0.8 * state.dni[k] * s[2] * (100.0 - shadow)
    lit = f.lit_fraction(TIMES[k])[np.searchsorted(f.traced.receivers, cols)]
    partial = int(np.sum((lit > 0) & (lit < 1)))
    se_area = np.sqrt(partial) * area.mean() / 8.0
    tol = 0.8 * state.dni[k] * s[2] * 4 * se_area
    assert abs(direct_power - expected) <= tol, (direct_power, expected, tol)
    assert 0 < partial < 0.2 * len(cols)
    # shaded faces get less than the open deck: fully dark faces exist and get only diffuse
    dark = lit == 0.0
    assert dark.sum() >= 10
    np.testing.assert_allclose(q[dark], diffuse[dark], rtol=1e-12)
    assert q[dark].max() < q[lit == 1.0].min()
    # the shadow's area in triangles agrees with the closed form to the partial-face band
    assert abs(np.sum(area * (1 - lit)) - shadow) <= 4 * se_area


@pytest.fixture(scope="module")
def boat(summer):
    ship = patrol_boat(edge_length=2.0)
    f, graph = forcing_of(ship, summer)
    return ship, f, graph


def test_direct_sun_on_a_closed_ship_equals_its_shadow_on_the_sea(boat, summer):
    # Every sun ray that meets a closed surface first meets exactly one lit front face, so
    # Σ_i A_i cos θ_i lit_i = A_⊥, the silhouette area seen from the sun = s_z × the shadow
    # area on the sea plane z = 0 (traced independently on a grid of the plane: the
    # waterplane inside the hull counts as shadow, as it must). Tolerance: 4 x the sum of
    # both standard errors (plane edge cells; face samples: partly lit faces, each with
    # SE ≤ A/(2 √16)).
    ship, f, graph = boat
    assert ship.is_watertight
    k = int(np.argmin(np.abs(TIMES - 9 * 3600.0)))
    s = f.sun_ship[k]
    air = f.traced.receivers
    cos = np.clip(f.traced.normals[air] @ s, 0.0, None)
    lit = f.lit_fraction(TIMES[k])
    a = f.traced.areas[air]
    direct_area = float(a @ (cos * lit))
    plane = ReceiverPlane(z=0.0, x_min=-45, x_max=45, y_min=-35, y_max=35, nx=450, ny=350,
                          samples_per_cell=2)
    shadow, se_plane = shadow_area_on_plane(f.traced.tracer, s, plane, seed=3)
    partial = (lit > 0) & (lit < 1)
    se_faces = np.sqrt(np.sum((a[partial] * cos[partial] / (2 * 4.0)) ** 2))
    assert abs(direct_area - s[2] * shadow) <= 4 * (s[2] * se_plane + se_faces), \
        (direct_area, s[2] * shadow, se_plane, se_faces)


def test_absorbed_shortwave_is_bounded_by_what_arrives(boat, summer):
    # Energy sanity over the whole day: the ship cannot absorb more than arrives
    # (direct on its silhouette + diffuse sky + sea-reflected on every dry face), and the
    # first bounce off the ship only adds (F ≥ 0, 1 − α ≥ 0).
    ship, f, graph = boat
    state = summer.at(TIMES)
    air = f.traced.receivers
    a = f.traced.areas[air]
    alpha = f.alpha[air]
    for k, t in enumerate(TIMES):
        q = f.absorbed_shortwave(t)[air]
        s = f.sun_ship[k]
        silhouette = float(a @ (np.clip(f.traced.normals[air] @ s, 0, None) * f.lit_fraction(t)))
        arriving = state.dni[k] * silhouette + (state.dhi[k] + state.sea_shortwave_up[k]) * a.sum()
        without_bounce = (state.dni[k] * np.clip(f.traced.normals[air] @ s, 0, None)
                          * f.lit_fraction(t) + state.dhi[k] * f.F_sky[air]
                          + state.sea_shortwave_up[k] * f.F_sea[air])
        assert float(a @ q) <= alpha.max() * arriving * (1 + 1e-12) + 1e-9
        assert np.all(q >= alpha * without_bounce * (1 - 1e-12) - 1e-9)
        assert float(a @ q) <= float(a @ without_bounce) * (1 + 1e-12) + 1e-9


def test_wetted_faces_get_no_sun_and_convect_to_the_sea(boat, summer):
    ship, f, graph = boat
    state = summer.at(TIMES)
    wet = ~f.outer_is_air
    assert wet.sum() > 100
    for t in TIMES[::4]:
        assert np.all(f.absorbed_shortwave(t)[wet] == 0.0)
    cond = f.conditions()["hull_wetted:outer"]
    assert type(cond).__name__ == "Convection"
    k = 20
    assert cond.temp_fluid(TIMES[k]) == state.temp_sea[k]
    # moored, no current: natural convection in water over the draught, O(100) W m-2 K-1
    # for ΔT ~ 0.1-1 K (Churchill-Chu in sea water), far above air-side values
    assert 20.0 < cond.h(TIMES[k]) < 500.0


def test_vertical_face_gets_half_sky_half_sea_and_the_beam(summer):
    # A lone vertical plate facing east (heading 0: x = bow = north, y = port = west, so the
    # normal is -y) 2-12 m above the sea. Closed forms: F_sky = F_sea = 1/2 (sky view of a
    # vertical face, also checked in tests/raytrace), lit fraction 1, cos θ = n·s. So
    # q = α (DNI max(n·s, 0) + (DHI + SW_sea↑)/2) up to the Monte-Carlo error of F_sky,
    # which enters as α |DHI − SW_sea↑| |F_sky − 1/2|; the area-mean F_sky over all rays has
    # binomial SE sqrt(1/4 / N_rays) and the tolerance is 4 SE. A wrong sign of the sun's
    # y component or a missing sea reflection moves q by far more (sky/sea mix-ups are
    # caught by the horizontal face above, where F_sea = 0).
    plate = rectangle([0, 0, 2.0], [10.0, 0, 0], [0, 0, 10.0], 4, 4)
    ship = scene_ship([plate], ["superstructure"])
    f, graph = forcing_of(ship, summer, absorptivity=0.7, rays_per_face=512)
    state = summer.at(TIMES)
    cols = f.patches["superstructure:outer"].cols
    np.testing.assert_allclose(f.traced.normals[cols], [[0.0, -1.0, 0.0]] * len(cols), atol=1e-12)
    a = f.traced.areas[cols]
    n_rays = 512 * len(cols)
    se = np.sqrt(0.25 / n_rays)
    for k in range(len(TIMES)):
        q = float(a @ f.absorbed_shortwave(TIMES[k])[cols] / a.sum())
        s = f.sun_ship[k]
        expected = 0.7 * (state.dni[k] * max(-s[1], 0.0)
                          + 0.5 * (state.dhi[k] + state.sea_shortwave_up[k]))
        tol = 0.7 * abs(state.dhi[k] - state.sea_shortwave_up[k]) * 4 * se + 1e-9
        assert abs(q - expected) <= tol, (TIMES[k] / 3600, q, expected, tol)
    morning = f.absorbed_shortwave(8 * 3600.0)[cols].mean()
    afternoon = f.absorbed_shortwave(16 * 3600.0)[cols].mean()
    assert morning > 2 * afternoon  # the east face is sunlit in the morning only


@pytest.mark.parametrize("interval", ["ending", "centred"])
def test_absorbed_sun_keeps_the_files_hourly_and_daily_integrals(interval):
    # A weather file's irradiance is each hour's energy (hour-ending in EPW / TMY files).
    # The environment spreads it over the hour by the sun's course on the forcing's 10-min
    # knots; the forcing's table (linear between its times, what the solver reads) then
    # carries every hour's and every day's energy exactly. On the lone open plate of the
    # test above (F_sky 1, lit fraction 1), the absorbed sun integrates to α × the file's
    # hourly values: 1e-9 relative (float64 tables; round-off only). Broken cloud, a dark
    # hour between sunny ones and 3 W m-2 in the hour of sunrise included.
    import pandas as pd

    from shipthermal.environment import Weather

    tz = "Etc/GMT-8"
    time = pd.date_range("2023-07-14 00:00", periods=73, freq="h", tz=tz)
    hour = time.hour.to_numpy()
    rng = np.random.default_rng(11)
    ghi = np.clip(950.0 * np.sin(np.pi * (hour - 5) / 14.0), 0.0, None) * rng.uniform(0.15, 1.0,
                                                                                      73)
    ghi[hour == 6] = 3.0
    ghi[(hour == 12) & (time.day == 15)] = 0.0
    w = Weather(time=time, temp_air=293.0 + 4 * np.sin(2 * np.pi * hour / 24), wind_speed=4.0,
                relative_humidity=75.0, wind_direction=200.0, cloud_cover=0.5,
                temp_sea=294.0, ghi=ghi, solar_interval=interval)
    env = Environment(38.91, 121.63, w)
    ship = scene_ship([rectangle([0, 0, 1.0], [10, 0, 0], [0, 10, 0], 3, 3)], ["deck"])
    span = 72 * 3600.0
    f, graph = forcing_of(ship, env, absorptivity=0.8, times=np.arange(0.0, span + 1.0, 600.0))
    cond = f.conditions()["deck:outer"]
    t = f.times
    q = np.array([cond.absorbed_shortwave(x)[0] for x in t])
    off = {"ending": 0.0, "centred": 1800.0}[interval]
    hourly = []
    for k in range(1, 72):                       # whole hours inside the record
        a, b = (k - 1) * 3600.0 + off, k * 3600.0 + off
        if b > span:
            break
        sel = (t >= a) & (t <= b)
        hourly.append((np.trapezoid(q[sel], t[sel]) / 3600.0, 0.8 * ghi[k]))
    got, want = np.array(hourly).T
    scale = 0.8 * ghi.max()
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * scale)
    # and the days (midnight to midnight) of the file's own hours
    for d in range(1, 3):
        sel = (t >= d * 86400.0 - 86400.0 + off) & (t <= d * 86400.0 + off)
        day = np.trapezoid(q[sel], t[sel])
        want_day = 0.8 * 3600.0 * ghi[(d - 1) * 24 + 1:d * 24 + 1].sum()
        assert day == pytest.approx(want_day, rel=1e-9)
    assert want.max() > 500.0 and (want == 0).any() and (want == 0.8 * 3.0).any()
