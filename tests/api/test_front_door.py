"""The front door: ``shipthermal.Simulation`` from a scenario to images, SCR, crossovers and
the report, checked against the command line on the same tiny scenario (a coarse patrol
boat, 30-min steps: ``tests/cli/cli_helpers.py``).

One thermal run each way, shared by the tests: ``SNIPPET`` (the documented four lines)
and ``shipthermal run --image`` on the same file.
"""

import importlib.metadata
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "cli"))
from cli_helpers import write_tiny  # noqa: E402

from shipthermal.errors import InputError  # noqa: E402

#: An image at a chosen time and band from one import: the README's and the tutorial's
#: promise (at most five lines)
SNIPPET = """\
import shipthermal as st
sim = st.Simulation(SCENARIO, progress=False)
res = sim.run()
img = res.image("2023-07-15 13:00", band="8-14")
"""


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    d = tmp_path_factory.mktemp("front")
    return write_tiny(d, name="tiny")


@pytest.fixture(scope="module")
def snippet(tiny):
    """The namespace after running :data:`SNIPPET` (the whole chain, once)."""
    ns = {"SCENARIO": str(tiny)}
    exec(compile(SNIPPET, "<snippet>", "exec"), ns)
    return ns


@pytest.fixture(scope="module")
def cli_run(tiny):
    """``shipthermal run --image`` on the same scenario file."""
    from shipthermal.app.cli import main

    out = tiny.parent / "runs" / "tiny"
    assert main(["-q", "run", str(tiny), "--out", str(out), "--image"]) == 0
    return out


def test_an_image_in_at_most_five_lines_from_one_import(snippet):
    lines = [ln for ln in SNIPPET.splitlines() if ln.strip()]
    imports = [ln for ln in lines if ln.startswith(("import ", "from "))]
    assert len(lines) <= 5 and imports == ["import shipthermal as st"], lines
    import xarray as xr

    assert isinstance(snippet["img"], xr.DataArray)


def test_the_image_has_map_coordinates_units_crs_and_time(snippet):
    img, res = snippet["img"], snippet["res"]
    assert img.dims == ("y", "x") and img.shape == (100, 100)
    assert img.attrs["units"] == "W m-2 sr-1" and img.attrs["band"] == "8-14"
    # 30 m pixels, row 0 north; map coordinates of the synthetic port's UTM grid
    assert np.allclose(np.diff(img.x), 30.0) and np.allclose(np.diff(img.y), -30.0)
    assert img.x.attrs["units"] == "m" and img.y.attrs["units"] == "m"
    assert "UTM zone" in img.attrs["crs_wkt"]
    assert img.spatial_ref.attrs["crs_wkt"] == img.attrs["crs_wkt"]
    # 13:00 at UTC+8 is 05:00 UTC
    assert img.time.values == np.datetime64("2023-07-15T05:00:00")
    assert img.attrs["local_time"] == "2023-07-15T13:00:00+08:00"
    assert bool((img.ship_coverage > 0).any()) and bool(np.isfinite(img).all())
    assert float(img.min()) > 0.0


def test_the_image_is_the_frame_the_series_measured(snippet):
    """``image()`` renders through the same chain as the SCR series: its local SCR is the
    series' value at that moment."""
    from imaging.metrics import local_scr

    img, res = snippet["img"], snippet["res"]
    m = local_scr(img.values, img.ship_coverage.values > 0)
    row = res.metrics("8-14").loc[pd.Timestamp("2023-07-15 13:00", tz="Etc/GMT-8")]
    assert m.scr == pytest.approx(row["scr"], rel=1e-6)
    assert m.contrast == pytest.approx(row["contrast"], rel=1e-6)


def test_times_in_every_form_name_the_same_moment(snippet):
    res = snippet["res"]
    forms = ["13:00", 13.0, "2023-07-15 13:00", pd.Timestamp("2023-07-15 05:00", tz="UTC"),
             pd.Timedelta(hours=13), np.datetime64("2023-07-15T13:00")]
    assert {res.seconds(f) for f in forms} == {13 * 3600.0}
    with pytest.raises(InputError, match="must lie within the simulated span 2023-07-15 00:00"):
        res.seconds("2023-07-16 13:00")
    with pytest.raises(InputError, match="must be a time"):
        res.seconds("noon-ish")


def test_other_quantities_views_and_several_times(snippet):
    res = snippet["res"]
    bt = res.image(["06:00", "13:00"], "lwir", quantity="brightness_temperature")
    assert bt.dims == ("time", "y", "x") and bt.attrs["units"] == "K"
    assert 250.0 < float(bt.min()) < float(bt.max()) < 350.0
    # the apparent temperature at noon is warmer than at dawn over the ship
    ship = bt.ship_coverage == bt.ship_coverage.max()
    assert float(bt[1].where(ship).mean()) > float(bt[0].where(ship).mean())
    oblique = res.image("13:00", "8-14", view=(40.0, 90.0))
    assert oblique.attrs["view_zenith_deg"] == 40.0
    assert not np.array_equal(oblique.ship_coverage, snippet["img"].ship_coverage)
    with pytest.raises(InputError, match=r"must be one of the scenario's imaging bands \(3-5, "
                       r"8-14\)"):
        res.image("13:00", "1-2")
    with pytest.raises(InputError, match="must be one of radiance"):
        res.image("13:00", "8-14", quantity="colour")


def test_part_means_scr_and_surface_carry_time_and_units(snippet):
    res = snippet["res"]
    pm = res.part_means
    assert isinstance(pm.index, pd.DatetimeIndex) and str(pm.index.tz) == "Etc/GMT-8"
    assert pm.index[0] == pd.Timestamp("2023-07-15 00:00", tz="Etc/GMT-8")
    assert pm.attrs["units"]["deck"] == "K"
    assert pm.loc["2023-07-15 12:00+08:00", "deck"] == pytest.approx(
        res.thermal.part_mean_at("deck", 12.0))
    scr = res.scr
    assert list(scr.columns) == ["3-5", "8-14"] and scr.index.tz is not None
    assert scr.index[1] - scr.index[0] == pd.Timedelta(minutes=10)
    s = res.surface("13:00")
    assert s.dims == ("face",) and s.attrs["units"] == "K"
    assert set(np.unique(s.part.values)) >= {"deck"}
    assert np.allclose(s.values, res.history.at(13 * 3600.0))


def _csv(path):
    """A product table of the command line with its ``name [unit]`` headers as names."""
    from shipthermal.units import strip_units

    return strip_units(pd.read_csv(path))


def test_crossovers_are_tz_aware_and_those_of_the_command_line(snippet, cli_run):
    res = snippet["res"]
    ours = res.crossovers
    assert str(ours["time"].dt.tz) == "Etc/GMT-8" and len(ours) >= 2
    cli = _csv(cli_run / "imaging" / "crossovers.csv")
    cli = cli.sort_values("time_h").reset_index(drop=True)
    assert list(ours["band"]) == list(cli["band"])
    assert list(ours["direction"]) == list(cli["direction"])
    hours = (ours["time"] - res.start).dt.total_seconds().to_numpy() / 3600.0
    assert np.abs(hours - cli["time_h"].to_numpy()).max() < 1.0 / 3600.0
    assert list(ours["time"].dt.round("min").dt.strftime("%H:%M")) == list(cli["time_local"])


def test_every_frame_measures_what_the_command_line_measured(snippet, cli_run):
    res = snippet["res"]
    for band in ("3-5", "8-14"):
        cli = _csv(cli_run / "imaging" / f"metrics_summer_{band}.csv")
        ours = res.metrics(band)
        assert len(ours) == len(cli)
        assert np.allclose(ours["scr"].to_numpy(), cli["scr"].to_numpy(), rtol=1e-6)


def test_paper_crossover_rows_image_the_scene_of_run_image(snippet, cli_run):
    """Validation and calibration image a scenario through the chain (the background,
    mooring and sensor of the scenario): their crossover moments are those of
    ``run --image``."""
    from shipthermal.app.chain import Simulation
    from shipthermal.app.paper import crossover_rows

    res = snippet["res"]
    again = Simulation(res.scenario, progress=False).result_from(res.thermal)
    rows = pd.DataFrame(crossover_rows({"summer": again}))
    cli = _csv(cli_run / "imaging" / "crossovers.csv")
    for band in ("3-5", "8-14"):
        ours = rows.loc[rows["band"] == band, "ours"].item()
        assert ours == ", ".join(cli.loc[cli["band"] == band, "time_local"]), band


def test_save_writes_the_files_of_run_image(snippet, cli_run, tmp_path):
    res = snippet["res"]
    out = res.save(tmp_path / "saved")

    def files(root):
        return sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file())

    assert files(out) == files(cli_run)
    m = json.loads((out / "manifest.json").read_text())
    assert (m["kind"], m["status"]) == ("run", "complete")
    a = pd.read_csv(out / "imaging" / "crossovers.csv")
    b = pd.read_csv(cli_run / "imaging" / "crossovers.csv")
    pd.testing.assert_frame_equal(a, b)


def test_the_report(snippet, tmp_path):
    from shipthermal.app.report import is_report_file

    path = snippet["res"].report(tmp_path / "out" / "report.html")
    assert is_report_file(path)
    text = path.read_text()
    assert "crossover" in text and "<script" in text
    assert not list(tmp_path.glob("shipthermal-report-*"))
    with pytest.raises(InputError, match="must name an .html file"):
        snippet["res"].report(tmp_path / "report.txt")


def test_reprs_are_a_few_lines(snippet):
    sim, res = snippet["sim"], snippet["res"]
    for obj in (sim, res):
        text = repr(obj)
        assert len(text) < 700 and len(text.splitlines()) <= 7, text
        assert "tiny" in text and "<table>" in obj._repr_html_()
    assert "thermal and imaging done" in repr(sim)
    first = res.crossovers["time"].iloc[0].round("min").strftime("%H:%M")
    assert "crossovers" in repr(res) and first in repr(res)
    # the results underneath print a line, not their arrays
    assert len(repr(res.thermal)) < 400
    assert len(repr(res.series["8-14"])) < 300


def test_changes_are_validated_and_nothing_runs_until_asked(tiny):
    import shipthermal as st

    sim = st.Simulation(tiny, {"ship.edge_length": 4.0}, **{"imaging.bands": ["8-14"]})
    assert sim.scenario.ship.edge_length == 4.0 and sim.scenario.bands == ("8-14",)
    assert sim.status == "not run" and sim._ship is None
    other = sim.with_changes({"ship.heading": 90.0})
    assert other.scenario.ship.heading == 90.0 and sim.scenario.ship.heading != 90.0
    with pytest.raises(InputError, match="ship.edge_length"):
        st.Simulation(tiny, {"ship.edge_length": -1.0})
    with pytest.raises(InputError, match="must be a scenario file"):
        st.Simulation(tiny.parent / "missing.toml")
    assert st.Simulation.default("winter").scenario.time.season == "winter"


def test_top_level_exports_version_and_a_light_import():
    import imaging
    import shipthermal as st

    assert st.__version__ == importlib.metadata.version("shipthermal") == imaging.__version__
    assert {"Simulation", "SimulationResult", "Scenario", "load_scenario"} <= set(dir(st))
    assert st.Simulation.__module__ == "shipthermal.app.chain"
    assert imaging.render_series.__module__ == "imaging.experiment"
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        st.nope  # noqa: B018
    # importing the package pulls in nothing heavy: the exports come on first use
    code = ("import sys, shipthermal, imaging; "
            "print(sorted(m for m in ('numpy', 'pandas', 'scipy', 'xarray', "
            "'shipthermal.app') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]", out
