"""The report's first screen on a hand-made SCR series: lowest SCR, its band and time, the
periods with SCR below 1 and their length, and the sentence that says so."""

from html import unescape

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.report_day import SCR_CLUTTER_LIMIT, first_screen, hardest_to_see


def _write(d, season, band, scr):
    t = np.arange(len(scr)) * (10 / 60)                            # every 10 min
    pd.DataFrame({"time_s": t * 3600, "time_h": t, "scr": scr,
                  "contrast": scr}).to_csv(d / f"metrics_{season}_{band}.csv", index=False)


def test_hardest_to_see_from_known_series(tmp_path):
    img = tmp_path / "imaging"
    img.mkdir()
    n = 145
    a = np.full(n, 5.0)
    a[36:40] = [0.8, 0.3, 0.5, 0.9]                                 # 06:00-06:30 below 1
    a[114] = 0.6                                                    # 19:00, one frame
    b = np.full(n, 3.0)
    b[37] = 1.2                                                     # never below 1
    _write(img, "summer", "3-5", a)
    _write(img, "summer", "8-14", b)
    pd.DataFrame([dict(season="summer", band="3-5", time_h=6.1, time_local="06:06",
                       direction="dark->bright")]).to_csv(img / "crossovers.csv", index=False)
    df = hardest_to_see(img).set_index("band")
    assert SCR_CLUTTER_LIMIT == 1.0
    assert df.loc["3-5", "scr_min"] == 0.3 and df.loc["3-5", "time_min"] == "06:10"
    assert df.loc["3-5", "low_periods"] == "06:00–06:30, 19:00"
    assert df.loc["3-5", "low_hours"] == pytest.approx(5 * 10 / 60, rel=1e-12)
    assert df.loc["3-5", "crossovers"] == "06:06"
    assert df.loc["8-14", "low_periods"] == "none" and df.loc["8-14", "crossovers"] == "none"
    html = unescape(first_screen(tmp_path))
    assert "hardest at <b>06:10</b> local in the <b>3-5 µm</b> band, local SCR 0.3." in html
    assert "0.8 h in all" in html and "time to ±5 min" in html
    assert "the 8-14 µm band's lowest SCR is 1.2 at 06:10 (4.0× the 3-5 µm minimum)" in html


def test_first_screen_warns_when_the_spin_up_did_not_converge(tmp_path):
    import json

    img = tmp_path / "imaging"
    img.mkdir()
    _write(img, "summer", "8-14", np.linspace(2.0, 0.5, 145))
    th = tmp_path / "thermal" / "summer"
    th.mkdir(parents=True)
    summary = {"converged": False, "day_changes_K": [None, 3.0, 2.5], "spinup_tolerance_K": 0.01}
    (th / "thermal_summary.json").write_text(json.dumps(summary))
    assert "did not converge (last day-to-day change 2.5 K, tolerance 0.01 K)" in \
        first_screen(tmp_path)
    summary["converged"] = True
    (th / "thermal_summary.json").write_text(json.dumps(summary))
    assert "did not converge" not in first_screen(tmp_path)


def test_crossover_between_frames_is_a_zero_of_the_scr(tmp_path):
    """Frames every 10 min with SCR 3 on either side of a sign change of the contrast:
    the frames never show an SCR below 1, but the contrast passes through zero between
    them. Linear in between, the signed SCR goes from +3 to -3 over 10 min: zero at
    the middle, below 1 for 10 min x 2 / 6 = 3.33 min."""
    img = tmp_path / "imaging"
    img.mkdir()
    n = 145
    t = np.arange(n) * (10 / 60)
    contrast = np.where(t < 6.05, 3.0, -3.0)                          # sign change 06:00 -> 06:10
    pd.DataFrame({"time_s": t * 3600, "time_h": t, "scr": np.abs(contrast),
                  "contrast": contrast}).to_csv(img / "metrics_summer_8-14.csv", index=False)
    pd.DataFrame([dict(season="summer", band="8-14", time_h=6.0 + 4 / 60, time_local="06:04",
                       direction="bright->dark")]).to_csv(img / "crossovers.csv", index=False)
    df = hardest_to_see(img).set_index("band")
    assert df.loc["8-14", "scr_min"] == 0.0 and df.loc["8-14", "time_min"] == "06:04"
    assert df.loc["8-14", "low_periods"] == "06:04"
    assert df.loc["8-14", "low_hours"] == pytest.approx(10 / 60 * 2 / 6, rel=1e-12)
    html = unescape(first_screen(tmp_path))
    assert "never falls below" not in html and "above the background clutter all day" not in html
    assert "hardest at <b>06:04</b>" in html and "SCR below 1" in html
    # without the crossovers file the zero is placed by the linear signed SCR: 06:05
    (img / "crossovers.csv").unlink()
    assert hardest_to_see(img).loc[0, "time_min"] == "06:05"


def test_series_names_with_underscores_in_season_and_band():
    from shipthermal.app.report_day import split_series_name

    assert split_series_name("summer_3-5") == ("summer", "3-5")
    assert split_series_name("subarctic_summer_8-14") == ("subarctic_summer", "8-14")
    assert split_series_name("us_standard_1976_landsat8_tirs_b10") == (
        "us_standard_1976", "landsat8_tirs_b10")
    assert split_series_name("winter_3.7-4.8") == ("winter", "3.7-4.8")
