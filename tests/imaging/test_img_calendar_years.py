"""The calendar over several years: each year's scenario, and every calendar date's
crossover times pooled across the years."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from imaging.calendar import crossover_dates_table
from shipthermal.app.calendar import year_scenarios
from shipthermal.app.scenario import load_scenario
from shipthermal.errors import InputError

NDBC = Path(__file__).resolve().parents[1] / "data" / "weather" / "44009h2013_mar03-09.txt"


def test_a_date_pools_its_crossovers_over_the_years():
    rng = np.random.default_rng(3)
    rows = []
    for year in range(2001, 2021):
        for day, clock in (("03-04", 7.0), ("03-05", 8.0)):
            rows.append(dict(band="8-14", date_local=f"{year}-{day}", year=year,
                             clock_h=clock + rng.normal(0.0, 0.5), direction="dark->bright"))
    rows.append(dict(band="8-14", date_local="2005-03-04", year=2005, clock_h=20.0,
                     direction="bright->dark"))
    every = pd.DataFrame(rows)
    t = crossover_dates_table(every).set_index(["date", "direction"])
    for day in ("03-04", "03-05"):
        clocks = every[(every["date_local"].str.endswith(day)) &
                       (every["direction"] == "dark->bright")]["clock_h"]
        row = t.loc[(day, "dark->bright")]
        assert row["years"] == 20 and row["crossovers"] == 20
        assert (row["first_year"], row["last_year"]) == (2001, 2020)
        assert row["median_clock_h"] == pytest.approx(np.median(clocks))
        assert row["p05_clock_h"] == pytest.approx(np.percentile(clocks, 5))
        assert row["p95_clock_h"] == pytest.approx(np.percentile(clocks, 95))
    lone = t.loc[("03-04", "bright->dark")]
    assert lone["years"] == 1 and lone["median_clock_h"] == 20.0
    assert crossover_dates_table(every.iloc[:0]).empty


def _ndbc_of_year(src: Path, dst: Path, year: int, air_offset: float = 0.0) -> Path:
    """The real crop with its rows moved to ``year`` (the NDBC layout kept)."""
    lines = src.read_text().splitlines()
    out = lines[:2]
    for ln in lines[2:]:
        f = ln.split()
        f[0] = str(year)
        f[13] = f"{float(f[13]) + air_offset:.1f}"
        out.append(" ".join(f))
    dst.write_text("\n".join(out) + "\n")
    return dst


def _scenario(d, calendar):
    return load_scenario({
        "location": {"latitude": 38.46, "longitude": -74.70, "time_zone": "Etc/GMT+5"},
        "time": {"date": "2013-03-04"},
        "weather": {"source": str(NDBC), "day": "record", "days": 2, "wind_height": 5.0,
                    "cloud_cover": 0.5},
        "calendar": calendar}, base_dir=d)


def test_each_year_runs_the_same_dates_from_its_own_file(tmp_path):
    _ndbc_of_year(NDBC, tmp_path / "b2011.txt", 2011, 2.0)
    sc = _scenario(tmp_path, {"years": [2011, 2013],
                              "year_sources": ["b2011.txt", str(NDBC)]})
    years = year_scenarios(sc)
    assert [(y, s.time.date, Path(s.weather.source).name, s.name) for y, s in years] == [
        (2011, "2011-03-04", "b2011.txt", f"{sc.name}-2011"),
        (2013, "2013-03-04", NDBC.name, f"{sc.name}-2013")]
    # the year's own weather: the 2011 file's air is the 2013 file's + 2 K
    a = years[0][1].environment().weather.temp_air
    b = years[1][1].environment().weather.temp_air
    np.testing.assert_allclose(a - b, 2.0, atol=1e-9)
    assert year_scenarios(_scenario(tmp_path, {}))[0][1].time.date == "2013-03-04"


def test_a_year_the_file_does_not_cover_is_refused(tmp_path):
    sc = _scenario(tmp_path, {"years": [2012, 2013]})       # weather.source: 2013 only
    with pytest.raises(InputError, match=r"calendar.years\[0\] = 2012: needs "
                                         r"44009h2013_mar03-09.txt \(weather.source\) over "
                                         r"2012-03-04.*covers 2013-03-02"):
        year_scenarios(sc)
    with pytest.raises(InputError, match="one file per year of calendar.years"):
        _scenario(tmp_path, {"years": [2012, 2013], "year_sources": [str(NDBC)]})
