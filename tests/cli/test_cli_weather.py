"""Station weather files through the command line, with no user code: the NDBC buoy crop
(tests/data/weather) and pvlib's TMY3 file; the outputs' air and sea temperatures are
compared with the files' own values."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import pandas as pd
from cli_helpers import write_tiny

from shipthermal.app.cli import main
from shipthermal.units import strip_units

NDBC = Path(__file__).resolve().parents[1] / "data" / "weather" / "44009h2013_mar03-09.txt"

BUOY = """
[location]
latitude = 38.46
longitude = -74.70
time_zone = "Etc/GMT+5"
[weather]
source = "buoy.txt"
day = "record"
days = 2
wind_height = 5.0
cloud_cover = 0.5
"""


def _with(path, text, date):
    t = path.read_text().replace("[time]\n", f"[time]\ndate = {date}\n")
    path.write_text(t.replace("[ship]", text.strip() + "\n[ship]"))
    return path


def _ndbc_raw():
    rows = [x.split() for x in NDBC.read_text().splitlines()[2:]]
    t = np.array([pd.Timestamp(f"{r[0]}-{r[1]}-{r[2]}T{r[3]}:{r[4]}Z").timestamp()
                  for r in rows])
    return t, np.array([float(r[13]) for r in rows]), np.array([float(r[14]) for r in rows])


def test_ndbc_record_run_from_the_command_line(tmp_path, capsys):
    shutil.copy(NDBC, tmp_path / "buoy.txt")
    sc = _with(write_tiny(tmp_path, name="buoy", season="winter"), BUOY, "2013-03-04")
    # validate opens the file and reports what it will do
    assert main(["check", str(sc)]) == 0
    out = capsys.readouterr().out
    assert "49 hourly values, 2013-03-04 00:00 … 2013-03-06 00:00 -05" in out
    assert "gap of 2 h between observations" in out and "reduced from 5 m to 10 m" in out
    assert main(["run", str(sc), "--out", str(tmp_path / "run")]) == 0
    captured = capsys.readouterr()
    err = captured.err
    assert "spin-up + 2 recorded days" in captured.out
    assert "cloud_cover: not in the file over the span, constant 0.5" in err
    pm = strip_units(pd.read_csv(tmp_path / "run" / "thermal" / "buoy" / "part_means.csv",
                                 index_col=0))
    assert pm.index[0] == 0 and pm.index[-1] == 48      # both recorded days
    t, atmp, wtmp = _ndbc_raw()
    hours = pm.index.to_numpy()
    g = pd.Timestamp("2013-03-04", tz="Etc/GMT+5").timestamp() + hours * 3600.0
    on = np.isclose(hours % 1, 0)
    # part_means.csv is written with 4 decimals
    np.testing.assert_allclose(pm["temp_air"][on], np.interp(g[on], t, atmp) + 273.15,
                               atol=6e-5)
    np.testing.assert_allclose(pm["temp_sea"][on], np.interp(g[on], t, wtmp) + 273.15,
                               atol=6e-5)
    summary = json.loads((tmp_path / "run" / "thermal" / "buoy" /
                          "thermal_summary.json").read_text())
    assert summary["record_days"] == 2
    assert any("gap of 2 h" in line for line in summary["weather_report"])


def test_tmy3_from_the_command_line(tmp_path, capsys):
    import pvlib

    src = Path(pvlib.__file__).parent / "data" / "703165TY.csv"
    text = f"""
[location]
latitude = 55.317
longitude = -160.517
time_zone = "Etc/GMT+9"
[weather]
source = "{src.as_posix()}"
format = "tmy3"
temp_sea = 279.0
"""
    sc = _with(write_tiny(tmp_path, name="tmy", season="summer"), text, "2023-07-20")
    assert main(["-q", "run", str(sc), "--out", str(tmp_path / "run")]) == 0
    pm = strip_units(pd.read_csv(tmp_path / "run" / "thermal" / "tmy" / "part_means.csv",
                                 index_col=0))
    data, _ = pvlib.iotools.read_tmy3(src, coerce_year=2023, map_variables=True)
    day = data["temp_air"].tz_convert("Etc/GMT+9")
    want = day.loc["2023-07-20 00:00":"2023-07-20 23:00"].to_numpy() + 273.15
    got = pm["temp_air"][np.isclose(pm.index % 1, 0)].to_numpy()[:24]
    np.testing.assert_allclose(got, want, atol=6e-5)
    np.testing.assert_allclose(pm["temp_sea"], 279.0, atol=6e-5)


def test_validate_lists_every_weather_problem_at_once(tmp_path, capsys):
    shutil.copy(NDBC, tmp_path / "buoy.txt")
    text = BUOY.replace("cloud_cover = 0.5\n", "max_gap_hours = 3.0\n").replace(
        "days = 2", "days = 3")
    sc = _with(write_tiny(tmp_path, name="buoy", season="winter"), text, "2013-03-04")
    before = sorted(p.name for p in tmp_path.iterdir())
    assert main(["check", str(sc)]) == 2
    err = capsys.readouterr().err
    assert "weather file buoy.txt: 6 problems" in err
    assert "has no column for cloud_cover" in err
    assert err.count("from 2013-03-06 11:50 to 2013-03-06 15:50 -05 (4 h)") == 5
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_record_is_imaged_over_its_span(tmp_path, capsys):
    # Two days of the buoy, imaged every 30 min over both: the port background follows the
    # record (its water is the buoy's sea at every frame, the ship's own), the crossovers carry
    # their dates, and the paper's chain (here also of another climate) is refused.
    shutil.copy(NDBC, tmp_path / "buoy.txt")
    sc = _with(write_tiny(tmp_path, name="buoy", season="winter"), BUOY, "2013-03-04")
    assert main(["-q", "run", str(sc), "--out", str(tmp_path / "run"), "--image"]) == 0
    run = tmp_path / "run"
    m = strip_units(pd.read_csv(run / "imaging" / "metrics_winter_8-14.csv"))
    assert m["time_h"].iloc[0] == 0.0 and m["time_h"].iloc[-1] == 48.0
    pm = strip_units(pd.read_csv(run / "thermal" / "buoy" / "part_means.csv", index_col=0))
    sea = pm["temp_sea_skin"] if "temp_sea_skin" in pm else pm["temp_sea"]
    on = np.isin(m["time_h"], pm.index)
    # the synthetic port's water pattern has zero mean over the water (part_means: 4 decimals)
    np.testing.assert_allclose(m["water_mean_temp"][on], np.interp(m["time_h"][on], pm.index,
                                                                    sea), atol=2e-4)
    cross = strip_units(pd.read_csv(run / "imaging" / "crossovers.csv"))
    assert set(cross["date_local"]) <= {"2013-03-04", "2013-03-05", "2013-03-06"}
    paper = _with(write_tiny(tmp_path / "p", name="buoy", season="winter"), BUOY, "2013-03-04")
    paper.write_text(paper.read_text().replace("[background]\n", "[background]\nmodel = \"paper\"\n"))
    shutil.copy(NDBC, tmp_path / "p" / "buoy.txt")
    before = sorted(p.name for p in (tmp_path / "p").iterdir())
    assert main(["-q", "run", str(paper), "--out", str(tmp_path / "p" / "run"), "--image"]) == 2
    err = capsys.readouterr().err
    # the paper's chain on the synthetic port is the Dalian design day: another climate
    assert "background.model = 'paper'" in err and "another climate" in err
    assert sorted(p.name for p in (tmp_path / "p").iterdir()) == before


def test_calendar_of_a_record(tmp_path, capsys):
    # Three days of the buoy with a listed overpass beside Landsat 8's: one row per overpass
    # and band, the monthly fraction is the overpasses' own, the dense series' crossovers
    # are those of its contrast, and a time outside the record is refused (exit 2).
    shutil.copy(NDBC, tmp_path / "buoy.txt")
    text = BUOY.replace("days = 2", "days = 3") + (
        "[calendar]\ntimes = ['2013-03-05T03:00:00Z']\ndense_step = 10800.0\n")
    sc = _with(write_tiny(tmp_path, name="buoy", season="winter"), text, "2013-03-04")
    assert main(["-q", "calendar", str(sc), "--out", str(tmp_path / "cal")]) == 0
    out = capsys.readouterr().out
    assert "overpasses; under the clutter" in out
    d = tmp_path / "cal" / "calendar"
    op = pd.read_csv(d / "overpasses.csv")
    assert set(op["satellite"]) == {"Landsat 8", "listed"}
    assert len(op) == 2 * op["time_utc"].nunique()                  # both bands
    listed = op[op["satellite"] == "listed"]
    assert set(listed["time_local"]) == {"22:00"} and not listed["daytime"].any()
    # each overpass through its own day's model atmosphere: early March at buoy 44009 the
    # air is 0-8 °C, nearest mid-latitude winter's 272.2 K of the six models' surfaces
    assert set(op["atmosphere_model"]) == {"midlatitude_winter"}
    m = pd.read_csv(d / "monthly.csv")
    for band, g in op.groupby("band"):
        row = m[m["band"] == band].iloc[0]
        assert row["overpasses"] == len(g)
        assert row["fraction_under"] == pytest.approx((g["scr"] < 1.0).mean())
    assert (d / "calendar_8-14.png").is_file() and (d / "summary.json").is_file()
    cross = pd.read_csv(d / "crossovers.csv")
    assert set(cross["direction"]) <= {"dark->bright", "bright->dark"}
    bad = sc.read_text().replace("2013-03-05T03:00:00Z", "2013-04-05T03:00:00Z")
    sc2 = tmp_path / "bad.toml"
    sc2.write_text(bad)
    assert main(["-q", "calendar", str(sc2), "--out", str(tmp_path / "cal2")]) == 2
    err = capsys.readouterr().err
    assert "calendar.times" in err and "must lie within the record" in err
    assert not (tmp_path / "cal2").exists()


@pytest.mark.slow
def test_calendar_across_years(tmp_path, capsys):
    # The buoy's three days in 2013 (the real crop) and the same dates of 2012 (the crop's
    # rows moved to 2012 with the air 3 K warmer, written in the NDBC layout): one thermal
    # case per year, the tables carry the year, and every calendar date's crossover times
    # across the years are those of crossovers.csv (median and 5-95 % by numpy here).
    shutil.copy(NDBC, tmp_path / "buoy.txt")
    lines = NDBC.read_text().splitlines()
    rows = [ln.split() for ln in lines[2:]]
    for r in rows:
        r[0], r[13] = "2012", f"{float(r[13]) + 3.0:.1f}"
    (tmp_path / "b2012.txt").write_text("\n".join(lines[:2] + [" ".join(r) for r in rows])
                                        + "\n")
    text = BUOY.replace("days = 2", "days = 3") + (
        "[calendar]\nyears = [2012, 2013]\nyear_sources = ['b2012.txt', 'buoy.txt']\n"
        "dense_step = 3600.0\ntimes = ['2013-03-05T03:00:00Z']\n")
    sc = _with(write_tiny(tmp_path, name="buoy", season="winter"), text, "2013-03-04")
    assert main(["-q", "calendar", str(sc), "--out", str(tmp_path / "cal")]) == 0
    d = tmp_path / "cal" / "calendar"
    assert sorted(p.name for p in (tmp_path / "cal" / "thermal").iterdir()) == [
        "buoy-2012", "buoy-2013"]
    for year in (2012, 2013):
        pm = strip_units(pd.read_csv(tmp_path / "cal" / "thermal" / f"buoy-{year}" /
                                     "part_means.csv", index_col=0))
        assert pm.index[-1] == 72
        if year == 2012:
            air12 = pm["temp_air"].to_numpy()
        else:
            np.testing.assert_allclose(air12 - pm["temp_air"].to_numpy(), 3.0, atol=2e-4)
        assert (d / f"calendar_8-14_{year}.png").is_file()
    op = pd.read_csv(d / "overpasses.csv")
    assert set(op.loc[op["satellite"] == "listed", "year"]) == {2013}   # its instant's year
    every = pd.read_csv(d / "crossovers.csv")
    dates = pd.read_csv(d / "crossover_dates.csv", dtype={"date": str})
    assert len(dates) and set(every["year"]) <= {2012, 2013}
    for _, row in dates.iterrows():
        g = every[every["date_local"].str.endswith(row["date"]) & (every["band"] == row["band"])
                  & (every["direction"] == row["direction"])]
        assert row["years"] == g["year"].nunique() and row["crossovers"] == len(g)
        assert row["median_clock_h"] == pytest.approx(np.median(g["clock_h"]), abs=1e-4)
        assert row["p95_clock_h"] == pytest.approx(np.percentile(g["clock_h"], 95), abs=1e-4)
