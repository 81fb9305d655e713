"""Overpass times and view geometry against real acquisitions, and the elements' checks."""

import math

import pandas as pd
import pytest

from imaging.overpass import (SATELLITES, listed_overpasses, parse_tle, satellite_overpasses,
                              swath_half_angle, tle_overpasses)
from shipthermal.errors import InputError

#: Two real Landsat-8 acquisitions (their MTL files): scene centre and SCENE_CENTER_TIME
MERSEY = (53.4828, -3.0980, "2020-09-27 11:10:50.314Z")          # examples/real_port, 204/023
FLORIDA = (30.2960, -87.0114, "2015-08-04 16:19:21.792Z")        # realdata L1T, 020/039


@pytest.mark.parametrize("lat, lon, when", [MERSEY, FLORIDA], ids=["mersey", "florida"])
def test_named_satellite_repeats_the_real_schedule(lat, lon, when):
    # The reference elements are of 2025-08-13; the scenes are 5 and 10 years older. The
    # 16-day repeat of the reference ground track puts a near-nadir pass on the scene's day
    # within a minute of its centre time (measured: 26 s early, 25 s late): the mean local
    # time of the orbit's node drifts by tens of seconds between manoeuvres, the ground track
    # is kept (WRS-2). No other pass that day or the next is within 90 s of it.
    t = pd.Timestamp(when)
    passes = satellite_overpasses("landsat8", lat, lon, t - pd.Timedelta(days=1),
                                  t + pd.Timedelta(days=1))
    near = [p for p in passes if abs((p.time_utc - t).total_seconds()) < 60.0]
    assert len(near) == 1, [p.time_utc for p in passes]
    p = near[0]
    assert p.off_nadir_deg < 2.0 and p.view_zenith_deg < 2.5
    assert "repeated every 16 days" in p.source


def test_landsat9_is_eight_days_from_landsat8_and_not_before_launch():
    lat, lon, when = MERSEY
    t = pd.Timestamp(when) + pd.Timedelta(days=16 * 80)          # 2024: both flying
    l8 = [p for p in satellite_overpasses("landsat8", lat, lon, t - pd.Timedelta(hours=1),
                                          t + pd.Timedelta(hours=1))]
    l9 = [p for p in satellite_overpasses("landsat9", lat, lon, t + pd.Timedelta(days=8) -
                                          pd.Timedelta(hours=1),
                                          t + pd.Timedelta(days=8, hours=1))]
    assert len(l8) == 1 and len(l9) == 1
    assert abs((l9[0].time_utc - l8[0].time_utc).total_seconds() - 8 * 86400) < 60.0
    assert not satellite_overpasses("landsat9", lat, lon, pd.Timestamp("2020-01-01", tz="UTC"),
                                    pd.Timestamp("2020-12-31", tz="UTC"))


def test_elements_propagated_directly_agree_with_the_named_satellite_near_their_epoch():
    lat, lon, _ = MERSEY
    sat = SATELLITES["landsat8"]
    start, end = pd.Timestamp("2025-08-05", tz="UTC"), pd.Timestamp("2025-08-20", tz="UTC")
    a = satellite_overpasses("landsat8", lat, lon, start, end)
    b = tle_overpasses("LANDSAT 8\n" + "\n".join(sat.tle), lat, lon, start, end,
                       swath_m=sat.swath_m, altitude_m=sat.altitude_m)
    assert [round(x.time_utc.timestamp()) for x in a] == [round(x.time_utc.timestamp())
                                                         for x in b]
    # a pass one cycle from the reference window is the reference pass shifted by 16 days;
    # SGP4 itself moves that track by well under 1 km (0.08 deg seen from the site)
    for x, y in zip(a, b):
        assert x.view_zenith_deg == pytest.approx(y.view_zenith_deg, abs=0.1)


def test_swath_edge_angle():
    # 185 km at 705 km: atan(R sin(θ) / (R + h - R cos θ)), θ = 92.5 km / R: 7.47 deg
    # (the flat-Earth atan(92.5 / 705) = 7.475 deg: the curvature changes it by 0.01 %)
    assert swath_half_angle(185e3, 705e3) == pytest.approx(
        math.degrees(math.atan(92.5 / 705.0)), rel=1e-3)


def test_elements_are_checked():
    l1, l2 = SATELLITES["landsat8"].tle
    assert parse_tle(f"LANDSAT 8\n{l1}\n{l2}")[0] == "LANDSAT 8"
    bad = l1[:60] + ("1" if l1[60] != "1" else "2") + l1[61:]
    with pytest.raises(InputError, match="fails its checksum"):
        parse_tle(f"{bad}\n{l2}")
    with pytest.raises(InputError, match="same satellite"):
        parse_tle(f"{l1}\n{SATELLITES['landsat9'].tle[1]}")
    with pytest.raises(InputError, match="two-line elements"):
        parse_tle("not elements at all")
    with pytest.raises(InputError, match="line 1 has 50 characters; a two-line element line "
                                         "has 69"):
        parse_tle(f"{l1[:50]}\n{l2}")
    with pytest.raises(InputError, match="calendar.satellite.*Did you mean 'landsat8'"):
        satellite_overpasses("landsat-88", 0.0, 0.0, pd.Timestamp("2024-01-01", tz="UTC"),
                             pd.Timestamp("2024-01-02", tz="UTC"))


def test_listed_instants_need_their_zone():
    ps = listed_overpasses(["2020-09-27T12:10:50+01:00", "2020-09-27T11:00:00Z"])
    assert [str(p.time_utc) for p in ps] == ["2020-09-27 11:00:00+00:00",
                                            "2020-09-27 11:10:50+00:00"]
    with pytest.raises(InputError, match="time zone"):
        listed_overpasses(["2020-09-27T11:10:50"])


def test_the_scenario_knows_every_named_satellite():
    from imaging.parameters import SATELLITE_NAMES

    assert tuple(SATELLITES) == SATELLITE_NAMES


def test_elements_far_from_the_span_are_refused():
    # SGP4 is trusted to MAX_TLE_DISTANCE_DAYS from the epoch (2025-08-13 here) at either
    # end of the span; a record of 2013 is twelve years away
    from imaging.overpass import check_tle_epoch
    from imaging.parameters import MAX_TLE_DISTANCE_DAYS

    l1 = SATELLITES["landsat8"].tle[0]
    epoch = check_tle_epoch(l1, pd.Timestamp("2025-08-01", tz="UTC"),
                            pd.Timestamp("2025-09-01", tz="UTC"))
    assert epoch.strftime("%Y-%m-%d") == "2025-08-13"
    edge = epoch + pd.Timedelta(days=MAX_TLE_DISTANCE_DAYS)
    check_tle_epoch(l1, epoch, edge - pd.Timedelta(hours=1))
    with pytest.raises(InputError, match="366 days from the epoch"):
        check_tle_epoch(l1, epoch, edge + pd.Timedelta(hours=1))
    with pytest.raises(InputError, match=r"calendar.tle = 'old.tle': holds elements of "
                                         r"2025-08-13, 4,54\d days from the record"):
        tle_overpasses("\n".join(SATELLITES["landsat8"].tle), 38.0, -74.0,
                       pd.Timestamp("2013-03-04", tz="UTC"),
                       pd.Timestamp("2013-03-06", tz="UTC"), swath_m=185e3, source="old.tle")
