"""Weather ensembles: a 3-member serial ensemble of the tiny scenario writes its folder;
the crossover medians and 5-95 % ranges equal numpy's statistics of the members' own
crossover times (recomputed here from the case files); the members really ran with their
drawn offsets; the same seed gives the same Latin-hypercube draws."""

import json

import numpy as np
import pandas as pd
import pytest
from cli_helpers import write_tiny
from scipy import stats

from shipthermal.app.cli import main
from shipthermal.app.ensemble import DISTRIBUTIONS, draw_members, parse_distribution
from shipthermal.app.scenario import loads_scenario
from shipthermal.app.sweep import load_sweep

MEMBERS = 3


@pytest.fixture(scope="module")
def ensemble(tmp_path_factory):
    d = tmp_path_factory.mktemp("ensemble")
    sc = write_tiny(d, name="tiny", days=1)
    out = d / "ens"
    code = main(["-q", "ensemble", str(sc), "--members", str(MEMBERS), "--serial",
                 "--seed", "7", "--out", str(out)])
    assert code == 0
    # signed: every top-level entry is listed as written by the tool
    manifest = json.loads((out / "manifest.json").read_text())
    assert (manifest["tool"], manifest["kind"]) == ("shipthermal", "ensemble")
    assert manifest["entries"] == sorted(p.name for p in out.iterdir())
    return out


def _member_times(out):
    """{(band, direction, order): [hours]} straight from the case files."""
    times: dict = {}
    for f in sorted((out / "cases").glob("*.json")):
        r = json.loads(f.read_text())
        assert r["status"] == "ok", r["error"]
        for band, items in r["crossovers"].items():
            count: dict = {}
            for t, direction in items:
                count[direction] = count.get(direction, 0) + 1
                times.setdefault((band, direction, count[direction]), []).append(t)
    return times


def test_ensemble_folder(ensemble):
    for name in ("crossovers.csv", "scr.csv", "members.csv", "member_crossovers.csv",
                 "ensemble.toml", "ensemble.png"):
        assert (ensemble / "ensemble" / name).is_file(), name
    assert (ensemble / "COMPLETE").is_file()
    assert len(list((ensemble / "cases").glob("*.json"))) == MEMBERS
    assert (ensemble / "ensemble" / "ensemble.png").stat().st_size > 20_000
    assert "Weather ensemble" in (ensemble / "report.html").read_text()


def test_members_ran_with_their_draws(ensemble):
    draws = pd.read_csv(ensemble / "ensemble" / "members.csv")
    np.testing.assert_allclose(
        draws.drop(columns="member").to_numpy(),
        draw_members(DISTRIBUTIONS.values(), MEMBERS, 7).drop(columns="member").to_numpy(),
        atol=1e-6)
    # the scenarios the cases ran (rebuilt from the sweep file the ensemble wrote)
    spec = load_sweep(ensemble / "sweep.toml")
    assert len(spec.cases) == MEMBERS
    for case in spec.cases:
        assert (ensemble / "cases" / f"{case.id}.json").is_file()
        w = loads_scenario(case.toml).weather
        row = draws.iloc[case.index]
        assert w.cloud_cover_offset == pytest.approx(row["weather.cloud_cover_offset"])
        assert w.wind_speed_offset == pytest.approx(row["weather.wind_speed_offset"])
        assert w.temp_air_offset == pytest.approx(row["weather.temp_air_offset"])
    # the members differ: the weather offsets move the SCR curves
    scr = pd.read_csv(ensemble / "ensemble" / "scr.csv")
    assert (scr["scr_p95"] - scr["scr_p05"]).max() > 1.0


def test_medians_and_ranges_equal_numpy_of_the_members(ensemble):
    dist = pd.read_csv(ensemble / "ensemble" / "crossovers.csv")
    times = _member_times(ensemble)
    assert len(dist) == len(times) >= 2
    for _, r in dist.iterrows():
        t = np.array(times[(r["band"], r["direction"], r["order"])])
        assert r["members"] == len(t) and r["of"] == MEMBERS
        # written with 6 decimals of an hour
        assert r["median_h"] == pytest.approx(np.median(t), abs=2e-6)
        assert r["p05_h"] == pytest.approx(np.percentile(t, 5), abs=2e-6)
        assert r["p95_h"] == pytest.approx(np.percentile(t, 95), abs=2e-6)
        assert r["p05_h"] <= r["median_h"] <= r["p95_h"]
        assert r["p05_h"] >= t.min() and r["p95_h"] <= t.max()


def test_crossover_command_prints_the_distribution(ensemble, capsys):
    assert main(["crossover", str(ensemble)]) == 0
    out = capsys.readouterr().out
    dist = pd.read_csv(ensemble / "ensemble" / "crossovers.csv", dtype=str)
    assert "5-95 % range" in out
    for m in dist["median"]:
        assert m in out


def test_same_seed_same_draws_and_latin_hypercube_strata():
    a = draw_members(DISTRIBUTIONS.values(), 10, seed=3)
    b = draw_members(DISTRIBUTIONS.values(), 10, seed=3)
    c = draw_members(DISTRIBUTIONS.values(), 10, seed=4)
    pd.testing.assert_frame_equal(a, b)
    assert not np.allclose(a.to_numpy(), c.to_numpy())
    # a Latin hypercube: each of the 10 equal-probability strata of every marginal holds
    # exactly one member (independent check through scipy's CDFs)
    cdfs = {"cloud": stats.uniform(-0.3, 0.6).cdf, "wind": stats.norm(0, 1.5).cdf,
            "air": stats.norm(0, 2.0).cdf}
    for name, cdf in cdfs.items():
        u = cdf(a[DISTRIBUTIONS[name].key].to_numpy())
        assert sorted(np.floor(u * 10).astype(int)) == list(range(10)), name


def test_parse_distribution():
    d = parse_distribution("wind=uniform:-2:2")
    assert (d.key, d.kind, d.a, d.b) == ("weather.wind_speed_offset", "uniform", -2.0, 2.0)
    np.testing.assert_allclose(d.ppf(np.array([0.25, 0.5])), [-1.0, 0.0])


def test_scr_band_equals_numpy_percentiles_of_the_member_curves(ensemble):
    band = pd.read_csv(ensemble / "ensemble" / "scr.csv")
    curves: dict = {}
    for f in sorted((ensemble / "cases").glob("*.json")):
        for b, c in json.loads(f.read_text())["curves"].items():
            curves.setdefault(b, []).append((np.array(c["time_h"]), np.array(c["scr"])))
    assert set(band["band"]) == set(curves)
    for b, members in curves.items():
        t = members[0][0]
        scr = np.vstack([s for _, s in members])          # members x frames
        assert scr.shape == (MEMBERS, len(t))
        g = band[band["band"] == b].sort_values("time_h")
        np.testing.assert_allclose(g["time_h"], t, atol=2e-6)
        p05, p50, p95 = np.percentile(scr, [5, 50, 95], axis=0)
        np.testing.assert_allclose(g["scr_p05"], p05, rtol=1e-6, atol=2e-6)
        np.testing.assert_allclose(g["scr_median"], p50, rtol=1e-6, atol=2e-6)
        np.testing.assert_allclose(g["scr_p95"], p95, rtol=1e-6, atol=2e-6)
        assert (g["scr_p05"] <= g["scr_median"]).all() and (g["scr_median"] <= g["scr_p95"]).all()
