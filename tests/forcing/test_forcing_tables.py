"""Tables, time interpolation, ordering, exchange matrix, convection and input checks.

One patrol boat at 2 m edges (≈1300 triangles) is traced once per module; everything else
reuses its tracer (``traced=``), so the file runs in a few seconds.
"""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import brentq

from shipthermal.conditions import Convection, SurfaceBalance
from shipthermal.environment import Environment, climate_day
from shipthermal.environment import convection as conv
from shipthermal.environment.weather import Weather
from shipthermal.errors import InputError
from shipthermal.forcing import (
    ForcingSettings,
    PeriodicTable,
    build_ship_forcing,
    part_values,
    quasi_steady_surface_temperature,
)
from shipthermal.geometry import build_ship_mesh, patrol_boat
from shipthermal.parameters import LONGWAVE_EMISSIVITY, SOLAR_ABSORPTIVITY
from shipthermal.units import DAY, SIGMA

TIMES = np.arange(0.0, DAY, 1800.0)


@pytest.fixture(scope="module")
def day():
    return climate_day("summer")


@pytest.fixture(scope="module")
def env(day):
    return Environment.from_climate_day(day, ship_heading=45.0)


@pytest.fixture(scope="module")
def boat(env):
    ship = patrol_boat(edge_length=2.0)
    graph, _ = build_ship_mesh(ship)
    f = build_ship_forcing(ship, env, graph, ForcingSettings(dtype=np.float64), times=TIMES,
                           progress=False)
    return ship, graph, f


def callables(cond):
    return {k: v for k, v in vars(cond).items() if callable(v)}


def test_values_are_exact_at_table_times_and_linear_between(boat, env):
    ship, graph, f = boat
    state = env.at(TIMES)
    cond = f.conditions()
    deck = cond["deck:outer"]
    for k in (0, 13, 24, 47):
        t = TIMES[k]
        # exact: the table row itself, bit for bit
        assert np.array_equal(deck.absorbed_shortwave(t), f._sw["deck:outer"][k])
        assert np.array_equal(deck.h(t), f._h["deck:outer"][k])
        assert deck.temp_air(t) == state.temp_air[k]
        assert cond["hull_wetted:outer"].temp_fluid(t) == state.temp_sea[k]
    # halfway: the mean of the neighbours (to round-off), also across midnight
    for k in (13, 47):
        t0, t1 = TIMES[k], TIMES[(k + 1) % len(TIMES)] + (DAY if k == 47 else 0.0)
        mid = deck.absorbed_shortwave(0.5 * (t0 + t1))
        np.testing.assert_allclose(
            mid, 0.5 * (deck.absorbed_shortwave(t0) + deck.absorbed_shortwave(t1)),
            rtol=1e-12, atol=1e-12)
        lw = deck.longwave_in(0.25 * t0 + 0.75 * t1)
        np.testing.assert_allclose(lw, 0.25 * deck.longwave_in(t0) + 0.75 * deck.longwave_in(t1),
                                   rtol=1e-12)


def test_periodic_folding_gives_identical_values(boat):
    ship, graph, f = boat
    # times on a 1/8 s grid: t + k·86400 is then exact in float64 (as the solver's clock
    # n·Δt is), and so is the folding (np.mod of floats is exact); an arbitrary real t
    # would already be rounded when 86400 k is added, before any folding
    rng = np.random.default_rng(1)
    ts = np.concatenate([rng.integers(0, 8 * 86400, 20) / 8.0,
                         [0.0, DAY - 0.125, TIMES[-1] + 900.0, 3.5]])
    for name, cond in f.conditions().items():
        for field, fn in callables(cond).items():
            for t in ts:
                a = fn(t)
                for day in (1, 9, 10):
                    assert np.array_equal(fn(t + day * DAY), a), (name, field, t, day)


def test_shapes_and_order_follow_patch_faces(boat):
    ship, graph, f = boat
    cond = f.conditions()
    assert set(cond) == set(graph.patch_names)
    t = 12.5 * 3600.0
    q_all = f.absorbed_shortwave(t)
    for name, c in cond.items():
        bf = graph.patch_faces(name)
        for field, fn in callables(c).items():
            v = np.asarray(fn(t))
            assert v.ndim == 0 or v.shape == (len(bf),), (name, field, v.shape)
        if name.endswith(":outer"):
            cols = np.searchsorted(f.outer_bfaces, bf)
            assert np.array_equal(f.outer_bfaces[cols], bf)
            # the traced triangle of each column is the graph's boundary face (shell graphs:
            # outer face b is surface triangle b)
            np.testing.assert_allclose(f.traced.centroids[cols], graph.bface_centroid[bf],
                                       atol=1e-9)
            np.testing.assert_allclose(f.traced.normals[cols], graph.bface_normal[bf], atol=1e-9)
            assert np.array_equal(ship.faces.shape[0] > bf, np.ones(len(bf), bool))
            if isinstance(c, SurfaceBalance):
                assert np.array_equal(c.absorbed_shortwave(t), q_all[cols])
        else:
            assert isinstance(c, Convection)
            part = name.split(":")[0]
            assert c.temp_fluid == ship.compartment_temperature[part]


def test_sunlit_side_gets_more_than_shaded_side_and_nothing_at_night(boat):
    # Guards the sign of the sun vector in the ship frame: in the morning the sun is in the
    # east; heading 45° puts east on the starboard bow (-y side of the ship), so starboard
    # topsides must absorb more than port ones, and at 15:00 local (sun in the SW) port.
    ship, graph, f = boat
    cols = f.patches["hull_dry:outer"].cols
    ny = f.traced.normals[cols, 1]
    a = f.traced.areas[cols]

    def side_mean(t, sign):
        sel = np.sign(ny) == sign
        return float(a[sel] @ f.absorbed_shortwave(t)[cols][sel] / a[sel].sum())

    assert side_mean(8 * 3600.0, -1) > 1.5 * side_mean(8 * 3600.0, +1)
    assert side_mean(16 * 3600.0, +1) > 1.5 * side_mean(16 * 3600.0, -1)
    assert np.all(f.absorbed_shortwave(1 * 3600.0) == 0.0)


def test_dark_intervals_are_those_without_shortwave_anywhere(boat):
    # ShipForcing.dark against the interpolated absorbed short-wave itself, sampled every
    # 60 s over each 30 min interval of the day and across midnight
    ship, graph, f = boat
    for start in np.arange(-3 * 1800.0, DAY, 1800.0):
        sampled = max(np.max(f.absorbed_shortwave(t))
                      for t in np.linspace(start, start + 1800.0, 31))
        assert f.dark(start, start + 1800.0) == (sampled == 0.0), start
    assert f.dark(0.0, 3600.0) and not f.dark(11 * 3600.0, 11.5 * 3600.0)


def test_exchange_matrix_is_symmetric_reciprocal_and_consistent(boat):
    ship, graph, f = boat
    bfaces, R = f.radiative_exchange()
    assert sp.issparse(R) and R.shape == (len(bfaces), len(bfaces))
    assert (R != R.T).nnz == 0
    assert np.all(np.isin(bfaces, f.outer_bfaces))
    cols = np.searchsorted(f.outer_bfaces, bfaces)
    A = f.traced.areas[cols]
    eps = f.epsilon[cols]
    F = f.traced.view.F_faces.tocsr()[cols][:, cols]
    # R_ij = A_i ε_i ε_j F_ij with the reciprocity-imposed F (A_i F_ij = A_j F_ji)
    expected = sp.diags(A * eps) @ F @ sp.diags(eps)
    assert abs(R - 0.5 * (expected + expected.T)).max() <= 1e-12 * abs(R).max()
    # exchange conserves energy for any temperatures: Σ_i Σ_j R_ij (T_j⁴ − T_i⁴) = 0
    T4 = np.random.default_rng(0).uniform(250, 350, len(bfaces)) ** 4
    net = SIGMA * (R @ T4 - np.asarray(R.sum(axis=1)).ravel() * T4)
    assert abs(net.sum()) <= 1e-10 * np.abs(net).sum()
    # with the exchange wired, the balance keeps only the environment share of emission:
    # ε_eff = ε (F_sky + F_sea) and the face's total emission coefficient with the
    # exchange, ε_eff A + Σ_j R_ij, never exceeds ε A (ε_j ≤ 1)
    deck = f.patches["deck:outer"].cols
    c_ex = f.conditions(with_exchange=True)["deck:outer"]
    c_no = f.conditions(with_exchange=False)["deck:outer"]
    np.testing.assert_allclose(c_ex.emissivity, f.epsilon[deck] * (f.F_sky + f.F_sea)[deck])
    np.testing.assert_allclose(c_no.emissivity, f.epsilon[deck])
    row = np.zeros(len(f.outer_bfaces))
    row[cols] = np.asarray(R.sum(axis=1)).ravel()
    total = c_ex.emissivity * f.traced.areas[deck] + row[deck]
    assert np.all(total <= f.epsilon[deck] * f.traced.areas[deck] * (1 + 1e-12))
    # absorbed long-wave from the environment is the same either way where no ship is seen
    t = 6 * 3600.0
    open_ = f.F_ship[deck] == 0
    assert open_.sum() > 10
    np.testing.assert_allclose((c_ex.emissivity * c_ex.longwave_in(t))[open_],
                               (c_no.emissivity * c_no.longwave_in(t))[open_], rtol=1e-12)


def test_convection_coefficients(boat, env, day):
    ship, graph, f = boat
    t = 14 * 3600.0
    cond = f.conditions()
    # inner faces: ISO 6946 Annex C convective constants plus ε 4σT_m³ (ε = 0.9); T_m lies
    # within ±40 K of the room, so the radiative part is 4.6-6.4 W m-2 K-1 and the
    # convective remainder must be one of 0.7 / 2.5 / 5.0 to within that band's width
    for name in ("deck:inner", "superstructure:inner"):
        h = cond[name].h(t)
        rad = 0.9 * 4 * SIGMA * ship.compartment_temperature[name.split(":")[0]] ** 3
        hc = h - rad
        assert np.all(np.min(np.abs(hc[:, None] - [0.7, 2.5, 5.0]), axis=1) < 0.9), name
    # a sun-heated deck over a cooler room: heat flows down through the ceiling -> 0.7
    hc_deck = cond["deck:inner"].h(13 * 3600.0) - 0.9 * 4 * SIGMA * 295.15 ** 3
    assert np.median(hc_deck) < 1.6
    # outer air faces: at least the natural-convection floor, at most the forced value of
    # a 10 m/s wind on the shortest plate, and stronger wind means larger h
    h_deck = f.convection_coefficient("deck:outer", t)
    assert np.all(h_deck > 0.5) and np.all(h_deck < 60.0)
    windy = Environment.from_climate_day(day.perturbed(wind=4.0), ship_heading=45.0)
    g = build_ship_forcing(ship, windy, graph, ForcingSettings(dtype=np.float64), times=TIMES,
                           traced=f.traced)
    assert g.n_rays == f.n_rays  # the lit fractions came from the cache: nothing re-traced
    assert np.array_equal(g.absorbed_shortwave(t), f.absorbed_shortwave(t))
    assert np.all(g.convection_coefficient("deck:outer", t) > h_deck)
    assert g.summary().loc["deck", "h_mean"] > f.summary().loc["deck", "h_mean"] + 2.0


def test_summary_means_are_those_of_the_patches_coefficients(boat):
    """The summary's outer convection mean of a part: the area mean of every air patch's
    coefficient at every table time, averaged over the day (trapezoid, wrapped), each
    patch's coefficients asked on their own, patch after patch."""
    _, _, f = boat
    df = f.summary()
    A = f.traced.areas
    for part in df.index:
        air = [p for p in f.patches.values() if p.part == part and p.kind == "air"]
        if not air:
            continue
        aa = A[np.concatenate([p.cols for p in air])]
        hh = np.concatenate([np.stack([f.convection_coefficient(p.name, t) for t in f.times])
                             for p in air], axis=1)
        mean_t = hh @ aa / aa.sum()
        y = np.r_[mean_t, mean_t[:1]]
        t = np.r_[f.times, f.times[0] + 86400.0]
        expect = np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)) / 86400.0
        assert df.loc[part, "h_mean"] == pytest.approx(expect, rel=1e-14), part


def test_quasi_steady_surface_temperature_solves_the_balance():
    # independent root finder (scipy brentq) on the same balance, face by face
    rng = np.random.default_rng(2)
    n = 40
    q = rng.uniform(0, 800, n)
    eps = rng.uniform(0.3, 0.95, n)
    lw = rng.uniform(250, 420, n)
    ta = rng.uniform(265, 305, n)
    nz = rng.uniform(-1, 1, n)
    u = rng.uniform(0, 8, n)
    ub = rng.uniform(0.5, 8, n)

    def h(temp, i=slice(None)):
        return conv.h_exterior_air(temp, ta[i], nz[i], u[i], 20.0, 5.0, 3.0)

    ts = quasi_steady_surface_temperature(q, eps, lw, ta, h, ub, 295.15)
    for i in range(n):
        def bal(x, i=i):
            return (q[i] + eps[i] * (lw[i] - SIGMA * x ** 4) + h(np.array(x), i) * (ta[i] - x)
                    + ub[i] * (295.15 - x))
        root = brentq(bal, 150.0, 450.0, xtol=1e-10)
        # 4 Newton steps from T_air: measured worst case ~0.3 K (calm wind, full sun);
        # the coefficient it feeds varies as ΔT^(1/3), i.e. by < 0.2 %
        assert abs(ts[i] - root) < 0.5, (i, ts[i], root)


def test_periodic_table_weights():
    tab = PeriodicTable(np.array([0.0, 100.0, 400.0]), period=1000.0)
    assert tab.weights(100.0) == (1, 2, 0.0)
    assert tab.weights(250.0) == (1, 2, 0.5)
    assert tab.weights(700.0) == (2, 0, 0.5)           # wraps to the next day's 0
    assert tab.weights(1250.0) == (1, 2, 0.5)
    assert tab.weights(-300.0) == (2, 0, 0.5)
    series = np.array([1.0, 2.0, 5.0])
    assert tab(series, 700.0) == 3.0


def test_part_values_and_defaults():
    names = ("hull_wetted", "hull_dry", "deck", "superstructure", "superstructure_mast")
    a = part_values(names, SOLAR_ABSORPTIVITY, {"superstructure": 0.5, "hull": 0.6,
                                                "superstructure_mast": 0.4}, "absorptivity", 0, 1)
    assert a == {"hull_wetted": 0.6, "hull_dry": 0.6, "deck": SOLAR_ABSORPTIVITY["deck"],
                 "superstructure": 0.5, "superstructure_mast": 0.4}
    e = part_values(names, LONGWAVE_EMISSIVITY, 0.95, "emissivity", 0, 1, low_open=True)
    assert set(e.values()) == {0.95}


@pytest.mark.parametrize("kwargs, field", [
    (dict(absorptivity={"funnel": 0.5}), "absorptivity['funnel']"),
    (dict(absorptivity={"deck": 1.2}), "absorptivity['deck']"),
    (dict(absorptivity=-0.1), "absorptivity"),
    (dict(emissivity={"superstructure": 0.0}), "emissivity['superstructure']"),
    (dict(times=np.arange(0.0, 43200.0, 600.0)), "times"),       # half a day
    (dict(times=np.arange(0.0, DAY, 7200.0)), "times"),          # 2 h gaps
    (dict(times=[0.0, 3600.0, 1800.0]), "times"),                 # not increasing
    (dict(times=np.arange(-600.0, DAY, 600.0)), "times[0]"),      # outside the day
    (dict(samples_per_face=0), "samples_per_face"),
    (dict(current_speed=-1.0), "current_speed"),
    (dict(convection="jurges"), "convection.model"),
    (dict(convection={"deck": "flat"}), "convection.model['deck']"),
    (dict(roughness="sandpaper"), "convection.roughness"),
])
def test_bad_inputs_name_the_field(boat, env, kwargs, field):
    ship, graph, f = boat
    with pytest.raises(InputError) as err:
        options = dict(kwargs)
        times = options.pop("times", None)
        build_ship_forcing(ship, env, graph, ForcingSettings(**options), times=times)
    assert err.value.field == field


def test_weather_record_gets_a_table_over_the_record(boat, day):
    """Non-periodic weather: one table over the record, not folded. Over the same hours as
    the design day it must give the design day's tables, row for row."""
    from shipthermal.forcing import RecordTable

    ship, graph, f = boat
    w = day.weather()
    real = Weather(time=w.time, temp_air=w.temp_air, relative_humidity=w.relative_humidity,
                   wind_speed=w.wind_speed, wind_direction=w.wind_direction,
                   cloud_cover=w.cloud_cover, temp_sea=w.temp_sea, periodic=False)
    env = Environment(day.latitude, day.longitude, real, altitude=day.altitude)
    periodic = Environment.from_climate_day(day)
    times = np.arange(0.0, 23 * 3600.0 + 1.0, 1800.0)
    rec = build_ship_forcing(ship, env, graph, ForcingSettings(dtype=np.float64), times=times,
                             traced=f.traced)
    per = build_ship_forcing(ship, periodic, graph, ForcingSettings(dtype=np.float64),
                             times=np.arange(0.0, DAY, 1800.0), traced=f.traced)
    assert isinstance(rec.table, RecordTable) and rec.table.period == 23 * 3600.0
    np.testing.assert_allclose(rec.temp_air, per.temp_air[:len(times)], rtol=1e-12)
    for t in (0.0, 3600.0 * 12.25, 3600.0 * 22.5):
        np.testing.assert_allclose(rec.absorbed_shortwave(t), per.absorbed_shortwave(t),
                                   rtol=1e-9, atol=1e-9)
    # past the record's end the last row is held (a periodic table would wrap to 00:00)
    np.testing.assert_allclose(rec.absorbed_shortwave(23.9 * 3600.0),
                               rec.absorbed_shortwave(23 * 3600.0), rtol=0, atol=0)
    with pytest.raises(InputError) as err:
        build_ship_forcing(ship, env, graph, times=times[:-4], traced=f.traced)
    assert err.value.field == "times" and "must cover the weather record" in str(err.value)
