"""Spin-up with a lead-in and a periodicity check against plain day-by-day stepping, and the
per-face surface balance kernel against the balance it solves."""

import numpy as np
import pytest

from shipthermal.diurnal import (NIGHT_SETTLE, SPINUP_LEAD_IN_STEP, DiurnalSettings,
                                 lead_in_seconds, lead_in_step, night_steps, run_diurnal)
from shipthermal.environment import Environment, climate_day
from shipthermal.geometry import patrol_boat
from shipthermal.units import DAY, SIGMA


@pytest.fixture(scope="module")
def runs():
    ship = patrol_boat(edge_length=3.0)
    env = Environment.from_climate_day(climate_day("summer"), ship_heading=90.0)
    base = dict(time_step=600.0, output_interval=1800.0, rays_per_face=32, samples_per_face=8)
    fast = run_diurnal(ship, env, DiurnalSettings(spinup_tolerance=0.01, spinup_max_days=4,
                                                  **base), progress=False)
    # Plain stepping: from midnight, day after day until a day repeats to 1e-8 K.
    plain = run_diurnal(ship, env, DiurnalSettings(spinup_tolerance=1e-8, spinup_max_days=8,
                                                   lead_in=0.0, **base),
                        progress=False, traced=fast.forcing.traced, graph=fast.graph)
    return fast, plain


def test_lead_in_reaches_the_periodic_day_of_plain_stepping(runs):
    fast, plain = runs
    print(f"lead-in run: {fast.days} day(s), defects {fast.day_changes}; plain stepping: "
          f"{plain.days} days, defects {plain.day_changes}")
    assert plain.converged and plain.days >= 2 and plain.day_changes[-1] <= 1e-8
    assert fast.converged and fast.days < plain.days
    diff = np.max(np.abs(fast.results.face_temperature - plain.results.face_temperature))
    diff_cells = np.max(np.abs(fast.results.cell_temperature - plain.results.cell_temperature))
    print(f"recorded day: max |ΔT| faces {diff:.2e} K, cells {diff_cells:.2e} K, "
          f"last defect {fast.day_changes[-1]:.2e} K")
    # The defect of the recorded day bounds its distance to the periodic day (maximum
    # principle; the 1e-8 K of the plain run's own defect aside).
    assert diff_cells <= fast.day_changes[-1] + 1e-8
    assert diff <= fast.day_changes[-1] + 1e-8
    np.testing.assert_array_equal(fast.results.times, plain.results.times)


def test_plain_stepping_without_lead_in_starts_at_midnight(runs):
    _, plain = runs
    assert lead_in_seconds(plain.settings) == 0.0
    assert plain.energy.time[0] == 600.0 and len(plain.energy.time) == plain.days * 144
    # a day that had not repeated was not accepted
    assert all(c > 1e-8 for c in plain.day_changes[:-1])


def test_lead_in_rounds_up_to_whole_output_intervals():
    s = DiurnalSettings(time_step=300.0, output_interval=1800.0, lead_in=3700.0)
    assert lead_in_seconds(s) == 5400.0
    assert lead_in_seconds(DiurnalSettings(lead_in=0.0)) == 0.0
    with pytest.raises(Exception, match="lead_in"):
        DiurnalSettings(lead_in=DAY)


def test_lead_in_step_divides_the_recording_interval():
    # 5400 s in steps of at most SPINUP_LEAD_IN_STEP (900 s): 6 steps
    s = DiurnalSettings(time_step=300.0, output_interval=1800.0, lead_in=3700.0)
    assert lead_in_step(s) == 900.0 == SPINUP_LEAD_IN_STEP
    # 600 s output → 3 × 600 s lead-in (1800 s) in 600 s steps (a 900 s step would pass
    # over recording times of the one simulation that runs the lead-in and the days)
    s = DiurnalSettings(time_step=120.0, output_interval=600.0, lead_in=1700.0)
    assert lead_in_seconds(s) == 1800.0 and lead_in_step(s) == 600.0
    # a lead-in that 900 s does not divide: the longest shorter step that does
    s = DiurnalSettings(time_step=300.0, output_interval=1500.0, lead_in=1500.0)
    assert lead_in_step(s) == 750.0
    # never shorter than the run's own step; no lead-in, the run's step
    assert lead_in_step(DiurnalSettings(time_step=1800.0, output_interval=1800.0)) == 1800.0
    assert lead_in_step(DiurnalSettings(lead_in=0.0)) == 300.0


def test_night_steps_lengthen_after_dusk_through_doubling_and_return_by_dawn():
    s = DiurnalSettings()            # 300 s, recording 1800 s, night up to 900 s
    settle = int(NIGHT_SETTLE / 1800.0)
    assert settle * 1800.0 == NIGHT_SETTLE
    # the settle intervals before the day, then 48: dark 0–4 h, light 4–20 h, dark 20–24 h
    dark = np.r_[[True] * settle, [b < 8 or b >= 40 for b in range(48)]]
    got = night_steps(s, dark, previous_step=900.0)
    want = np.r_[[900.0] * 8, [300.0] * (32 + settle), [600.0], [900.0] * (7 - settle)]
    assert np.array_equal(got, want), got
    # after a 300 s step the night starts at 600 s; a 600 s limit; uniform on request
    assert night_steps(s, dark)[0] == 600.0
    assert night_steps(DiurnalSettings(night_step=600.0), dark).max() == 600.0
    assert np.all(night_steps(DiurnalSettings(night_step=300.0), dark) == 300.0)
    # the night step divides the recording interval: 1200 s is not used with 1800 s
    assert night_steps(DiurnalSettings(night_step=1200.0), dark).max() == 900.0
    # every interval is covered by whole steps, and no step more than doubles the last
    steps = night_steps(s, dark)
    assert np.all(np.abs(1800.0 / steps - np.round(1800.0 / steps)) < 1e-12)
    assert np.all(steps[1:] <= 2.0 * steps[:-1])
    # a short night (shorter than the settle time) keeps the day's step
    short = np.r_[[False] * settle, [38 <= b < 38 + settle for b in range(48)]]
    assert np.all(night_steps(s, short) == 300.0)


@pytest.fixture(scope="module")
def night_runs(tmp_path_factory):
    """The patrol boat's day in 300 s steps: night steps (with a checkpoint every simulated
    hour), uniform steps, and a resume from the last checkpoint (23:00, in the night)."""
    ship = patrol_boat(edge_length=3.0)
    env = Environment.from_climate_day(climate_day("winter"), ship_heading=90.0)
    base = DiurnalSettings(time_step=300.0, output_interval=1800.0, rays_per_face=32,
                           samples_per_face=8, spinup_max_days=1, spinup_tolerance=1.0)
    ckpt = tmp_path_factory.mktemp("night") / "run.npz"
    night = run_diurnal(ship, env, base, progress=False, checkpoint=ckpt,
                        checkpoint_interval=3600.0)
    with np.load(ckpt) as c:
        saved_at = float(c["time"])
    resumed = run_diurnal(ship, env, base, progress=False, checkpoint=ckpt, resume=True,
                          traced=night.forcing.traced, graph=night.graph)
    uniform = run_diurnal(ship, env, DiurnalSettings(**{**base.__dict__, "night_step": 300.0}),
                          progress=False, traced=night.forcing.traced, graph=night.graph)
    return night, uniform, resumed, saved_at


def test_night_steps_keep_the_day_and_its_energy(night_runs):
    night, uniform, resumed, saved_at = night_runs
    steps = np.diff(night.results.times)   # recording times: every 1800 s either way
    assert np.allclose(steps, 1800.0)
    n_night, n_uniform = len(night.energy.time), len(uniform.energy.time)
    d = np.max(np.abs(night.results.face_temperature - uniform.results.face_temperature))
    print(f"patrol boat, winter: {n_night} vs {n_uniform} steps, faces within {d:.2e} K")
    assert n_night < 0.8 * n_uniform
    # measured 0.0089 K on the frigate at 0.5 m in winter; the same bound here
    assert d < 0.02
    assert night.energy.max_step_imbalance <= night.settings.energy_tolerance


def test_a_run_resumed_in_the_night_repeats_the_uninterrupted_one(night_runs):
    night, uniform, resumed, saved_at = night_runs
    assert 20 * 3600.0 <= saved_at < DAY     # the last hourly checkpoint, night steps on
    assert np.array_equal(resumed.results.face_temperature, night.results.face_temperature)
    assert np.array_equal(resumed.results.cell_temperature, night.results.cell_temperature)


def test_energy_closes_over_lead_in_and_days(runs):
    for r in runs:
        # Newton's stopping rule bounds every step's imbalance (NEWTON_ENERGY_TOLERANCE)
        assert r.energy.max_step_imbalance <= r.settings.energy_tolerance, \
            r.energy.summary()
        assert abs(r.energy.relative_imbalance) <= r.settings.energy_tolerance


def test_surface_balance_kernel_solves_the_face_balance(runs):
    """The converged surface temperature of every face zeroes its balance
    g (T_P − T_s) + A q(T_s) = 0 (with the face-to-face gain at the given lagged temperatures,
    and the air faces' convection law taken to first order about them), and the reported
    conductance is −∂flow/∂T_P by central differences."""
    from shipthermal.model import (RadiativeExchange, ThermalModel, law_coefficients,
                                   surface_balance)

    fast, _ = runs
    g = fast.graph
    f = fast.forcing
    model = ThermalModel(g, f.conditions(with_exchange=True),
                         exchange=RadiativeExchange(*f.radiative_exchange()))
    forcing = model.forcing(13.0 * 3600.0)
    rng = np.random.default_rng(3)
    temp = 290.0 + 20.0 * rng.random(g.n_cells)
    lag = 285.0 + 30.0 * rng.random(g.n_bfaces)
    ex = model.exchange
    bs = surface_balance(g, forcing, temp, lag, exchange=ex, exchange_temp=lag)
    area, cond = g.bface_area, g.bface_conductance
    tc = temp[g.bface_cell]
    e = forcing.emissivity.copy()
    gain = np.zeros(g.n_bfaces)
    e[ex.bfaces] += np.asarray(ex.area_exchange.sum(axis=1)).ravel() / area[ex.bfaces]
    gain[ex.bfaces] = SIGMA * (ex.area_exchange @ lag[ex.bfaces] ** 4)
    ts = bs.temp_face
    assert forcing.has_law
    h0, slope, ref = law_coefficients(forcing, lag)
    conv = h0 * (forcing.temp_fluid - ref) - (h0 + slope) * (ts - ref)
    q = (forcing.q0 + conv + forcing.emissivity * forcing.longwave_in - e * SIGMA * ts ** 4
         + gain / area)
    resid = cond * (tc - ts) + area * q
    scale = cond * tc + area * (forcing.q0 + SIGMA * ts ** 4)
    assert np.max(np.abs(resid) / scale) < 1e-12
    dt = 1e-3
    up = surface_balance(g, forcing, temp + dt, lag, exchange=ex, exchange_temp=lag)
    dn = surface_balance(g, forcing, temp - dt, lag, exchange=ex, exchange_temp=lag)
    # the flow's own face-to-face term is evaluated at the converged T_s on both sides;
    # with exchange_temp fixed the derivative of the balance flow is −cond
    fd = -(up.flow - dn.flow) / (2 * dt)
    own = np.ones(g.n_bfaces, bool)
    own[ex.bfaces] = False
    np.testing.assert_allclose(fd[own], bs.conductance[own], rtol=1e-6)
