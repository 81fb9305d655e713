"""Weather-record runs: spin-up on the record's first day, then the record as it is.

A coarse patrol boat (30-min steps) on two real days of NDBC buoy 44009 (tests/data).
"""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.thermal import run_scenario_thermal
from shipthermal.app.scenario import load_scenario

NDBC = Path(__file__).resolve().parents[1] / "data" / "weather" / "44009h2013_mar03-09.txt"


def _scenario(**weather):
    return load_scenario({
        "name": "buoy",
        "location": {"latitude": 38.46, "longitude": -74.70, "time_zone": "Etc/GMT+5"},
        "time": {"season": "winter", "date": "2013-03-04", "output_interval": 1800},
        "weather": {"source": str(NDBC), "day": "record", "days": 2, "wind_height": 5.0,
                    "cloud_cover": 0.5, **weather},
        "ship": {"builtin": "patrol_boat", "edge_length": 5.6},
        "solver": {"time_step": 1800, "spinup_max_days": 8, "spinup_tolerance": 0.02,
                   "rays_per_face": 16, "samples_per_face": 4}})


@pytest.fixture(scope="module")
def record_run():
    sc = _scenario()
    return sc, run_scenario_thermal(sc, progress=False)


def test_record_covers_every_day_and_follows_the_file(record_run):
    sc, res = record_run
    pm = res.part_means
    # every output time of both recorded days, closing midnight included
    np.testing.assert_allclose(pm.index.to_numpy(), np.arange(0, 48.01, 0.5))
    assert res.meta["record_days"] == 2 and res.days == res.meta["spinup_days"] + 2
    assert res.converged
    # air and sea in the outputs are the file's :50 values interpolated onto the clock
    lines = NDBC.read_text().splitlines()[2:]
    t = np.array([pd.Timestamp(f"{r[0]}-{r[1]}-{r[2]}T{r[3]}:{r[4]}Z").timestamp()
                  for r in (x.split() for x in lines)])
    atmp = np.array([float(x.split()[13]) for x in lines])
    wtmp = np.array([float(x.split()[14]) for x in lines])
    # on the hours; the half hours lie halfway between them (the weather is hourly)
    hours = pm.index.to_numpy()[::2]
    g = sc.start.timestamp() + hours * 3600.0
    for col, raw in (("temp_air", atmp), ("temp_sea", wtmp)):
        on = pm[col].to_numpy()
        np.testing.assert_allclose(on[::2], np.interp(g, t, raw) + 273.15, atol=1e-9)
        np.testing.assert_allclose(on[1::2], 0.5 * (on[:-1:2] + on[2::2]), atol=1e-9)
    # energy bookkeeping over spin-up and record
    assert abs(res.energy.relative_imbalance) < 1e-10


def test_record_starts_from_the_spun_up_day(record_run):
    """Day 1 of the record has the spin-up day's weather except in its last hour (the
    record goes on into day 2, the periodic day wraps to its own midnight): until 22:00
    the two must agree to the spin-up tolerance plus the solver's round-off."""
    sc, res = record_run
    from shipthermal.app.thermal import settings_from_scenario
    from shipthermal.diurnal import run_diurnal

    spin = run_diurnal(res.ship, sc.environment().first_day(), settings_from_scenario(sc),
                       absorptivity={p: sc.solar_absorptivity(p) for p in res.ship.part_names},
                       emissivity={p: sc.longwave_emissivity(p) for p in res.ship.part_names},
                       graph=res.graph, traced=res.forcing.traced, progress=False)
    a = spin.part_means.loc[:22.0, ["hull", "deck", "superstructure"]].to_numpy()
    b = res.part_means.loc[:22.0, ["hull", "deck", "superstructure"]].to_numpy()
    assert np.max(np.abs(a - b)) < 2 * sc.solver.spinup_tolerance + 1e-6
    # the record then departs from the repeated day (day 2 is other weather)
    c = res.part_means.loc[24.0:46.0, ["deck"]].to_numpy()
    assert np.max(np.abs(c - a[: len(c)])) > 0.5
