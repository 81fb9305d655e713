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
    assert "hardest at <b>06:10</b> local in the <b>3–5 µm</b> band, local SCR 0.3." in html
    assert "0.8 h in all" in html and "time to ±5 min" in html
    assert "the 8–14 µm band's lowest SCR is 1.2 at 06:10 (4.0× the 3–5 µm minimum)" in html


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


def _series(img, season="summer", band="8-14", n=145, collapse_at=None):
    """A day of frames every 10 min: contrast from the ship-water temperature difference
    (+2 K/h from 05:00 to 06:00 past water at 296.1 K: a crossover at 05:33, between
    frames), a steady background spread that
    collapses to 5 % at ``collapse_at`` (frame index)."""
    t = np.arange(n) * (10 / 60)
    ship = np.where(t < 5.0, 295.0, np.where(t < 6.0, 295.0 + 2.0 * (t - 5.0), 297.0))
    water = np.full(n, 296.1)
    contrast = 0.3 * (ship - water)
    std = np.full(n, 0.05)
    if collapse_at is not None:
        std[collapse_at] = 0.0025
    pd.DataFrame({"time_s": t * 3600, "time_h": t, "scr": np.abs(contrast) / std,
                  "contrast": contrast, "std_background": std, "ship_mean_temp": ship,
                  "water_mean_temp": water, "tau_300k": 0.5}).to_csv(
        img / f"metrics_{season}_{band}.csv", index=False)


def _summary(img):
    import json

    (img / "summary.json").write_text(json.dumps({"scenarios": {"summer": {
        "date": "2023-07-15", "tz": "Etc/GMT-8", "latitude": -33.9, "longitude": -70.5,
        "background": "synthetic port (not a real place) centred on 33.90 S 70.50 W"}}}))


def test_first_screen_names_the_zone_the_hemispheres_and_the_background(tmp_path):
    img = tmp_path / "imaging"
    img.mkdir()
    _series(img)
    _summary(img)
    html = unescape(first_screen(tmp_path))
    assert "hardest at <b>05:33</b> local (UTC+8)" in html
    assert "Times are local = UTC+8 (Etc/GMT-8)." in html
    assert "33.90 S 70.50 W" in html
    assert "Background: a synthetic port, not a real place" in html
    assert '<th>at (UTC+8)</th>' in html


def test_crossover_sensitivity_is_the_error_over_the_rate_the_temperatures_part(tmp_path):
    """Ship and water part at 2 K/h around the crossover: 1 K of error moves it 30 min."""
    img = tmp_path / "imaging"
    img.mkdir()
    _series(img)
    df = hardest_to_see(img)
    (t0, minutes), = df.loc[0, "zeros"]
    assert t0 == pytest.approx(5.55) and minutes == pytest.approx(30.0, rel=1e-9)
    assert "8–14 µm crossovers 05:33 ±30 min per 1 K error" in unescape(first_screen(tmp_path))


def test_scr_spike_from_a_collapsing_background_is_explained_and_marked(tmp_path):
    img = tmp_path / "imaging"
    img.mkdir()
    _series(img, collapse_at=102)                                    # 17:00
    df = hardest_to_see(img)
    top = df.loc[0, "collapsed"][0]
    assert top["time_h"] == pytest.approx(17.0) and top["std"] == pytest.approx(0.0025)
    html = unescape(first_screen(tmp_path))
    assert "SCR peak of 108 at 17:00" in html and "5 % of its median over 2 h" in html
    assert "▼" in html.split("<svg", 1)[1]
    # no collapse, no sentence
    _series(img)
    assert "spread collapsing" not in unescape(first_screen(tmp_path))


def test_one_chart_per_season_with_both_bands_on_a_log_scale(tmp_path):
    img = tmp_path / "imaging"
    img.mkdir()
    _series(img, band="3-5")
    _series(img, band="8-14")
    html = first_screen(tmp_path)
    assert html.count('<svg class="scr"') == 1
    svg = html.split('<svg class="scr"', 1)[1].split("</svg>", 1)[0]
    assert "3–5 µm" in svg and "8–14 µm" in svg and "SCR = 1" in svg and "log scale" in svg
    assert svg.count("<polyline") == 2


def test_slider_adds_the_key_moments_to_the_hours(tmp_path):
    from shipthermal.app.report_day import key_moments, slider_hours

    img = tmp_path / "imaging"
    img.mkdir()
    _series(img)
    df = hardest_to_see(img)
    assert key_moments(df) == [("lowest SCR 05:33 (summer 8–14 µm)", pytest.approx(5.55))]
    hours = slider_hours(df, np.arange(145) * (10 / 60))
    assert hours == pytest.approx(sorted(set(range(25)) | {5.5}))    # on the nearest frame


def test_ensemble_distribution_answers_how_sure(tmp_path):
    ens = tmp_path / "ensemble"
    ens.mkdir()
    pd.DataFrame([dict(season="summer", band="8-14", direction="dark->bright", order=1,
                       members=8, of=8, median="05:20", p05="05:02", p95="05:41")]).to_csv(
        ens / "crossovers.csv", index=False)
    html = unescape(first_screen(tmp_path))
    assert "median 05:20, 5–95 % 05:02–05:41 over 8 of 8 weather members" in html


def test_the_slow_day_night_swing_of_the_spread_is_not_a_collapse(tmp_path):
    """A spread that halves and doubles over the day (a factor 4 from night to noon) marks
    nothing; one frame falling to a third of its neighbours does."""
    from shipthermal.app.report_day import _collapsed_spread

    t = np.arange(145) * (10 / 60)
    std = 0.05 * 2.0 ** np.sin(2 * np.pi * t / 24.0)
    m = pd.DataFrame({"time_h": t, "scr": 1.0 / std, "std_background": std})
    assert _collapsed_spread(m) == []
    std[100] /= 3.0
    m["std_background"], m["scr"] = std, 1.0 / std
    assert [r["time_h"] for r in _collapsed_spread(m)] == [pytest.approx(t[100])]


def test_surface_frames_are_the_triangles_drawn_frame_by_frame(tmp_path):
    """The slider's frames (one picture of triangle indices, coloured per frame) show what
    drawing every triangle for every frame showed: a faceted sphere whose temperatures
    move round it over the day, compared pixel by pixel with a direct PolyCollection
    drawing of the same figure."""
    import base64
    import io

    import matplotlib.pyplot as plt
    import trimesh
    from PIL import Image

    from imaging.thermal_history import ShipThermalHistory
    from shipthermal.app.pipeline import save_history
    from shipthermal.app.report_day import _surface_frames
    from shipthermal.geometry.surface_maps import surface_frame_figure

    mesh = trimesh.creation.icosphere(subdivisions=3, radius=5.0)
    v, f = mesh.vertices + [0.0, 0.0, 6.0], mesh.faces
    times = np.arange(0.0, 86400.0 + 1.0, 3600.0)
    centre = mesh.triangles_center
    temp = 290.0 + 20.0 * np.cos(np.arctan2(centre[:, 1], centre[:, 0])[None, :]
                                 - 2 * np.pi * times[:, None] / 86400.0)
    save_history(ShipThermalHistory(v, f, np.zeros(len(f), int), ("hull",), times, temp,
                                    label="sphere"), tmp_path / "history.npz")
    hours = (6.0, 12.0)
    uris, _ = _surface_frames(tmp_path, "sphere", hours)

    def pixels(data):
        return np.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(int)

    got = [pixels(base64.b64decode(u.split(",", 1)[1])) for u in uris]
    assert np.mean(np.abs(got[0] - got[1]).max(axis=-1) > 30) > 0.05   # the day moves
    # the reference: every triangle drawn for the frame (the same figure otherwise)
    vmin, vmax = np.nanpercentile(temp[[6, 12]], [0.5, 99.5])
    for k, hour in enumerate(hours):
        fig, _, coll, title, order = surface_frame_figure(v, f, vmin, vmax)
        coll.set_array(temp[int(hour)][order])
        title.set_text(f"sphere, {int(hour):02d}:00 local")
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        plt.close(fig)
        ref = pixels(buf.getvalue())
        assert ref.shape == got[k].shape
        diff = np.abs(ref - got[k]).max(axis=-1)
        # colour rounding (a level or two) everywhere; another triangle nowhere
        assert np.mean(diff > 12) < 2e-3, (hour, np.mean(diff > 12))
