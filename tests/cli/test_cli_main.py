"""The command line: help everywhere, quiet/verbose, exit codes, the subcommands on a tiny
run (image, crossover, report, mesh, validate plumbing)."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from shipthermal.app import cli
from shipthermal.app.cli import main
from shipthermal.errors import InputError

from cli_helpers import write_tiny
from shipthermal.units import strip_units

COMMANDS = ["demo", "mesh", "run", "image", "crossover", "validate", "sweep", "ensemble", "report"]


@pytest.mark.parametrize("command", [None] + COMMANDS)
def test_help_everywhere(command, capsys):
    argv = ([command] if command else []) + ["--help"]
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 0
    text = capsys.readouterr().out
    assert "usage: shipthermal" in text
    if command is None:
        for c in COMMANDS:          # every subcommand is listed at the top
            assert c in text
    else:
        assert "-q, --quiet" in text and "-v, --verbose" in text


def test_console_script_and_module_entry(tmp_path):
    """The installed `shipthermal` script and `python -m shipthermal` both answer; a user
    error exits 2 with the message only (no traceback)."""
    exe = subprocess.run([sys.executable, "-m", "shipthermal", "run", str(tmp_path / "no.toml")],
                         capture_output=True, text=True, cwd=tmp_path)
    assert exe.returncode == 2
    assert "must be an existing TOML file" in exe.stderr
    assert "Traceback" not in exe.stderr
    assert list(tmp_path.iterdir()) == []
    script = subprocess.run([str(sys.executable).rsplit("/", 1)[0] + "/shipthermal", "--help"],
                            capture_output=True, text=True)
    assert script.returncode == 0 and "sweep" in script.stdout


def _boom(args, con):
    raise RuntimeError("something broke inside")


def _interrupt(args, con):
    raise KeyboardInterrupt


def _user(args, con):
    raise InputError("ship.heading", 400, "must lie in [0, 360) deg")


@pytest.mark.parametrize("func, code, verbose, fragments, absent", [
    (_boom, 1, False, ["internal error: RuntimeError: something broke inside", "-v"],
     ["Traceback"]),
    (_boom, 1, True, ["internal error", "Traceback", "_boom"], []),
    (_interrupt, 130, False, ["interrupted", "--resume"], ["Traceback"]),
    (_user, 2, True, ["error: ship.heading = 400: must lie in [0, 360) deg"], ["Traceback"]),
])
def test_exit_codes(monkeypatch, capsys, func, code, verbose, fragments, absent):
    monkeypatch.setattr(cli, "cmd_crossover", func)
    argv = (["-v"] if verbose else []) + ["crossover", "anything"]
    assert main(argv) == code
    err = capsys.readouterr().err
    for f in fragments:
        assert f in err
    for a in absent:
        assert a not in err


def test_quiet_prints_results_only(imaged_run, capsys):
    assert main(["-q", "crossover", str(imaged_run)]) == 0
    cap = capsys.readouterr()
    assert cap.err == ""
    assert "thermal crossover moments" in cap.out


def test_options_after_the_subcommand(imaged_run, capsys):
    assert main(["crossover", str(imaged_run), "--csv", "-q"]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0] == ("season,band,time_h [h],date_local [UTC+8],time_local [UTC+8],"
                                   "direction")


def test_run_directory_of_a_run_with_imaging(imaged_run):
    """Layout, manifest contents, marker, no temporaries; crossovers printed = the CSV."""
    names = {p.name for p in imaged_run.iterdir()}
    assert {"COMPLETE", "manifest.json", "scenario.toml", "thermal", "imaging",
            "report.html"} <= names
    assert "checkpoints" not in names and ".lock" not in names
    assert not [p for p in imaged_run.rglob("*") if ".tmp" in p.name or ".part-" in p.name
                or p.name.startswith(".stage-")]
    m = json.loads((imaged_run / "manifest.json").read_text())
    assert m["status"] == "complete" and m["finished"]
    for pkg in ("numpy", "scipy", "embreex", "pyvista"):
        assert m["versions"][pkg]
    assert m["seeds"]["tiny"] == {"solver": 0, "background": 2026}
    assert {"thermal/tiny", "imaging", "report", "total"} <= set(m["timings_s"])
    assert m["command"][-3:] == ["--out", str(imaged_run), "--image"]
    th = imaged_run / "thermal" / "tiny"
    for f in ("part_means.csv", "thermal_summary.json", "energy.csv", "history.npz",
              "part_means.png", "surface_0700.png", "surface_1200.png"):
        assert (th / f).is_file(), f
    im = imaged_run / "imaging"
    for f in ("crossovers.csv", "panels_3-5.png", "scr_8-14.png", "metrics_summer_3-5.csv",
              "images_summer_8-14.nc"):
        assert (im / f).is_file(), f


def test_history_file_is_the_thermal_result(imaged_run):
    """history.npz (the imaging input) holds the recorded day: its deck area mean equals the
    part_means.csv column (same triangles, same area weights). The CSV is written with 4
    decimals, hence 5e-5 K."""
    from shipthermal.app.pipeline import load_history

    h = load_history(imaged_run / "thermal" / "tiny" / "history.npz")
    pm = strip_units(pd.read_csv(imaged_run / "thermal" / "tiny" / "part_means.csv", index_col=0))
    assert pm.attrs["units"] == {"hour": "h", **{c: "K" for c in pm.columns}}
    np.testing.assert_allclose(h.times_s / 3600.0, pm.index.to_numpy(), atol=1e-9)
    tri = h.vertices[h.faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    deck = np.array([n == "deck" or n.startswith("deck_") for n in h.part_names])[h.face_part]
    mean = (h.face_temperature[:, deck] * area[deck]).sum(axis=1) / area[deck].sum()
    np.testing.assert_allclose(mean, pm["deck"].to_numpy(), atol=5e-5)


def test_image_command_reimages_with_another_step(imaged_run, tmp_path, capsys):
    """`image` on a finished run replaces the imaging stage (30-min frames: 49 rows per
    band instead of the scenario's 145), keeps COMPLETE and lists itself in the manifest's
    amendments. (On a copy: the session's run stays as the other tests read it.)"""
    import shutil

    imaged_run = Path(shutil.copytree(imaged_run, tmp_path / "copy"))
    assert len(pd.read_csv(imaged_run / "imaging" / "metrics_summer_3-5.csv")) == 145
    assert main(["-q", "image", str(imaged_run), "--step-min", "30"]) == 0
    metrics = pd.read_csv(imaged_run / "imaging" / "metrics_summer_3-5.csv")
    # 00:00..24:00 every 30 min plus the image times 01:00, 06:00, 07:00, 13:00 (on the grid)
    assert len(metrics) == 49
    assert (imaged_run / "COMPLETE").is_file()
    m = json.loads((imaged_run / "manifest.json").read_text())
    assert m["amendments"][-1]["kind"] == "image" and m["amendments"][-1]["status"] == "done"
    out = capsys.readouterr().out
    cross = strip_units(pd.read_csv(imaged_run / "imaging" / "crossovers.csv"))
    for t in cross["time_local"]:
        assert t in out


def test_mesh_command(tmp_path, capsys):
    out = tmp_path / "m"
    sc = write_tiny(tmp_path)
    assert main(["-q", "mesh", str(sc), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    rep = json.loads((out / "mesh" / "mesh_report.json").read_text())
    assert rep["ship"] == "patrol_boat" and rep["n_surface_faces"] > 100
    assert f"{rep['n_surface_faces']} surface faces" in text
    for f in ("ship.ply", "ship_parts.json", "parts.png", "ship_parts/deck.stl"):
        assert (out / "mesh" / f).is_file(), f
    assert (out / "COMPLETE").is_file() and (out / "report.html").is_file()
    m = json.loads((out / "manifest.json").read_text())
    assert (m["tool"], m["kind"]) == ("shipthermal", "mesh")
    assert m["entries"] == sorted(p.name for p in out.iterdir())
    # the written ship reads back with the same triangle count
    from shipthermal.geometry import read_ship

    ship, _ = read_ship(out / "mesh" / "ship.ply", units="m",
                        part_map=out / "mesh" / "ship_parts.json")
    assert ship.n_faces == rep["n_surface_faces"]


class _FakeReport:
    table = pd.DataFrame([{"season": "summer", "time": "12:00", "ours_K": 305.0,
                           "reference_K": 304.67}])

    def text(self):
        return "FAKE VALIDATION TABLE"


def test_validate_plumbing(monkeypatch, tmp_path, capsys):
    """`validate` calls shipthermal.app.validation.validate(out_dir, progress, quick) and files
    its table in a run directory (the real validation runs in its own tests)."""
    import shipthermal.app.validation as V

    seen = {}

    def fake(out_dir=None, progress=True, quick=False):
        seen.update(out_dir=out_dir, progress=progress, quick=quick)
        return _FakeReport()

    monkeypatch.setattr(V, "validate", fake)
    out = tmp_path / "val"
    assert main(["-q", "validate", "--quick", "--out", str(out)]) == 0
    assert seen["quick"] is True and seen["progress"] is False
    assert "FAKE VALIDATION TABLE" in capsys.readouterr().out
    assert (out / "validation" / "validation_table.csv").is_file()
    assert "304.67" in (out / "report.html").read_text()
    m = json.loads((out / "manifest.json").read_text())
    assert (m["tool"], m["kind"]) == ("shipthermal", "validate")
    assert m["entries"] == sorted(p.name for p in out.iterdir())


def test_validate_missing_module_message(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "shipthermal.app.validation", None)
    assert main(["validate", "--out", "unused"]) == 1
    assert "validation is not available" in capsys.readouterr().err


def test_bare_call_prints_the_help_and_where_to_start(capsys):
    assert main([]) == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: shipthermal") and "demo" in out and "--version" in out
    assert "shipthermal demo --quick" in out


def test_version(capsys):
    from importlib.metadata import version

    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.strip() == f"shipthermal {version('shipthermal')}"


@pytest.mark.parametrize("argv, hint", [
    (["rnu", "summer"], "did you mean 'run'?"),
    (["reprot", "runs/x"], "did you mean 'report'?"),
    (["image", "runs/x", "--stpe-min", "5"], "did you mean '--step-min'?"),
    (["demo", "--quikc"], "did you mean '--quick'?"),
])
def test_a_typo_gets_the_nearest_command_or_option(argv, hint, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and hint in err


def test_nothing_near_gets_no_suggestion(capsys):
    with pytest.raises(SystemExit):
        main(["zzzzzz"])
    assert "did you mean" not in capsys.readouterr().err


def test_every_subcommand_shows_examples_that_parse(capsys):
    import shlex

    from shipthermal.app.cli import EXAMPLES, build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert set(EXAMPLES) == set(sub.choices)
    for name, examples in EXAMPLES.items():
        with pytest.raises(SystemExit):
            main([name, "--help"])
        out = capsys.readouterr().out
        assert "examples:" in out
        for e in examples:
            assert e in out
            words = shlex.split(e)
            assert words[0] == "shipthermal" and words[1] == name
            args = parser.parse_args(words[1:])          # exits 2 if it did not parse
            assert args.command == name
