"""Weather records: CSV / EPW / TMY3 readers, validation messages, interpolation."""

import csv

import numpy as np
import pandas as pd
import pvlib
import pytest

from shipthermal.environment import sky
from shipthermal.environment.station import check_weather, read_station, to_weather
from shipthermal.environment.weather import Weather, read_weather_csv
from shipthermal.errors import InputError

TMY3 = pvlib.__path__[0] + "/data/703165TY.csv"   # Sand Point, Alaska (coastal)

HEADER = "time,temp_air,relative_humidity,wind_speed,wind_direction,cloud_cover,ghi,longwave_down,temp_sea"


def _rows(n=6, start="2024-07-15T00:00:00+08:00"):
    t0 = pd.Timestamp(start)
    out = []
    for i in range(n):
        t = (t0 + pd.Timedelta(hours=i)).isoformat()
        out.append(f"{t},{20 + i},{80 - i},{4 + 0.5 * i},{(350 + 10 * i) % 360},0.{i},{100 * i},"
                   f"{380 + i},{22.0 + 0.1 * i}")
    return out


def _write(path, header, rows):
    path.write_text(header + "\n" + "\n".join(rows) + "\n")
    return path


def test_csv_canonical_columns_units(tmp_path):
    w = read_weather_csv(_write(tmp_path / "w.csv", HEADER, _rows()))
    assert str(w.tz) == "UTC+08:00" and len(w.time) == 6 and w.step == 3600.0
    np.testing.assert_allclose(w.temp_air, 273.15 + 20 + np.arange(6))
    np.testing.assert_allclose(w.temp_sea, 273.15 + 22.0 + 0.1 * np.arange(6))
    np.testing.assert_allclose(w.cloud_cover, 0.1 * np.arange(6))
    np.testing.assert_allclose(w.longwave_down, 380 + np.arange(6))
    assert w.ghi is not None and w.ghi[3] == 300.0


def test_csv_radtherm_names_naive_time_and_dew_point(tmp_path):
    rows = ["2024-01-15 00:00,-5.0,-12.0,6.0,0,50,0,3.0",
            "2024-01-15 01:00,-6.0,-12.0,6.0,10,60,0,3.0"]
    p = _write(tmp_path / "r.csv", "TIME,AIRT,DEWPT,WIND,WINDIR,CLOUD,SOLAR,SST", rows)
    w = read_weather_csv(p, tz="Etc/GMT-8", cloud_unit="percent")
    assert w.time[0] == pd.Timestamp("2024-01-15 00:00", tz="Etc/GMT-8")
    np.testing.assert_allclose(w.cloud_cover, [0.5, 0.6])
    # RH from dew point with the Magnus formula (independent route: ratio of e_s)
    es = 611.2 * np.exp(17.625 * np.array([-12.0, -5.0, -6.0]) / (np.array([-12.0, -5.0, -6.0]) + 243.04))
    np.testing.assert_allclose(w.relative_humidity, [100 * es[0] / es[1], 100 * es[0] / es[2]],
                               rtol=1e-3)
    assert w.longwave_down is None     # optional column absent


def test_interpolation_linear_and_wind_vector(tmp_path):
    w = read_weather_csv(_write(tmp_path / "w.csv", HEADER, _rows()))
    s = w.at(np.array([0.0, 1800.0, 5400.0]))
    np.testing.assert_allclose(s.temp_air, 273.15 + np.array([20, 20.5, 21.5]))
    np.testing.assert_allclose(s.wind_speed, [4.0, 4.25, 4.75])
    # 350 deg -> 0 deg: half way is 355 (vector), never 175 (naive average)
    d = s.wind_direction[1]
    assert min(abs(d - 355.0), abs(d - 355.0 + 360)) < 0.3
    # datetimes are accepted too and give the same values
    s2 = w.at(w.start + pd.to_timedelta([0.0, 1800.0, 5400.0], unit="s"))
    np.testing.assert_allclose(s2.temp_air, s.temp_air)
    with pytest.raises(InputError, match="within the weather record"):
        w.at([6 * 3600.0])


def test_periodic_record_wraps():
    t = pd.date_range("2024-07-15", periods=24, freq="h", tz="Etc/GMT-8")
    temp = 290 + 5 * np.sin(2 * np.pi * np.arange(24) / 24)
    w = Weather(t, temp, 70.0, 3.0, 180.0, 0.2, 295.0, periodic=True)
    a = w.at(np.arange(0, 86400, 900.0))
    b = w.at(np.arange(0, 86400, 900.0) + 3 * 86400)
    np.testing.assert_allclose(a.temp_air, b.temp_air)
    # between 23:00 and 24:00 the record interpolates back to 00:00
    assert w.at([23.5 * 3600]).temp_air[0] == pytest.approx(0.5 * (temp[-1] + temp[0]))


@pytest.mark.parametrize("mutate, match", [
    (lambda h, r: (h.replace(",wind_speed", ""), [",".join(x.split(",")[:3] + x.split(",")[4:]) for x in r]),
     "missing required column 'wind_speed'"),
    (lambda h, r: (h, r[:2] + r[3:]), "missing or extra time steps"),
    (lambda h, r: (h, [r[0].replace(",80,", ",180,")] + r[1:]), r"relative_humidity\[.*must lie in \[0, 100\]"),
    (lambda h, r: (h, r[:1] + [",".join(r[1].split(",")[:1] + [""] + r[1].split(",")[2:])] + r[2:]),
     r"temp_air\[.*no NaN"),
    (lambda h, r: (h.replace("cloud_cover", "clouds"), r), "unknown column"),
    (lambda h, r: (h, [x.replace("+08:00", "") for x in r]), "no UTC offset"),
    (lambda h, r: (h, [r[1], r[0]] + r[2:]), "strictly increasing"),
])
def test_csv_bad_inputs_clear_messages(tmp_path, mutate, match):
    header, rows = mutate(HEADER, _rows())
    with pytest.raises(InputError, match=match):
        read_weather_csv(_write(tmp_path / "bad.csv", header, rows))


def test_csv_kelvin_given_as_celsius_hint(tmp_path):
    rows = [r.replace(",20,", ",293.15,") for r in _rows()]
    with pytest.raises(InputError, match="temperature unit"):
        read_weather_csv(_write(tmp_path / "k.csv", HEADER, rows))
    with pytest.raises(InputError, match="existing file"):
        read_weather_csv(tmp_path / "nope.csv")


def test_tmy3_reader_matches_raw_file():
    rec = read_station(TMY3, "tmy3")
    frame = rec.frame
    assert len(frame) == 8760 and frame.index.is_monotonic_increasing
    assert rec.solar_interval == "ending"
    # independent parse of the raw file (line 1 metadata, line 2 header)
    with open(TMY3, newline="") as fh:
        rows = list(csv.reader(fh))
    head = rows[1]
    col_t, col_rh = head.index("Dry-bulb (C)"), head.index("RHum (%)")
    col_cld = head.index("TotCld (tenths)")
    raw_t = np.array([float(r[col_t]) for r in rows[2:]])
    raw_rh = np.array([float(r[col_rh]) for r in rows[2:]])
    raw_cld = np.array([float(r[col_cld]) for r in rows[2:]])
    # the reader sorts the year; row order is unchanged except for pvlib's move of the
    # final 24:00 row, which lands last in either case
    np.testing.assert_allclose(frame["temp_air"], raw_t + 273.15)
    np.testing.assert_allclose(frame["relative_humidity"], raw_rh)
    np.testing.assert_allclose(frame["cloud_cover"], raw_cld / 10)
    assert "ghi" in frame and "longwave_down" not in frame
    # TMY3 carries no sea temperature: a run needs weather.temp_sea
    start = frame.index[0]
    _, _, problems = check_weather(rec, start, start + pd.Timedelta(hours=23))
    assert any("weather.temp_sea" in str(p) for p in problems), problems


EPW_HEADER = [
    "LOCATION,Dalian,LN,CHN,SYNTHETIC,546620,38.91,121.63,8.0,92.0",
    "DESIGN CONDITIONS,0",
    "TYPICAL/EXTREME PERIODS,0",
    "GROUND TEMPERATURES,0",
    "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
    "COMMENTS 1,written by the shipthermal test suite",
    "COMMENTS 2,",
    "DATA PERIODS,1,1,Data,Sunday, 7/15, 7/16",
]


def _epw_row(day, hour, t, td, rh, ir, ghi, wd, ws, cld):
    # the 35 EnergyPlus weather-file fields, in order
    f = [2023, 7, day, hour, 0, "?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9?9?9",
         t, td, rh, 101000, 9999, 9999, ir, ghi, 0, 0, 999999, 999999, 999999, 9999,
         wd, ws, cld, cld, 9999, 99999, 9, 999999999, 999, 0.999, 999, 99, 999, 0, 0]
    return ",".join(str(x) for x in f)


def _epw_weather(path, **kwargs):
    """An EPW file through the one EPW parser, on the hours of its two days."""
    rec = read_station(path, "epw", tz="Etc/GMT-8", year=2023, **kwargs)
    start = pd.Timestamp("2023-07-15 01:00", tz="Etc/GMT-8")
    return to_weather(rec, start, start + pd.Timedelta(hours=47),
                      fallback={"temp_sea": 295.0})[0]


def test_epw_reader(tmp_path):
    rows = []
    for i in range(48):
        day, hour = 15 + i // 24, i % 24 + 1
        rows.append(_epw_row(day, hour, 20 + (i % 24) / 4, 18.0, 80, 390 + i, 100 * (i % 3),
                             (170 + i) % 360, 3.5, 5))
    p = tmp_path / "dalian.epw"
    p.write_text("\n".join(EPW_HEADER + rows) + "\n")
    w = _epw_weather(p)
    assert len(w.time) == 48 and w.step == 3600.0
    assert w.time[0].utcoffset() == pd.Timedelta(hours=8)
    # EPW "hour 1" holds the values at the end of 00:00-01:00
    assert w.time[0] == pd.Timestamp("2023-07-15 01:00", tz="Etc/GMT-8")
    np.testing.assert_allclose(w.temp_air[:4], 273.15 + 20 + np.arange(4) / 4)
    np.testing.assert_allclose(w.cloud_cover, 0.5)
    np.testing.assert_allclose(w.wind_speed, 3.5)
    # GHI is the hour's energy, kept as the file gives it (the environment spreads it over
    # the hour); the infrared is the value at the hour's end, as EnergyPlus reads it
    assert w.solar_interval == "ending"
    np.testing.assert_allclose(w.ghi[:3], [0.0, 100.0, 200.0])
    np.testing.assert_allclose(w.longwave_down[:2], [390.0, 391.0])
    # between labels, the weather gives the mean of the hour a time falls in
    s = w.at(pd.DatetimeIndex([w.time[1] - pd.Timedelta(minutes=30), w.time[1],
                               w.time[1] + pd.Timedelta(seconds=1)]))
    np.testing.assert_allclose(s.ghi, [100.0, 100.0, 200.0])
    assert w.temp_dew[0] == pytest.approx(sky.dew_point(w.temp_air[0], 80.0))


def test_epw_missing_longwave_falls_back_to_the_sky_model(tmp_path):
    """An infrared column of missing-value codes (9999) is no measurement: dropped, as is
    a measured one with ``use_measured_longwave=False`` (the sky model is used)."""
    rows = [_epw_row(15 + i // 24, i % 24 + 1, 20, 18, 80, 9999, 0, 180, 3, 5)
            for i in range(48)]
    p = tmp_path / "m.epw"
    p.write_text("\n".join(EPW_HEADER + rows) + "\n")
    assert _epw_weather(p).longwave_down is None
    rows = [_epw_row(15 + i // 24, i % 24 + 1, 20, 18, 80, 390, 0, 180, 3, 5)
            for i in range(48)]
    p.write_text("\n".join(EPW_HEADER + rows) + "\n")
    assert _epw_weather(p).longwave_down is not None
    assert _epw_weather(p, use_measured_longwave=False).longwave_down is None
