"""Station weather records: NDBC, TMY3 and CSV files onto the hour, gaps, wind height.

The real files are a crop of NOAA NDBC buoy 44009 (tests/data/weather, README beside it)
and pvlib's bundled TMY3 file of Sand Point, Alaska. Values are checked against an
independent parse of the raw text (plain string splitting, no pandas) and hand formulas.
"""

from pathlib import Path

import dataclasses

import numpy as np
import pandas as pd
import pytest

from shipthermal.environment import convection
from shipthermal.environment.station import (MAX_GAP_HOURS, check_weather, read_ndbc,
                                             read_station, reduce_wind_to_10m, to_weather,
                                             weather_sense)
from shipthermal.errors import InputError
from shipthermal.app.scenario import load_scenario

DATA = Path(__file__).resolve().parents[1] / "data" / "weather"
NDBC = DATA / "44009h2013_mar03-09.txt"
TZ = "Etc/GMT+5"   # US Eastern standard time, the buoy's local clock


def _raw_ndbc(path):
    """(UTC instants as seconds, {column: values}) by splitting the text lines."""
    lines = Path(path).read_text().splitlines()
    names = lines[0].lstrip("#").split()
    rows = [line.split() for line in lines[2:] if line.strip()]
    cols = {n: np.array([float(r[i]) for r in rows]) for i, n in enumerate(names)}
    t = np.array([pd.Timestamp(f"{r[0]}-{r[1]}-{r[2]}T{r[3]}:{r[4]}Z").timestamp()
                  for r in rows])
    return t, cols


def test_ndbc_reader_matches_the_text():
    rec = read_ndbc(NDBC, tz=TZ)
    t, raw = _raw_ndbc(NDBC)
    f = rec.frame
    assert len(f) == len(t) == 160
    assert (f.index.minute == 50).all() and str(f.index.tz) == TZ
    np.testing.assert_array_equal([x.timestamp() for x in f.index], t)
    np.testing.assert_allclose(f["temp_air"], raw["ATMP"] + 273.15, atol=1e-9)
    np.testing.assert_allclose(f["temp_sea"], raw["WTMP"] + 273.15, atol=1e-9)
    np.testing.assert_allclose(f["wind_speed"], raw["WSPD"], atol=0)
    # humidity from the dew point: Magnus with the constants of sky.saturation_vapour_pressure
    # (Alduchov & Eskridge 1996: 6.1094 exp(17.625 T / (T + 243.04)) hPa)
    def es(tc):
        return 6.1094 * np.exp(17.625 * tc / (tc + 243.04))
    np.testing.assert_allclose(f["relative_humidity"],
                               np.minimum(100 * es(raw["DEWP"]) / es(raw["ATMP"]), 100),
                               rtol=2e-3)
    assert "cloud_cover" not in f


def test_ndbc_missing_codes_by_column(tmp_path):
    lines = NDBC.read_text().splitlines()
    row = lines[10].split()
    # WDIR 999, WSPD 99.0, ATMP 999.0, DEWP 99.0: missing; PRES 999.0 hPa is a real value
    row[5], row[6], row[12], row[13], row[15] = "999", "99.0", "999.0", "999.0", "99.0"
    row2 = lines[11].split()
    row2[5] = "99"        # a wind FROM 99 degrees is real
    (tmp_path / "b.txt").write_text("\n".join(lines[:10] + [" ".join(row), " ".join(row2)]
                                              + lines[12:]) + "\n")
    f = read_station(tmp_path / "b.txt", "ndbc", tz=TZ).frame
    k = 8
    assert np.isnan(f["wind_direction"].iloc[k]) and np.isnan(f["wind_speed"].iloc[k])
    assert np.isnan(f["temp_air"].iloc[k]) and np.isnan(f["relative_humidity"].iloc[k])
    assert f["wind_direction"].iloc[k + 1] == 99.0
    assert np.isfinite(f["temp_sea"].iloc[k])


def test_ndbc_onto_the_hour_gaps_and_wind_height():
    rec = read_ndbc(NDBC, tz=TZ)
    start = pd.Timestamp("2013-03-04", tz=TZ)
    w, rep = to_weather(rec, start, start + pd.Timedelta(days=3), wind_height=5.0,
                        fallback={"cloud_cover": 0.4})
    assert len(w.time) == 73 and (w.time.minute == 0).all() and not w.periodic
    # every hour: linear interpolation between the two :50 observations around it
    t, raw = _raw_ndbc(NDBC)
    g = np.array([x.timestamp() for x in w.time])
    ok = raw["ATMP"] < 99
    np.testing.assert_allclose(w.temp_air, np.interp(g, t[ok], raw["ATMP"][ok]) + 273.15,
                               atol=1e-9)
    i = int(np.searchsorted(t, g[30]))           # 10 min after t[i-1], 50 min before t[i]
    assert t[i] - t[i - 1] == 3600.0
    assert w.temp_sea[30] == pytest.approx(
        273.15 + raw["WTMP"][i - 1] + (raw["WTMP"][i] - raw["WTMP"][i - 1]) / 6, abs=1e-9)
    # wind at 5 m reduced to 10 m: ln(10/z0)/ln(5/z0) with z0 = 2e-4 m = 1.068448
    factor = np.log(10 / 2e-4) / np.log(5 / 2e-4)
    assert factor == pytest.approx(1.068448, abs=1e-6)
    np.testing.assert_allclose(w.wind_speed, factor * np.interp(g, t, raw["WSPD"]), rtol=1e-12)
    # the 4 h hole of 2013-03-06 (16:50 -> 20:50 UTC) is bridged and reported
    assert ("temp_air", pd.Timestamp("2013-03-06 11:50", tz=TZ),
            pd.Timestamp("2013-03-06 15:50", tz=TZ), 4.0) in rep.interpolated
    text = "\n".join(rep.lines())
    assert "gap of 4 h between observations 2013-03-06 11:50 and 2013-03-06 15:50" in text
    assert "cloud_cover: not in the file over the span, constant 0.4" in text
    assert "reduced from 5 m to 10 m" in text


def test_log_law_round_trip():
    """The anemometer's wind to 10 m and back is the same profile (one function)."""
    u = np.array([0.0, 3.0, 12.5])
    for z in (2.0, 5.0, 25.0):
        u10 = convection.wind_speed_at_height(u, 10.0, reference_height=z)
        np.testing.assert_allclose(convection.wind_speed_at_height(u10, z), u, rtol=1e-13)
    assert convection.wind_speed_at_height(7.0, 10.0, reference_height=10.0) == pytest.approx(
        7.0, rel=1e-15)


def test_wind_reduced_to_10m_only_from_another_height():
    """An anemometer at 10 m leaves the record's wind as read, without a note; from 4 m the
    log law's factor is applied and named in the note."""
    u = np.array([0.0, 4.0, 11.0])
    same, note = reduce_wind_to_10m(u, 10.0)
    assert same is u and note is None
    low, note = reduce_wind_to_10m(u, 4.0)
    factor = np.log(10 / 2e-4) / np.log(4 / 2e-4)
    np.testing.assert_allclose(low, factor * u, rtol=1e-14)
    assert "reduced from 4 m to 10 m" in note and f"x {factor:.4f}" in note


def test_an_anemometer_height_below_the_profile_is_refused_at_the_input(tmp_path):
    """The profile holds the wind below 10 roughness lengths; an anemometer height that
    low is refused where the scenario is read (``weather.wind_height``, at least 0.1 m)."""
    from shipthermal.app.scenario.sections import WeatherSettings
    spec = {f.name: f for f in dataclasses.fields(WeatherSettings)}["wind_height"]
    assert spec.metadata["spec"].lo >= 10.0 * convection.SEA_ROUGHNESS_LENGTH


def test_long_gap_is_refused_naming_the_span():
    rec = read_ndbc(NDBC, tz=TZ)
    start = pd.Timestamp("2013-03-04", tz=TZ)
    w, rep, problems = check_weather(rec, start, start + pd.Timedelta(days=3),
                                     max_gap_hours=3.0, wind_height=5.0)
    assert w is None
    fields = [p.field for p in problems]
    # every problem at once: five fields with the 4 h gap, and the missing cloud cover
    assert fields.count("weather.source[cloud_cover]") == 1 and len(problems) == 6
    text = str(problems[0])
    assert "from 2013-03-06 11:50 to 2013-03-06 15:50 -05 (4 h)" in text
    assert "longer than weather.max_gap_hours = 3 h" in text
    assert MAX_GAP_HOURS == 6.0


def test_csv_off_the_hour_and_all_missing_column(tmp_path):
    t = pd.date_range("2024-05-01 23:20", periods=40, freq="h", tz="UTC")
    df = pd.DataFrame({"time": t.strftime("%Y-%m-%dT%H:%M:%SZ"),
                       "temp_air": 10.0 + 0.5 * np.arange(40), "relative_humidity": 70.0,
                       "wind_speed": 5.0, "wind_direction": np.where(np.arange(40) % 2, 350, 10),
                       "cloud_cover": "", "temp_sea": 12.0})
    df.to_csv(tmp_path / "w.csv", index=False)
    rec = read_station(tmp_path / "w.csv", "csv", tz="UTC")
    start = pd.Timestamp("2024-05-02", tz="UTC")
    w, rep, problems = check_weather(rec, start, start + pd.Timedelta(hours=23))
    assert w is None and len(problems) == 1
    assert "has no valid value of cloud_cover between 2024-05-02 00:00" in str(problems[0])
    w, rep = to_weather(rec, start, start + pd.Timedelta(hours=23),
                        fallback={"cloud_cover": 0.2})
    # 00:00 is 40 min after 23:20: 10 + 0.5 * 40/60
    assert w.temp_air[0] == pytest.approx(273.15 + 10.0 + 0.5 * 40 / 60, abs=1e-9)
    # 350° and 10° alternate: the vector mean stays near north, never sweeps through south
    d = np.asarray(w.wind_direction)
    assert np.all(np.minimum(d, 360 - d) <= 10.0 + 1e-9)


def test_tmy3_record_through_the_scenario():
    import pvlib

    src = Path(pvlib.__file__).parent / "data" / "703165TY.csv"
    sc = load_scenario({"location": {"latitude": 55.317, "longitude": -160.517,
                                     "time_zone": "Etc/GMT+9"},
                        "time": {"season": "winter", "date": "2023-01-20"},
                        "weather": {"source": str(src), "format": "tmy3", "temp_sea": 276.0,
                                    "day": "record", "days": 3}})
    w = sc.weather_record()
    assert len(w.time) == 73 and w.time[0] == sc.start and not w.periodic
    data, _ = pvlib.iotools.read_tmy3(src, coerce_year=2023, map_variables=True)
    ref = data["temp_air"].tz_convert("Etc/GMT+9").loc[w.time[1:]]   # 01:00 … 24:00
    np.testing.assert_allclose(w.temp_air[1:], ref.to_numpy() + 273.15, atol=1e-9)
    # the irradiance stays the file's hourly energy, the hour ending at each label (the
    # environment spreads it over the hour: tests/forcing/test_forcing_solar.py)
    assert w.solar_interval == "ending" and sc.environment().weather.solar_interval == "ending"
    ghi = data["ghi"].tz_convert("Etc/GMT+9").loc[w.time[1:]]
    np.testing.assert_allclose(w.ghi[1:], ghi.to_numpy(), atol=1e-9)
    assert sc.check_weather()[0].startswith("weather tmy3:703165TY.csv: 73 hourly values")


def test_tmy2_units_and_hour_ending_labels():
    """pvlib's Miami TMY2 file: values in 0.1 °C and 0.1 m/s (TMY2 User's Manual,
    Table 3-2), row 'hour h' observed at the end of hour h."""
    import pvlib

    src = Path(pvlib.__file__).parent / "data" / "12839.tm2"
    rec = read_station(src, "tmy2", tz="Etc/GMT+5", year=2023)
    lines = src.read_text().splitlines()[1:]
    # fixed columns (manual Table 3-1): hour 8-9, dry bulb 68-71, wind speed 96-98 (1-based)
    row = lines[12]                       # 1 January, hour 13
    assert int(row[7:9]) == 13
    at = pd.Timestamp("2023-01-01 13:00", tz="Etc/GMT+5")
    assert rec.frame.loc[at, "temp_air"] == pytest.approx(int(row[67:71]) / 10 + 273.15)
    assert rec.frame.loc[at, "wind_speed"] == pytest.approx(int(row[95:98]) / 10)
    sc = load_scenario({"location": {"latitude": 25.8, "longitude": -80.27,
                                     "time_zone": "Etc/GMT+5"},
                        "time": {"date": "2023-07-01"},
                        "weather": {"source": str(src), "temp_sea": 302.0}})
    assert sc.weather.file_format == "tmy2"
    assert len(sc.weather_record().time) == 24


def test_epw_through_the_station_path(tmp_path):
    """The EPW rows as written, with a missing-value code (99.9 °C) bridged and reported,
    and an infrared column that is all 9999 dropped (the sky model is used)."""
    from test_env_weather import EPW_HEADER, _epw_row

    rows = [_epw_row(15 + i // 24, i % 24 + 1, 20 + (i % 24) / 4, 18.0, 80, 390 + i,
                     100 * (i % 3), 180, 3.5, 5) for i in range(48)]
    (tmp_path / "a.epw").write_text("\n".join(EPW_HEADER + rows) + "\n")
    rec = read_station(tmp_path / "a.epw", "epw", tz="Etc/GMT-8", year=2023)
    start = pd.Timestamp("2023-07-15 01:00", tz="Etc/GMT-8")
    w, rep = to_weather(rec, start, start + pd.Timedelta(hours=47),
                        fallback={"temp_sea": 295.0})
    i = np.arange(48)
    expected = {"temp_air": 273.15 + 20 + (i % 24) / 4, "relative_humidity": 80.0,
                "wind_speed": 3.5, "cloud_cover": 0.5, "ghi": 100.0 * (i % 3),
                "longwave_down": 390.0 + i}
    for f, want in expected.items():
        np.testing.assert_allclose(getattr(w, f), np.broadcast_to(want, (48,)), rtol=1e-12)
    rows = [_epw_row(15 + i // 24, i % 24 + 1, 20 + (i % 24) / 4 if i != 5 else 99.9, 18.0,
                     80, 9999, 100 * (i % 3), 180, 3.5, 5) for i in range(48)]
    (tmp_path / "b.epw").write_text("\n".join(EPW_HEADER + rows) + "\n")
    rec = read_station(tmp_path / "b.epw", "epw", tz="Etc/GMT-8", year=2023)
    w, rep = to_weather(rec, start, start + pd.Timedelta(hours=47),
                        fallback={"temp_sea": 295.0})
    assert w.longwave_down is None
    assert w.temp_air[5] == pytest.approx(0.5 * (w.temp_air[4] + w.temp_air[6]), abs=1e-12)
    assert [g[:2] for g in rep.interpolated] == [
        ("temp_air", pd.Timestamp("2023-07-15 05:00", tz="Etc/GMT-8"))]


def test_record_days_default_and_limit(tmp_path):
    """weather.days defaults to the whole days the file covers; a year is refused with the
    key to set."""
    import shutil

    shutil.copy(NDBC, tmp_path / "b.txt")
    base = {"location": {"latitude": 38.46, "longitude": -74.70, "time_zone": TZ},
            "time": {"season": "winter", "date": "2013-03-04"}}
    sc = load_scenario({**base, "weather": {"source": "b.txt", "day": "record",
                                            "cloud_cover": 0.5}}, base_dir=tmp_path)
    first, last = sc.weather_span(read_ndbc(tmp_path / "b.txt", tz=TZ))
    assert (last - first) == pd.Timedelta(days=5)     # 03-04 00:00 … 03-09 00:00 local
    assert len(sc.weather_record().time) == 121
    t = pd.date_range("2013-03-01", periods=410 * 24, freq="h", tz=TZ)
    pd.DataFrame({"time": t.strftime("%Y-%m-%dT%H:%M:%S%z"), "temp_air": 5.0,
                  "relative_humidity": 80.0, "wind_speed": 4.0, "wind_direction": 90.0,
                  "cloud_cover": 0.5, "temp_sea": 6.0}).to_csv(tmp_path / "long.csv",
                                                                index=False)
    year = load_scenario({**base, "weather": {"source": "long.csv", "day": "record"}},
                         base_dir=tmp_path)
    with pytest.raises(InputError, match=r"weather.days = None: the record covers 407 days "
                       r"from time.date; a record run takes at most 400. Set weather.days"):
        year.weather_record()


def test_ndbc_old_and_realtime_layouts(tmp_path):
    """Files before 2007 (no minute column, 'WD' / 'BAR', no units line) and the real-time
    layout (newest row first, 'MM' for missing) read to the same quantities."""
    old = ("YYYY MM DD hh  WD  WSPD GST  WVHT  DPD   APD  MWD  BAR    ATMP  WTMP  DEWP  VIS\n"
           "1998 03 04 00 280  7.9  9.3  0.76  3.57  3.77 313 1008.9   2.9   4.6  -2.5 99.0\n"
           "1998 03 04 01 999  8.1  9.9  0.80  3.60  3.80 310 1008.5   2.7   4.6  99.0 99.0\n")
    (tmp_path / "old.txt").write_text(old)
    f = read_station(tmp_path / "old.txt", "ndbc").frame
    assert list(f.index) == [pd.Timestamp("1998-03-04 00:00", tz="UTC"),
                             pd.Timestamp("1998-03-04 01:00", tz="UTC")]
    assert f["wind_direction"].iloc[0] == 280 and np.isnan(f["wind_direction"].iloc[1])
    assert np.isnan(f["relative_humidity"].iloc[1]) and f["temp_air"].iloc[1] == pytest.approx(275.85)
    rt = ("#YY  MM DD hh mm WDIR WSPD GST  WVHT   DPD   APD MWD   PRES  ATMP  WTMP  DEWP  VIS "
          "PTDY  TIDE\n"
          "#yr  mo dy hr mn degT m/s  m/s     m   sec   sec degT   hPa  degC  degC  degC  nmi  "
          "hPa    ft\n"
          "2026 11 20 14 50 200  5.0  6.0    MM    MM    MM  MM 1015.0  12.1  14.2   8.0   MM "
          "-0.4    MM\n"
          "2026 11 20 13 50 190  4.0  5.0    MM    MM    MM  MM 1015.4    MM  14.3   7.9   MM "
          "+0.1    MM\n")
    (tmp_path / "rt.txt").write_text(rt)
    rec = read_station(tmp_path / "rt.txt", "ndbc")
    assert rec.frame.index.is_monotonic_increasing and "sorted" in " ".join(rec.notes)
    assert np.isnan(rec.frame["temp_air"].iloc[0]) and rec.frame["temp_air"].iloc[1] == pytest.approx(285.25)


# ---------------------------------------------------------------------------------------
# physical sense: values in range, a day that cannot be
# ---------------------------------------------------------------------------------------
def _sense_csv(path, air_c, rh=80.0, sea_c=10.0, wind=4.0):
    """A day of hourly rows: air (scalar or 24 values), humidity, wind; SST column."""
    air = np.broadcast_to(np.asarray(air_c, float), (25,))
    rows = [f"2023-07-15T{h:02d}:00:00+08:00,{air[h]:.2f},{rh},{wind},180,0.3,{sea_c}"
            for h in range(24)] + [f"2023-07-16T00:00:00+08:00,{air[24]:.2f},{rh},{wind},"
                                   f"180,0.3,{sea_c}"]
    path.write_text("time,temp_air,relative_humidity,wind_speed,wind_direction,cloud_cover,"
                    "temp_sea\n" + "\n".join(rows) + "\n")
    return path


def _day(path, **read):
    rec = read_station(path, "csv", tz="Etc/GMT-8", **read)
    start = pd.Timestamp("2023-07-15", tz="Etc/GMT-8")
    return check_weather(rec, start, start + pd.Timedelta(hours=23))


def test_fahrenheit_read_as_celsius_is_refused(tmp_path):
    """41-59 'degC' air over a 10 degC sea (a cool day's air written in degF): +40 K over
    the water. The message names the unit: as degF the air is 5-15 degC."""
    air_f = 50.0 + 9.0 * np.sin(2 * np.pi * (np.arange(25) - 9) / 24)        # 41-59 degF
    w, _, problems = _day(_sense_csv(tmp_path / "f.csv", air_f, sea_c=10.0))
    assert w is None and len(problems) == 1
    msg = str(problems[0])
    assert "weather.source[temp_air]" in msg and "50.0 degC over a 10.0 degC sea" in msg
    assert "(+40.0 K)" in msg and "within -30 to +15 K" in msg
    assert "air temperatures look like degrees Fahrenheit" in msg
    # the whole file in degF (air 59, SST 34 degF read as degC: +25 K; as degF 15.0 and
    # 1.1 degC: +13.9 K): the fix is the unit key
    grid = pd.date_range("2023-01-15", periods=24, freq="h", tz="Etc/GMT-8")
    problems, _ = weather_sense({"temp_air": np.full(24, 59.0 + 273.15),
                                 "temp_sea": np.full(24, 34.0 + 273.15)}, grid, "csv:a.csv",
                                maybe_fahrenheit=True)
    assert len(problems) == 1 and "(+25.0 K)" in str(problems[0])
    assert 'look like degrees Fahrenheit: set weather.temp_unit = "F"' in str(problems[0])


def test_fahrenheit_file_read_as_fahrenheit(tmp_path):
    air_f = 50.0 + 9.0 * np.sin(2 * np.pi * (np.arange(25) - 9) / 24)
    path = _sense_csv(tmp_path / "f.csv", air_f, sea_c=50.0)      # SST 50 degF = 10 degC
    w, _, problems = _day(path, temp_unit="F")
    assert problems == []
    np.testing.assert_allclose(w.temp_air, (np.round(air_f[:24], 2) - 32) / 1.8 + 273.15,
                               atol=1e-9)
    np.testing.assert_allclose(w.temp_sea, 283.15, atol=1e-9)


def test_air_far_above_the_sea_is_refused_and_a_cold_outbreak_warned(tmp_path):
    w, _, problems = _day(_sense_csv(tmp_path / "hot.csv", 52.0, sea_c=12.0))
    assert w is None and "(+40.0 K)" in str(problems[0])
    # -25 K: a cold-air outbreak over open water, rare but real: run, with a warning
    w, rep, problems = _day(_sense_csv(tmp_path / "cold.csv", -23.0, sea_c=2.0))
    assert problems == [] and w is not None
    assert any("the air is -25.0 K from the sea" in n for n in rep.notes)


def test_humidity_written_as_a_fraction_is_refused(tmp_path):
    w, _, problems = _day(_sense_csv(tmp_path / "rh.csv", 20.0, rh=0.86, sea_c=19.0))
    assert w is None and len(problems) == 1
    msg = str(problems[0])
    assert "weather.source[relative_humidity]" in msg and "never exceeds 0.86 %" in msg
    assert "Multiply the column by 100" in msg


def test_storm_force_mean_wind_is_warned(tmp_path):
    w, rep, problems = _day(_sense_csv(tmp_path / "kmh.csv", 20.0, sea_c=19.0, wind=36.0))
    assert problems == [] and any("km/h or knots" in n for n in rep.notes)


def test_typical_year_file_of_another_site_is_refused():
    """pvlib's Miami TMY2 file (25.80 N, 80.27 W in its header) run for San Francisco:
    4 161 km away on the great circle (haversine, mean Earth radius)."""
    import pvlib

    from shipthermal.app.scenario import ScenarioError

    src = Path(pvlib.__file__).parent / "data" / "12839.tm2"
    sf = {"location": {"latitude": 37.77, "longitude": -122.42, "time_zone": "Etc/GMT+8"},
          "time": {"date": "2023-07-01"}, "weather": {"source": str(src), "temp_sea": 290.0}}
    with pytest.raises(ScenarioError) as err:
        load_scenario(sf).check_weather()
    msg = str(err.value)
    assert "is the record of MIAMI at 25.80 N, -80.27 E (its header), 4,161 km from" in msg
    assert "weather.max_site_distance" in msg
    sf["weather"]["max_site_distance"] = 5000.0            # a deliberate stand-in
    assert load_scenario(sf).check_weather()[0].startswith("weather tmy2:12839.tm2")
