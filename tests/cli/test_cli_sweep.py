"""Sweeps on dask.distributed: an 8-case sweep on a 2-worker LocalCluster gives the same
table as the cases run one by one; re-running skips finished cases; a failing case is
reported with its error and the others still finish."""

import json

import numpy as np
import pandas as pd
import pytest
from cli_helpers import write_tiny

from shipthermal.app.cli import main
from shipthermal.app.sweep import load_sweep, run_case, run_sweep

# columns that legitimately differ between runs (wall times, which process ran the case)
VOLATILE = ("seconds", "thermal_s", "imaging_s", "worker")

SWEEP = """\
name = "eight"
base = "tiny.toml"
stages = ["thermal"]
[set]
"solver.spinup_max_days" = 1
[axes]
"ship.heading" = [0, 90, 180, 270]
"weather.wind_speed_offset" = [-1.0, 1.0]
"""


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("sweep")
    write_tiny(d)
    path = d / "eight.toml"
    path.write_text(SWEEP)
    return path


@pytest.fixture(scope="module")
def serial(sweep_file, tmp_path_factory):
    """The 8 cases run one by one in this process (the reference)."""
    out = tmp_path_factory.mktemp("serial")
    return run_sweep(load_sweep(sweep_file), out, serial=True, progress=False), out


def _stable(table):
    return table.drop(columns=[c for c in VOLATILE if c in table]).reset_index(drop=True)


def test_sweep_on_two_workers_equals_serial(sweep_file, serial, tmp_path):
    spec = load_sweep(sweep_file)
    assert len(spec.cases) == 8
    assert len({c.id for c in spec.cases}) == 8
    par = run_sweep(spec, tmp_path / "par", n_workers=2, progress=False)
    assert par.workers == 2 and par.ran == 8 and par.failed == 0
    assert (par.table["status"] == "ok").all()
    # the cases really ran on two worker processes, not here
    assert par.table["worker"].nunique() == 2
    ser = serial[0]
    # same code, inputs and seeds, single-threaded steps: bit-identical results
    pd.testing.assert_frame_equal(_stable(par.table), _stable(ser.table), check_exact=True)
    # the axes matter (the table is not 8 copies of one case): heading moves the deck mean
    # and more wind cools it at noon
    t = par.table
    assert t["deck_12h_K"].nunique() == 8
    for h in (0, 90, 180, 270):
        rows = t[t["ship.heading"] == h].set_index("weather.wind_speed_offset")
        assert rows.loc[1.0, "deck_12h_K"] < rows.loc[-1.0, "deck_12h_K"]
    # the CSV holds the same table
    csv = pd.read_csv(tmp_path / "par" / "table.csv")
    np.testing.assert_allclose(csv["deck_12h_K"], t["deck_12h_K"], atol=1e-6)
    assert (tmp_path / "par" / "table.png").stat().st_size > 10_000


def test_rerun_skips_finished_cases_and_one_case_equals_a_single_run(sweep_file, serial):
    spec = load_sweep(sweep_file)
    first, out = serial
    again = run_sweep(spec, out, serial=True, progress=False)
    assert again.ran == 0 and again.skipped == 8
    pd.testing.assert_frame_equal(first.table, again.table)
    # a case = the scenario run on its own (the case TOML is a complete scenario)
    from shipthermal.app.thermal import run_scenario_thermal
    from shipthermal.app.scenario import loads_scenario

    case = spec.cases[3]
    res = run_scenario_thermal(loads_scenario(case.toml), progress=False)
    row = first.table.set_index("case").loc[case.id]
    assert row["deck_12h_K"] == res.part_mean_at("deck", 12.0)
    assert row["days"] == res.days == 1


def test_failed_case_is_reported_not_lost(tmp_path, capsys):
    """One case reads a weather file whose content is bad (found only when it runs): the
    table keeps its error, the other case finishes, the exit code says 'failure' (1), and a
    re-run retries only the failed case."""
    write_tiny(tmp_path)
    (tmp_path / "broken.csv").write_text("time,temp_air\n2023-07-15T00:00+08:00,20\n")
    (tmp_path / "s.toml").write_text(
        'base = "tiny.toml"\nstages = ["thermal"]\n[set]\n"solver.spinup_max_days" = 1\n'
        '[[axes.weather]]\n"weather.source" = "builtin"\n'
        '[[axes.weather]]\n"weather.source" = "broken.csv"\n"weather.temp_sea" = 295.0\n')
    out = tmp_path / "out"
    assert main(["-q", "sweep", str(tmp_path / "s.toml"), "--serial", "--out", str(out)]) == 1
    text = capsys.readouterr().out
    table = pd.read_csv(out / "table.csv")
    assert list(table["status"]) == ["ok", "failed"]
    err = table.loc[1, "error"]
    assert err.startswith("InputError") and "missing required column" in err
    assert f"failed: {err}" in text
    case = json.loads(next((out / "cases").glob("0001-*.json")).read_text())
    assert "Traceback" in case["traceback"] and case["status"] == "failed"
    # retry: the ok case is skipped, the failed one runs (and fails) again
    assert main(["-q", "sweep", str(tmp_path / "s.toml"), "--serial", "--out", str(out)]) == 1
    assert "1 ran, 1 skipped" in capsys.readouterr().out
    assert (out / "COMPLETE").is_file()
    assert "missing required column" in (out / "report.html").read_text()


def test_season_axis_moves_the_season_defaults(tmp_path):
    """time.season on the built-in base also moves date, image times and compartment air to
    the winter defaults (changes go to the raw scenario before validation)."""
    (tmp_path / "s.toml").write_text('base = "summer"\n[axes]\n"time.season" = '
                                     '["summer", "winter"]\n')
    spec = load_sweep(tmp_path / "s.toml")
    from shipthermal.app.scenario import default_scenario, loads_scenario

    for case, season in zip(spec.cases, ("summer", "winter")):
        assert loads_scenario(case.toml) == default_scenario(season)


def test_run_case_never_raises():
    r = run_case({"id": "x", "index": 0, "changes": {}, "labels": {}, "toml": "not = [toml",
                  "stages": ["thermal"]})
    assert r["status"] == "failed" and "must be valid TOML" in r["error"]


def test_sweep_with_imaging_columns(tmp_path):
    """Thermal + imaging cases (8-14 um only, 10-min frames, 100-pixel port): per-band
    crossover times and SCR range land in the table, and both headings cross over twice a
    day (the moored ship is warmer than the water by day, colder by night)."""
    write_tiny(tmp_path)
    (tmp_path / "s.toml").write_text(
        'base = "tiny.toml"\n[set]\n"solver.spinup_max_days" = 1\n"imaging.bands" = ["8-14"]\n'
        '[axes]\n"ship.heading" = [0, 90]\n')
    res = run_sweep(load_sweep(tmp_path / "s.toml"), tmp_path / "out", serial=True,
                    progress=False)
    t = res.table
    assert list(t["status"]) == ["ok", "ok"], list(t["error"])
    for col in ("crossovers_8-14", "n_crossovers_8-14", "scr_min_8-14", "scr_max_8-14"):
        assert col in t
    assert not [c for c in t.columns if c.endswith("3-5")]
    assert (t["scr_max_8-14"] > t["scr_min_8-14"]).all()
    assert (t["scr_min_8-14"] >= 0).all()
    assert (t["n_crossovers_8-14"] == 2).all()


def test_existing_scheduler_by_address(sweep_file, serial, tmp_path, capsys):
    """`sweep --scheduler ADDRESS` sends the cases to a running cluster (here a LocalCluster
    started by the test) instead of starting one; results equal the serial ones."""
    from dask.distributed import LocalCluster

    text = SWEEP.replace('"ship.heading" = [0, 90, 180, 270]', '"ship.heading" = [90]')
    (sweep_file.parent / "two.toml").write_text(text.replace('name = "eight"', 'name = "two"'))
    with LocalCluster(n_workers=1, threads_per_worker=1, dashboard_address=None,
                      silence_logs=40) as cluster:
        code = main(["sweep", str(sweep_file.parent / "two.toml"), "--scheduler",
                     cluster.scheduler_address, "--out", str(tmp_path / "o")])
        assert code == 0
        assert f"dask: 1 workers at {cluster.scheduler_address}" in capsys.readouterr().err
    t = pd.read_csv(tmp_path / "o" / "table.csv")
    ref = serial[0].table
    ref = ref[ref["ship.heading"] == 90].reset_index(drop=True)
    np.testing.assert_array_equal(t["deck_12h_K"].round(6), ref["deck_12h_K"].round(6))
    manifest = json.loads((tmp_path / "o" / "manifest.json").read_text())
    assert manifest["settings"]["scheduler"] == cluster.scheduler_address
