"""Convection models of the air faces and the one source of the surface optics.

One patrol boat at 2 m edges is traced once; the other builds reuse its tracer.
"""

import numpy as np
import pytest

from shipthermal.environment import Environment, climate_day
from shipthermal.environment import convection as conv
from shipthermal.errors import InputError
from shipthermal.forcing import (ForcingSettings, build_ship_forcing,
                                 quasi_steady_surface_temperature)
from shipthermal.geometry import build_ship_mesh, patrol_boat
from shipthermal.parameters import LONGWAVE_EMISSIVITY, SOLAR_ABSORPTIVITY
from shipthermal.units import DAY, SIGMA

TIMES = np.arange(0.0, DAY, 1800.0)


@pytest.fixture(scope="module")
def boat():
    env = Environment.from_climate_day(climate_day("summer"), ship_heading=45.0)
    ship = patrol_boat(edge_length=2.0)
    graph, _ = build_ship_mesh(ship)
    f = build_ship_forcing(ship, env, graph, ForcingSettings(dtype=np.float64), times=TIMES,
                           progress=False)
    return ship, env, graph, f


def _air_table(f, tables=None):
    """(n_times, K) table of the air faces (default: the forced part of the coefficient)."""
    tables = f._h if tables is None else tables
    out = np.full((len(f.times), len(f.outer_bfaces)), np.nan)
    for name, p in f.patches.items():
        if p.kind == "air":
            out[:, p.cols] = tables[name]
    return out[:, f.outer_is_air]


def _air_h_table(f):
    """(n_times, K) convection coefficients of the air faces at the quasi-steady estimate
    (the forced part with each model's law)."""
    out = np.full((len(f.times), len(f.outer_bfaces)), np.nan)
    for name, p in f.patches.items():
        if p.kind == "air":
            out[:, p.cols] = np.stack([f.convection_coefficient(name, t) for t in f.times])
    return out[:, f.outer_is_air]


def _apparent_wind(f, env, state):
    """Apparent wind speed [m/s] and angle off the bow [deg] at every air face's height."""
    air = np.flatnonzero(f.outer_is_air)
    z = np.maximum(f.traced.centroids[air, 2], 0.0)
    u = conv.wind_speed_at_height(state.wind_speed[:, None], z[None, :])
    speed, _, off_bow = conv.relative_wind(u, state.wind_direction[:, None], env.ship_speed,
                                           env.ship_heading)
    return speed, off_bow


def test_default_model_is_the_turbulent_churchill_flat_plate_bit_for_bit(boat):
    # the default tables are those of the documented physics, composed here from the public
    # correlation functions and nothing of the forcing's own stages: apparent wind at face
    # height over the part's box length along it, h_exterior_air at the quasi-steady
    # estimate with the layup + ISO 6946 back side. The tables hold the estimate and the
    # forced part; the solver adds natural convection at the solved temperature.
    ship, env, graph, f = boat
    assert f.convection_model == conv.DEFAULT_CONVECTION_MODEL
    state = env.at(f.times)
    air = np.flatnonzero(f.outer_is_air)
    speed, off_bow = _apparent_wind(f, env, state)
    names = f.part_names
    part = f.outer_part[air]
    tri = f.traced.vertices[f.traced.faces]
    edge = float(np.sqrt(np.median(f.traced.areas) * 2.0))
    box = {}
    for k, n in enumerate(names):
        sel = f.outer_part == k
        if sel.any():
            pts = tri[sel].reshape(-1, 3)
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            bx, by = hi[0] - lo[0], hi[1] - lo[1]
            bz = hi[2] - (max(lo[2], 0.0) if hi[2] > 0 else lo[2])
            box[k] = (max(bx, edge), max(by, edge), max(bz, edge),
                      max(bx * by / (2.0 * (bx + by)), edge))
    lx, ly, lv, lh = (np.array([box[k][i] for k in part]) for i in range(4))
    ang = np.radians(off_bow)
    length = lx * np.abs(np.cos(ang)) + ly * np.abs(np.sin(ang))
    t_room = np.array([ship.compartment_temperature[names[k]] for k in part])
    h_in = 2.5 + 0.9 * 4.0 * SIGMA * t_room ** 3
    u_back = 1.0 / (np.array([ship.layups[names[k]].thermal_resistance for k in part])
                    + 1.0 / h_in)
    share = (f.F_sky + f.F_sea)[air]
    lw = f.F_sky[air] * state.longwave_down[:, None] + f.F_sea[air] * state.sea_longwave_up[:, None]
    absorbed = np.stack([f.absorbed_shortwave(t)[air] for t in f.times])
    ta = state.temp_air[:, None]
    nz = f.traced.normals[air, 2]

    assert conv.DEFAULT_CONVECTION_MODEL == "flat_plate_turbulent"

    def h_of(ts):
        return conv.h_exterior_air_turbulent(ts, ta, nz, speed, length, lv, lh)

    inv_share = np.divide(1.0, share, out=np.zeros_like(share), where=share > 0)
    ts = quasi_steady_surface_temperature(absorbed, f.epsilon[air] * share, lw * inv_share, ta,
                                          h_of, u_back, t_room)
    np.testing.assert_array_equal(_air_table(f, f._est), ts)
    props = conv.air_properties(0.5 * (ts + ta))
    np.testing.assert_array_equal(_air_table(f), conv.h_forced(speed, length, props,
                                                               boundary_layer="turbulent"))
    # the forced part with the law: the coefficient at the estimate (the law's air
    # properties are those of the estimate's film temperature, as the correlation's)
    np.testing.assert_allclose(_air_h_table(f), h_of(ts), rtol=1e-12)
    # choosing it by name or passing the model object changes nothing
    name = conv.DEFAULT_CONVECTION_MODEL
    for model in (name, conv.CONVECTION_MODELS[name]):
        g = build_ship_forcing(ship, env, graph,
                               ForcingSettings(dtype=np.float64, convection=model),
                               times=TIMES, traced=f.traced)
        np.testing.assert_array_equal(_air_table(g), _air_table(f))


def test_iso6946_model_is_four_plus_four_v_at_the_apparent_wind(boat):
    # ISO 6946:2017 Annex C eq. C.2: h_ce = 4 + 4 v with v the wind at the surface
    ship, env, graph, f = boat
    g = build_ship_forcing(ship, env, graph,
                           ForcingSettings(dtype=np.float64, convection="iso6946"),
                           times=TIMES, traced=f.traced)
    assert g.convection_model == "iso6946"
    speed, _ = _apparent_wind(g, env, env.at(g.times))
    np.testing.assert_allclose(_air_table(g), 4.0 + 4.0 * speed, rtol=1e-14)
    np.testing.assert_allclose(_air_h_table(g), 4.0 + 4.0 * speed, rtol=1e-14)
    # the short-wave does not depend on the convection model
    for t in (6 * 3600.0, 13 * 3600.0):
        assert np.array_equal(g.absorbed_shortwave(t), f.absorbed_shortwave(t))


def test_a_users_own_correlation_needs_only_its_terms(boat):
    # a correlation the package does not know: a ConvectionModel with its terms alone (no
    # closed-form twin, no registry entry) runs through the forcing; written as ISO 6946's
    # 4 + 4 v per part on the superstructure, it gives the registered model's tables
    ship, env, graph, f = boat
    from shipthermal.conditions import LAW_PARAMETERS, ConvectionLaw

    def terms(temp_film, flow, law=True):
        shape = np.broadcast_shapes(np.shape(temp_film), np.shape(flow.wind_speed))
        hf = np.broadcast_to(4.0 + 4.0 * np.abs(np.asarray(flow.wind_speed, float)), shape)
        natural = np.zeros(shape + (2, len(LAW_PARAMETERS)))
        return hf, (ConvectionLaw(natural, 1.0, 1.0, 0.0) if law else None)

    mine = conv.ConvectionModel("my_4_plus_4v", terms, source="test", validity="test")
    ts, ta = np.array([300.0, 280.0]), np.array([290.0, 290.0])
    flow = conv.ExteriorFlow(normal_z=np.array([0.0, 1.0]), wind_speed=np.array([2.0, 5.0]))
    np.testing.assert_array_equal(mine.h_direct(ts, ta, flow), [12.0, 24.0])
    tables = {}
    for model in ("iso6946", mine):
        g = build_ship_forcing(ship, env, graph, ForcingSettings(
            dtype=np.float64, convection={"superstructure": model}), times=TIMES,
            traced=f.traced)
        name = getattr(model, "name", model)
        tables[name] = (_air_table(g), _air_h_table(g))
        assert name in g.convection_models.values()
    for a, b in zip(tables["iso6946"], tables["my_4_plus_4v"]):
        np.testing.assert_array_equal(a, b)


def test_unknown_model_lists_the_known_ones(boat):
    ship, env, graph, f = boat
    with pytest.raises(InputError) as err:
        build_ship_forcing(ship, env, graph, ForcingSettings(convection="jurges"), times=TIMES,
                           traced=f.traced)
    assert err.value.field == "convection.model" and err.value.value == "jurges"
    for name in conv.CONVECTION_MODELS:
        assert name in str(err.value)
    with pytest.raises(InputError) as err:
        build_ship_forcing(ship, env, graph, ForcingSettings(convection={"dek": "doe2"}),
                           times=TIMES, traced=f.traced)
    assert err.value.field == "convection.model['dek']"
    with pytest.raises(InputError) as err:
        build_ship_forcing(ship, env, graph, ForcingSettings(convection={"deck": "doe3"}),
                           times=TIMES, traced=f.traced)
    assert err.value.field == "convection.model['deck']" and "doe2" in err.value.allowed


def test_direct_api_takes_the_parameter_module_optics(boat):
    # one source: the forcing's defaults are the parameter module's per part
    ship, env, graph, f = boat
    for part in f.part_names:
        main = "hull" if part.startswith("hull") else part.split("_")[0]
        assert f.emissivity[part] == LONGWAVE_EMISSIVITY[main]
        assert f.absorptivity[part] == SOLAR_ABSORPTIVITY[main]
    assert LONGWAVE_EMISSIVITY["deck"] == 0.95


def test_scenario_and_direct_api_give_the_deck_the_same_emissivity(boat):
    # the default scenario and the forcing's direct API must agree on every part's
    # broadband emissivity and solar absorptivity (the deck once differed: 0.95 vs 0.90)
    from shipthermal.app.scenario import default_scenario

    ship, env, graph, f = boat
    sc = default_scenario("summer")
    for part in f.part_names:
        assert sc.longwave_emissivity(part) == f.emissivity[part], part
        assert sc.solar_absorptivity(part) == f.absorptivity[part], part


def test_diurnal_settings_choose_the_model():
    # the model named in the run settings is the one the forcing of the run uses
    from shipthermal.diurnal import DiurnalSettings, run_diurnal

    env = Environment.from_climate_day(climate_day("winter"))
    settings = DiurnalSettings(time_step=1800.0, output_interval=3600.0, spinup_max_days=1,
                               rays_per_face=16, samples_per_face=4, convection="iso6946")
    res = run_diurnal(patrol_boat(edge_length=4.0), env, settings, progress=False)
    assert res.forcing.convection_model == "iso6946"
    speed, _ = _apparent_wind(res.forcing, env, env.at(res.forcing.times))
    np.testing.assert_allclose(_air_table(res.forcing), 4.0 + 4.0 * speed, rtol=1e-6)


def test_scenario_key_chooses_the_model_and_names_the_allowed_ones():
    from shipthermal.app.scenario import loads_scenario
    from shipthermal.app.thermal import settings_from_scenario

    sc = loads_scenario('[convection]\nmodel = "flat_plate_turbulent"\n')
    assert settings_from_scenario(sc).convection == "flat_plate_turbulent"
    with pytest.raises(InputError) as err:
        loads_scenario('[convection]\nmodel = "jurges"\n')
    assert err.value.field == "convection.model" and err.value.value == "jurges"
    for name in conv.CONVECTION_MODELS:
        assert repr(name) in str(err.value)


def test_tables_do_not_depend_on_threads_or_row_blocks(boat, monkeypatch):
    """The tables are built in blocks of rows, on numba's thread budget: blocks of five
    rows on two threads give the same tables, bit for bit, as one block."""
    import numba

    import shipthermal.forcing.build as forcing_build

    ship, env, graph, f = boat
    monkeypatch.setattr(forcing_build, "_ROW_CHUNK_ELEMENTS", 5 * len(f.outer_bfaces))
    threads = numba.get_num_threads()
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    try:
        g = build_ship_forcing(ship, env, graph, ForcingSettings(dtype=np.float64),
                               times=TIMES, traced=f.traced, progress=False)
    finally:
        numba.set_num_threads(threads)
    assert set(g._sw) == set(f._sw) and set(g._h) == set(f._h) and set(g._est) == set(f._est)
    for name in f._sw:
        np.testing.assert_array_equal(g._sw[name], f._sw[name])
    for name in f._h:
        np.testing.assert_array_equal(g._h[name], f._h[name])
    for name in f._est:
        np.testing.assert_array_equal(g._est[name], f._est[name])


def test_models_per_part_with_their_roughness(boat):
    # DOE-2 on the deck (a rough covering), TARP on the superstructure, the default on the
    # hull: each part's coefficient at the estimate is its correlation's, with the part's
    # roughness multiplier and each face's windward / leeward side of the apparent wind
    ship, env, graph, f = boat
    g = build_ship_forcing(ship, env, graph,
                           ForcingSettings(dtype=np.float64,
                                           convection={"deck": "doe2", "superstructure": "tarp"},
                                           roughness={"deck": "rough"}),
                           times=TIMES, traced=f.traced)
    models = g.convection_models
    assert models["deck"] == "doe2" and models["hull_dry"] == conv.DEFAULT_CONVECTION_MODEL
    assert all(m == "tarp" for p, m in models.items() if p.startswith("superstructure"))
    state = env.at(g.times)
    speed, off_bow = _apparent_wind(g, env, state)
    air = np.flatnonzero(g.outer_is_air)
    normals = g.traced.normals[air]
    ang = np.radians(off_bow)
    windward = conv.is_windward(normals[None], np.stack([np.cos(ang), -np.sin(ang)], -1))
    ts, ta = _air_table(g, g._est), state.temp_air[:, None]
    h = _air_h_table(g)
    part = np.array(g.part_names)[g.outer_part[air]]
    deck = part == "deck"
    want = conv.h_exterior_doe2(ts, ta, normals[:, 2], speed, windward,
                                conv.ROUGHNESS_MULTIPLIERS["rough"])
    np.testing.assert_allclose(h[:, deck], want[:, deck], rtol=1e-6)
    sup = np.char.startswith(part.astype(str), "superstructure")
    p_over_a = g.air_faces.convection.perimeter_over_area
    want = conv.h_exterior_tarp(ts, ta, normals[:, 2], speed, p_over_a, windward,
                                conv.ROUGHNESS_MULTIPLIERS["smooth"])
    np.testing.assert_allclose(h[:, sup], want[:, sup], rtol=1e-6)
    # faces on both sides of the wind, and the hull keeps the default's table
    assert windward[:, sup].any() and (~windward[:, sup]).any()
    hull = ~deck & ~sup
    np.testing.assert_array_equal(_air_table(g)[:, hull], _air_table(f)[:, hull])
    # (f's one model takes every air face as a view, g's three models their own columns:
    # the equality above holds between those two ways of taking the columns)
    assert [cols for _, cols in f.air_faces.convection.groups()] == [slice(None)]
    cols = [c for _, c in g.air_faces.convection.groups()]
    assert len(cols) == 3 and sorted(np.concatenate(cols)) == list(range(len(air)))


def test_the_natural_law_between_table_times_is_each_patchs_own(boat):
    # the solver's law of a film-dependent model is evaluated once for all the patches
    # that use it: each patch gets its own faces' law at its own estimate's film
    # temperature, interpolated linearly between the table times, and the values handed
    # out are read-only (the patches share them)
    ship, env, graph, f = boat
    flat = [n for n, p in f.patches.items() if p.kind == "air"]
    assert len(flat) > 1
    i, w = 5, 0.3
    t = (1.0 - w) * f.times[i] + w * f.times[i + 1]
    for name in flat:
        law = f.convection_law(name)
        pos = f._air_positions(name)
        air = f.air_faces
        flow = conv.ExteriorFlow(normal_z=air.normals[pos, 2], wind_speed=0.0,
                                 length_vertical=air.lengths.vertical[pos],
                                 length_horizontal=air.lengths.horizontal[pos])
        model = conv.convection_model(conv.DEFAULT_CONVECTION_MODEL)
        rows = [model.natural_law(0.5 * (f._est[name][k] + f.temp_air[k]), flow)
                for k in (i, i + 1)]
        got = law.natural(t)
        np.testing.assert_allclose(got, (1.0 - w) * rows[0] + w * rows[1], rtol=1e-14,
                                   atol=0.0)
        np.testing.assert_array_equal(law.natural(f.times[i]), rows[0])
        assert not got.flags.writeable
