"""Diurnal ship runs: sign of the solar loading, energy, spin-up, outputs, validation table."""

import numpy as np
import pytest

from shipthermal.diurnal import DiurnalSettings, lead_in_seconds, lead_in_step, run_diurnal
from shipthermal.environment import Environment, climate_day
from shipthermal.geometry import patrol_boat
from shipthermal.units import HOUR


@pytest.fixture(scope="module")
def summer_run():
    ship = patrol_boat(edge_length=2.0)
    env = Environment.from_climate_day(climate_day("summer"), ship_heading=90.0)
    settings = DiurnalSettings(time_step=600.0, output_interval=1800.0, spinup_tolerance=0.01,
                               spinup_max_days=6, rays_per_face=64, samples_per_face=16)
    return run_diurnal(ship, env, settings, progress=False)


def test_spinup_converges_and_reports_days(summer_run):
    r = summer_run
    print(f"patrol boat: {r.ship.n_faces} faces, {r.graph.n_cells} cells, days {r.days}, "
          f"changes {r.day_changes}, timings {r.timings}")
    assert r.converged
    assert r.days >= 1 and len(r.day_changes) == r.days
    assert r.day_changes[-1] <= 0.01
    # every day before the last one was not yet periodic
    assert all(c > 0.01 for c in r.day_changes[:-1])
    assert r.results.times[0] == 0.0 and r.results.times[-1] == 24 * HOUR


def test_energy_closes_over_the_whole_run(summer_run):
    e = summer_run.energy
    # the lead-in before the first midnight in its own (longer) steps, then whole days of
    # 144 steps
    lead = lead_in_seconds(summer_run.settings)
    step = lead_in_step(summer_run.settings)
    assert lead > 0 and step > summer_run.settings.time_step
    assert len(e.time) == summer_run.days * 144 + round(lead / step)
    assert e.time[0] == -lead + step and e.time[-1] == summer_run.days * 24 * HOUR
    np.testing.assert_allclose(np.diff(e.time), np.r_[np.full(round(lead / step) - 1, step),
                                                      np.full(summer_run.days * 144, 600.0)])
    # every step converged until Σ residual ≤ energy_tolerance of its gross boundary heat
    # (Newton's stopping rule, NEWTON_ENERGY_TOLERANCE): the step's and so the run's bound
    tol = summer_run.settings.energy_tolerance
    assert e.max_step_imbalance <= tol, e.summary()
    assert abs(e.relative_imbalance) <= tol, e.summary()


def test_sunlit_deck_warmer_than_shaded_deck(summer_run):
    """Guards against a sign error in the solar loading: at 09:00 the deck faces the sun
    reaches are warmer than deck faces in the superstructure's shadow."""
    r = summer_run
    ship, forcing = r.ship, r.forcing
    t = 9 * HOUR
    # lit fraction of the sun receivers → per surface triangle (shell graph: outer boundary
    # face b is triangle b)
    lit = np.zeros(ship.n_faces)
    lit[forcing.outer_bfaces[forcing.traced.receivers]] = forcing.lit_fraction(t)
    deck = np.array([ship.part_names[p].startswith("deck") for p in ship.face_part])
    flat = ship.face_normals[:, 2] > 0.95
    temp = r.face_temperature_at(9.0)
    sunny = deck & flat & (lit > 0.95)
    shaded = deck & flat & (lit < 0.05)
    assert sunny.sum() > 10 and shaded.sum() > 3, (sunny.sum(), shaded.sum())
    gap = temp[sunny].mean() - temp[shaded].mean()
    print(f"09:00 deck: sunlit {temp[sunny].mean():.2f} K vs shaded {temp[shaded].mean():.2f} K")
    assert gap > 2.0
    # and the sunlit deck is warmer than the air in the morning sun
    assert temp[sunny].mean() > r.part_mean_at("temp_air", 9.0)


def test_wetted_hull_follows_the_sea(summer_run):
    pm = summer_run.part_means
    assert np.max(np.abs(pm["hull_wetted"] - pm["temp_sea"])) < 1.0


def test_outputs_written_atomically(summer_run, tmp_path):
    paths = summer_run.write(tmp_path, map_hours=(12.0,))
    for p in paths.values():
        assert p.exists() and p.stat().st_size > 0
    assert (tmp_path / "part_means.png").exists() and (tmp_path / "surface_1200.png").exists()
    assert not list(tmp_path.glob(".*tmp*"))
    from shipthermal.app.thermal import ship_thermal_history

    hist = ship_thermal_history(summer_run)
    np.testing.assert_allclose(hist.at(12 * HOUR), summer_run.face_temperature_at(12.0))
    # the imaging's sea is the skin the thermal run's hull saw (bulk + warm layer - cool skin)
    pm = summer_run.part_means
    np.testing.assert_array_equal(hist.temp_sea, pm["temp_sea_skin"].to_numpy())
    st = summer_run.environment.at(summer_run.results.times)
    np.testing.assert_array_equal(pm["temp_sea_skin"], st.temp_sea_skin)
    np.testing.assert_array_equal(pm["temp_sea"], st.temp_sea)


#: Area-mean deck temperature [K] of `validate(quick=True)` at the four reference moments.
#: These pin today's answer, so that a change in any stage that moves the deck shows up here:
#: a commit that changes a value states why in its message (never to match the reference).
EXPECTED_DECK_K = {("summer", "12:00"): 331.65, ("summer", "07:00"): 305.56,
                   ("winter", "12:00"): 293.69, ("winter", "08:00"): 276.33}
DECK_TOLERANCE_K = 0.5


def test_four_moment_validation_table(capsys):
    from shipthermal.app.validation import REFERENCE_DECK, validate

    rep = validate(quick=True, sensitivity=False, crossovers=False, progress=False)
    with capsys.disabled():
        print("\n" + rep.text())
    t = rep.table
    assert len(t) == len(REFERENCE_DECK) == len(EXPECTED_DECK_K)
    for _, row in t.iterrows():
        expected = EXPECTED_DECK_K[(row.season, row.time)]
        assert abs(row.ours_K - expected) <= DECK_TOLERANCE_K, (row.season, row.time,
                                                                row.ours_K, expected)
    np.testing.assert_allclose(t["diff_K"], t["ours_K"] - t["reference_K"])
