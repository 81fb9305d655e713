"""No command ever changes a user's files: every command (`run`, `mesh`, `image`,
`background`, `sweep`, `ensemble`, `calibrate`, `report`, `validate`) pointed at a folder of
user files (a scenario, its weather CSV, notes, someone else's manifest.json and .lock, a
subfolder of data, measurements, a sweep file, a Landsat scene) with `--out` (plain,
`--force`, `--resume`, and `--out .` from inside it) stops with exit 2 and one line naming
the flag, and every file keeps its bytes and its modification time.

Exit 0 where writing beside the files is right: an output folder *inside* the folder of the
inputs (a new `runs/s` next to the scenario, `scene/bg` next to the Landsat files, an empty
folder given as `--out .`), `--resume` and `report` on a run folder that holds a user's
file (left alone), `--force` on a folder this tool wrote and that holds nothing else.

The refusals come before any slow work: the solve, the mesh, the fits, the validation, the
sweep and the background are replaced by functions that fail the test if they are called.
"""

import json
import os
import shutil
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_helpers import write_tiny

from shipthermal.app.cli import main
from shipthermal.app.rundir import RunDir, read_signature
from shipthermal.errors import InputError

REPO = Path(__file__).resolve().parents[2]
SCENE = REPO / "examples" / "real_port" / "data"
MTL = "LC08_L2SP_204023_20200927_20201006_02_T1_MTL.txt"
ROIS = "mersey_rois.geojson"

# ---------------------------------------------------------------------------------------
# the user's folder
# ---------------------------------------------------------------------------------------
MEASUREMENTS = ("case,time,target,temperature_K,sigma_K,split\n"
                "s.toml,10:00,deck,300.0,0.3,fit\ns.toml,13:00,deck,305.0,0.3,fit\n"
                "s.toml,16:00,deck,302.0,0.3,holdout\n")
SWEEP = ('name = "mine"\nbase = "s.toml"\nstages = ["thermal"]\n'
         '[axes]\n"ship.heading" = [0, 90]\n')


def _weather_csv(path):
    hours = np.arange(48)
    pd.DataFrame({
        "time": pd.date_range("2024-07-14 00:00", periods=48, freq="h")
                  .strftime("%Y-%m-%dT%H:%M:%S"),
        "temp_air": 24.0 + 4.0 * np.sin(2 * np.pi * (hours - 9) / 24),
        "relative_humidity": 80.0, "wind_speed": 3.0, "wind_direction": 180.0,
        "cloud_cover": 0.4, "temp_sea": 23.0}).to_csv(path, index=False)


def make_user_folder(root, scene=False) -> Path:
    """``root/proj``: the inputs of a study and the user's own files, nothing written by
    shipthermal (the ``manifest.json`` and ``.lock`` are someone else's)."""
    proj = root / "proj"
    sc = write_tiny(proj, name="s", extra='[weather]\nsource = "weather.csv"\n')
    sc.write_text(sc.read_text().replace("[time]\n", "[time]\ndate = 2024-07-15\n"))
    _weather_csv(proj / "weather.csv")
    (proj / "notes.txt").write_text("deck paint changed on 12 July\n")
    (proj / "bg.csv").write_text("x,y\n1,2\n")
    (proj / "manifest.json").write_text(json.dumps(
        {"name": "field campaign", "kind": "run", "status": "complete",
         "files": ["weather.csv", "notes.txt"]}, indent=1))
    (proj / ".lock").write_text("alice: editing the notes, do not touch\n")
    (proj / "m.csv").write_text(MEASUREMENTS)
    (proj / "sweep.toml").write_text(SWEEP)
    (proj / "data" / "raw").mkdir(parents=True)
    (proj / "data" / "values.csv").write_text("a,b\n1,2\n")
    (proj / "data" / "raw" / "readme.txt").write_text("raw logger files\n")
    # a folder someone else made with a manifest in the fields earlier versions wrote, but
    # not by this tool (the command is theirs), and a finished-looking marker
    theirs = proj / "theirs"
    theirs.mkdir()
    (theirs / "manifest.json").write_text(json.dumps(
        {"kind": "run", "status": "complete", "versions": {"shipthermal": "0.1"},
         "command": ["their-tool", "run"], "cases": {}}))
    (theirs / "COMPLETE").write_text("yes\n")
    (theirs / "results.csv").write_text("t,T\n0,300\n")
    # a folder that holds nothing but someone else's lock file
    (proj / "locked").mkdir()
    (proj / "locked" / ".lock").write_text("1 fileserver\n")
    if scene:
        shutil.copytree(SCENE, proj / "scene")
    return proj


def snapshot(root) -> dict:
    """Every path under ``root``: kind, bytes and modification time of the files."""
    out = {}
    for p in sorted(Path(root).rglob("*")):
        rel = str(p.relative_to(root))
        if p.is_symlink():
            out[rel] = ("link", os.readlink(p))
        elif p.is_dir():
            out[rel] = ("dir",)
        else:
            out[rel] = ("file", p.read_bytes(), p.stat().st_mtime_ns)
    return out


def _main(argv, cwd, monkeypatch, capsys):
    monkeypatch.chdir(cwd)
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    cap = capsys.readouterr()
    return code, cap.err


def _one_line_error(code, err, field, fragments=()):
    assert code == 2, err
    assert err.startswith("error: ") and err.count("\n") == 1, err
    assert f"error: {field} = " in err, err
    assert "Traceback" not in err and "internal error" not in err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"


@pytest.fixture
def no_slow_work(monkeypatch):
    """Fail the test if a command gets as far as its slow work."""
    import imaging.background.background as bgb
    import imaging.background.landsat as landsat

    import shipthermal.app.calibration.command as calibration
    import shipthermal.app.commands as commands
    import shipthermal.app.pipeline as pipeline
    import shipthermal.app.sweep as sweep
    import shipthermal.app.validation as validation
    import shipthermal.geometry as geometry

    def forbidden(*a, **k):
        raise AssertionError("slow work started before the output folder was checked")

    for mod, name in [(pipeline, "prepare"), (pipeline, "thermal_case"),
                      (pipeline, "build_background"), (geometry, "build_ship_mesh"),
                      (sweep, "run_sweep"), (commands, "prepare"), (commands, "thermal_case"),
                      (commands, "build_background"), (commands, "build_ship_mesh"),
                      (calibration, "calibrate"),
                      (calibration, "paper_calibration"), (validation, "validate"),
                      (landsat, "read_landsat_scene"), (bgb, "build_overpass")]:
        monkeypatch.setattr(mod, name, forbidden)


# ---------------------------------------------------------------------------------------
# refusals: (id, argv with {proj} for the folder's absolute path, working folder under
# proj, the flag the message names, fragments of the message)
# ---------------------------------------------------------------------------------------
INPUT = "holds an input of this command"
FOREIGN = "is a non-empty folder that is not a shipthermal run directory"
NOT_OURS = "its manifest.json was not written by shipthermal"
A_FILE = "must be a folder (a file of that name exists)"
NOT_A_RUN = "must be a shipthermal run directory"
NOT_BG = "is not an output folder of `shipthermal background`"
UNKNOWN = "ship.solar_absorptivity.deck=0.2:0.95"
BG = f"background --mtl scene/{MTL} --roi scene/{ROIS}"

REFUSALS = [
    # run: the scenario and weather file are inputs; user folders are not run folders
    ("run", "run s.toml --out {proj}", ".", "--out", [INPUT, "s.toml"]),
    ("run-force", "run s.toml --out {proj} --force", ".", "--out", [INPUT]),
    ("run-resume", "run s.toml --out {proj} --resume", ".", "--out", [INPUT]),
    ("run-dot", "run s.toml --out .", ".", "--out", [INPUT]),
    ("run-dot-force", "run s.toml --out . --force", ".", "--out", [INPUT]),
    ("run-weather-folder", "run ../s.toml --out . --force", "data", "--out", [FOREIGN]),
    ("run-data", "run s.toml --out data", ".", "--out", [FOREIGN, "raw, values.csv"]),
    ("run-data-force", "run s.toml --out data --force", ".", "--out", [FOREIGN]),
    ("run-data-resume", "run s.toml --out data --resume", ".", "--out", [FOREIGN]),
    ("run-theirs-force", "run s.toml --out theirs --force", ".", "--out", [NOT_OURS]),
    ("run-theirs-resume", "run s.toml --out theirs --resume", ".", "--out", [NOT_OURS]),
    ("run-lock-only", "run s.toml --out locked --force", ".", "--out", [FOREIGN, ".lock"]),
    ("run-file", "run s.toml --out notes.txt --force", ".", "--out", [A_FILE]),
    ("run-input-file", "run s.toml --out weather.csv --force", ".", "--out", [A_FILE]),
    ("run-resume-force", "run s.toml --out new --resume --force", ".", "--resume --force",
     ["contradict each other", "Give one of them"]),
    # mesh
    ("mesh", "mesh s.toml --out {proj}", ".", "--out", [INPUT]),
    ("mesh-dot-force", "mesh s.toml --out . --force", ".", "--out", [INPUT]),
    ("mesh-data-force", "mesh s.toml --out data --force", ".", "--out", [FOREIGN]),
    ("mesh-theirs-force", "mesh s.toml --out theirs --force", ".", "--out", [NOT_OURS]),
    ("mesh-file", "mesh s.toml --out notes.txt --force", ".", "--out", [A_FILE]),
    # image amends only a run folder this tool wrote
    ("image", "image {proj}", ".", "run directory", [NOT_A_RUN, "not written by shipthermal"]),
    ("image-theirs", "image theirs", ".", "run directory", [NOT_A_RUN]),
    ("image-dot", "image .", "data", "run directory", [NOT_A_RUN]),
    # background: the scene's files are inputs; --force replaces only its own output
    ("background-scene-force", BG + " --out scene --force", ".", "--out", [INPUT, MTL]),
    ("background-dot-force", f"background --mtl {MTL} --roi {ROIS} --out . --force", "scene",
     "--out", [INPUT]),
    ("background-proj-force", BG + " --out {proj} --force", ".", "--out", [INPUT]),
    ("background-file-force", BG + " --out bg.csv --force", ".", "--out", [A_FILE]),
    ("background-data", BG + " --out data", ".", "--out", ["exists and is not empty"]),
    ("background-data-force", BG + " --out data --force", ".", "--out", [NOT_BG]),
    ("background-theirs-force", BG + " --out theirs --force", ".", "--out", [NOT_BG]),
    # sweep (always continues a sweep folder: it must be one)
    ("sweep", "sweep sweep.toml --serial --out {proj}", ".", "--out", [INPUT]),
    ("sweep-dot-force", "sweep sweep.toml --serial --out . --force", ".", "--out", [INPUT]),
    ("sweep-data", "sweep sweep.toml --serial --out data", ".", "--out", [FOREIGN]),
    ("sweep-theirs", "sweep sweep.toml --serial --out theirs", ".", "--out", [NOT_OURS]),
    ("sweep-lock-only", "sweep sweep.toml --serial --out locked", ".", "--out", [FOREIGN]),
    # ensemble
    ("ensemble", "ensemble s.toml --members 2 --serial --out {proj}", ".", "--out", [INPUT]),
    ("ensemble-dot-force", "ensemble s.toml --members 2 --serial --out . --force", ".", "--out",
     [INPUT]),
    ("ensemble-data", "ensemble s.toml --members 2 --serial --out data", ".", "--out",
     [FOREIGN]),
    ("ensemble-theirs-force", "ensemble s.toml --members 2 --serial --out theirs --force", ".",
     "--out", [NOT_OURS]),
    ("ensemble-seed", "ensemble s.toml --members 2 --seed -1 --out new", ".", "--seed",
     ["must be an integer in [0, 4294967295]"]),
    # calibrate: the measurement CSV and the scenarios it names are inputs
    ("calibrate", f"calibrate m.csv --unknown {UNKNOWN} --out {{proj}}", ".", "--out",
     [INPUT, "m.csv"]),
    ("calibrate-dot-force", f"calibrate m.csv --unknown {UNKNOWN} --out . --force", ".",
     "--out", [INPUT]),
    ("calibrate-data-force", f"calibrate m.csv --unknown {UNKNOWN} --out data --force", ".",
     "--out", [FOREIGN]),
    ("calibrate-paper-theirs", "calibrate --paper --out theirs --force", ".", "--out",
     [NOT_OURS]),
    ("calibrate-paper-file", "calibrate --paper --out notes.txt --force", ".", "--out",
     [A_FILE]),
    ("calibrate-paper-dot", "calibrate --paper --out . --force", "data", "--out", [FOREIGN]),
    # report reads and amends only a run folder this tool wrote
    ("report", "report {proj}", ".", "run directory", [NOT_A_RUN]),
    ("report-theirs", "report theirs", ".", "run directory", [NOT_A_RUN]),
    ("report-output", "report theirs --output notes.txt", ".", "run directory", [NOT_A_RUN]),
    # validate
    ("validate", "validate --quick --out {proj}", ".", "--out", [NOT_OURS]),
    ("validate-force", "validate --quick --out {proj} --force", ".", "--out", [NOT_OURS]),
    ("validate-dot-force", "validate --quick --out . --force", ".", "--out", [NOT_OURS]),
    ("validate-data-force", "validate --quick --out data --force", ".", "--out", [FOREIGN]),
    ("validate-theirs-force", "validate --quick --out theirs --force", ".", "--out",
     [NOT_OURS]),
    ("validate-into", "validate --quick --into {proj}", ".", "run directory", [NOT_A_RUN]),
    ("validate-into-theirs", "validate --quick --into theirs", ".", "run directory",
     [NOT_A_RUN]),
]


def test_every_command_is_tried():
    tried = {c[1].split()[0] for c in REFUSALS}
    assert tried == {"run", "mesh", "image", "background", "sweep", "ensemble", "calibrate",
                     "report", "validate"}


@pytest.mark.parametrize("case, argv, cwd, field, fragments", REFUSALS,
                         ids=[c[0] for c in REFUSALS])
def test_user_folder_is_refused_and_unchanged(case, argv, cwd, field, fragments, tmp_path,
                                              monkeypatch, capsys, no_slow_work):
    proj = make_user_folder(tmp_path, scene=case.startswith("background"))
    before, around = snapshot(proj), sorted(os.listdir(tmp_path))
    code, err = _main(["-q"] + argv.format(proj=proj).split(), proj / cwd, monkeypatch,
                      capsys)
    _one_line_error(code, err, field, fragments)
    assert snapshot(proj) == before                   # bytes, mtimes, nothing added
    assert sorted(os.listdir(tmp_path)) == around     # no sibling left behind either


def test_refusal_from_a_real_process(tmp_path):
    """`shipthermal run s.toml --out .` in the user's folder, as a user types it."""
    proj = make_user_folder(tmp_path)
    before = snapshot(proj)
    exe = subprocess.run([sys.executable, "-m", "shipthermal", "run", "s.toml", "--out", "."],
                         cwd=proj, capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert exe.returncode == 2, exe.stderr
    assert exe.stderr.startswith("error: --out = '.': holds an input of this command")
    assert exe.stderr.count("\n") == 1 and "Traceback" not in exe.stderr
    assert snapshot(proj) == before


# ---------------------------------------------------------------------------------------
# what is allowed: a run folder inside the inputs' folder, and what --force, --resume and
# report do with a run folder this tool wrote
# ---------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """`shipthermal run s.toml --out runs/s` from inside the user's folder (a new folder next
    to the inputs is where a run belongs): (proj, run folder, snapshot before)."""
    proj = make_user_folder(tmp_path_factory.mktemp("finished"))
    before = snapshot(proj)
    cwd = os.getcwd()
    os.chdir(proj)
    try:
        assert main(["-q", "run", "s.toml", "--out", "runs/s"]) == 0
    finally:
        os.chdir(cwd)
    return proj, proj / "runs" / "s", before


def _without(snap, prefix):
    return {k: v for k, v in snap.items() if k != prefix and not k.startswith(prefix + "/")}


def test_run_beside_the_inputs_changes_none_of_them(finished):
    proj, run, before = finished
    assert _without(snapshot(proj), "runs") == before
    m = json.loads((run / "manifest.json").read_text())
    assert (m["tool"], m["kind"]) == ("shipthermal", "run")
    # every top-level entry of the run is listed as the tool's own, and nothing else is
    assert sorted(m["entries"]) == sorted(p.name for p in run.iterdir())
    assert (run / "COMPLETE").is_file() and not (run / ".lock").exists()
    assert (proj / ".lock").read_text().startswith("alice")


def _copy(run, tmp_path) -> Path:
    dst = tmp_path / "copy"
    shutil.copytree(run, dst)
    return dst


def test_force_never_deletes_a_file_it_did_not_write(finished, tmp_path, monkeypatch, capsys):
    proj, run, _ = finished
    copy = _copy(run, tmp_path)
    (copy / "notes.txt").write_text("my notes on this run\n")
    (copy / "thermal-mine").mkdir()
    before = snapshot(copy)
    code, err = _main(["-q", "run", str(proj / "s.toml"), "--out", str(copy), "--force"],
                      tmp_path, monkeypatch, capsys)
    _one_line_error(code, err, "--out", ["holds files that shipthermal did not write",
                                         "notes.txt", "thermal-mine", "Move them out"])
    assert snapshot(copy) == before
    # --resume of the finished run and report amend it and leave the user's files alone
    code, err = _main(["run", str(proj / "s.toml"), "--out", str(copy), "--resume"], tmp_path,
                      monkeypatch, capsys)
    assert code == 0 and "already complete" in err, err
    assert main(["-q", "report", str(copy)]) == 0
    after = snapshot(copy)
    for name in ("notes.txt", "thermal-mine"):
        assert after[name] == before[name]
    assert "notes.txt" not in json.loads((copy / "manifest.json").read_text())["entries"]


def test_force_replaces_a_run_folder_it_wrote(finished, tmp_path, monkeypatch, capsys):
    proj, run, _ = finished
    copy = _copy(run, tmp_path)
    (copy / ".report.html.tmp4242").write_text("debris of a crashed writer")
    before = snapshot(proj)
    code, err = _main(["-q", "run", "s.toml", "--out", str(copy), "--force"], proj,
                      monkeypatch, capsys)
    assert code == 0, err
    assert sorted(p.name for p in copy.iterdir()) == sorted(p.name for p in run.iterdir())
    assert _without(snapshot(proj), "runs") == _without(before, "runs")


def test_sweep_does_not_take_over_a_run(finished, tmp_path, monkeypatch, capsys, no_slow_work):
    proj, run, _ = finished
    copy = _copy(run, tmp_path)
    before = snapshot(copy)
    code, err = _main(["-q", "sweep", str(proj / "sweep.toml"), "--serial", "--out", str(copy)],
                      tmp_path, monkeypatch, capsys)
    _one_line_error(code, err, "--out", ["is a shipthermal run folder, not a sweep folder"])
    for argv in (["calibrate", "--paper", "--out", str(copy), "--force"],
                 ["mesh", str(proj / "s.toml"), "--out", str(copy), "--force"],
                 ["validate", "--quick", "--out", str(copy), "--force"]):
        code, err = _main(["-q"] + argv, tmp_path, monkeypatch, capsys)
        _one_line_error(code, err, "--out", ["is a shipthermal run folder, not a"])
    assert snapshot(copy) == before


def test_report_output_writes_over_nothing_but_a_report(finished, tmp_path, monkeypatch,
                                                        capsys):
    proj, run, _ = finished
    copy = _copy(run, tmp_path)
    mine = tmp_path / "mine.html"
    mine.write_text("<!DOCTYPE html><html><title>my page</title></html>")
    before = snapshot(tmp_path)
    for target in (proj / "notes.txt", mine, copy / "manifest.json", proj / "data"):
        code, err = _main(["-q", "report", str(copy), "--output", str(target)], tmp_path,
                          monkeypatch, capsys)
        _one_line_error(code, err, "--output", [str(target)])
    assert snapshot(tmp_path) == before
    # a new file, then a report it wrote, may be written
    for _ in range(2):
        code, err = _main(["-q", "report", str(copy), "--output", str(tmp_path / "old.html")],
                          tmp_path, monkeypatch, capsys)
        assert code == 0, err


def test_run_folder_of_an_earlier_version(finished, tmp_path, monkeypatch, capsys):
    """A manifest without the signature, as earlier versions wrote it, is still a run folder
    for `report` (and becomes signed); only its products are the tool's: a user's file in it
    stops --force."""
    proj, run, _ = finished
    copy = _copy(run, tmp_path)
    m = json.loads((copy / "manifest.json").read_text())
    for key in ("tool", "entries"):
        del m[key]
    (copy / "manifest.json").write_text(json.dumps(m))
    (copy / "notes.txt").write_text("mine\n")
    sig = read_signature(copy)
    assert sig.legacy and "notes.txt" not in sig.entries and "thermal" in sig.entries
    assert main(["-q", "report", str(copy)]) == 0
    m = json.loads((copy / "manifest.json").read_text())
    assert m["tool"] == "shipthermal" and "notes.txt" not in m["entries"]
    before = snapshot(copy)
    code, err = _main(["-q", "run", "s.toml", "--out", str(copy), "--force"], proj, monkeypatch,
                      capsys)
    _one_line_error(code, err, "--out", ["notes.txt"])
    assert snapshot(copy) == before


# ---------------------------------------------------------------------------------------
# background: beside its inputs, --force of its own output, a failure keeps what was there
# ---------------------------------------------------------------------------------------
def test_background_output_beside_the_scene(tmp_path, monkeypatch, capsys):
    proj = make_user_folder(tmp_path, scene=True)
    before = snapshot(proj)
    argv = ["-q"] + BG.split() + ["--out", "scene/bg"]
    code, err = _main(argv, proj, monkeypatch, capsys)
    assert code == 0, err
    bg = proj / "scene" / "bg"
    assert _without(snapshot(proj), "scene/bg") == before
    sig = read_signature(bg)
    assert sig.kind == "background" and sig.entries == {p.name for p in bg.iterdir()}
    assert not [p for p in (proj / "scene").iterdir() if ".part-" in p.name]
    first = snapshot(bg)
    # --force replaces its own output
    code, err = _main(argv + ["--force"], proj, monkeypatch, capsys)
    assert code == 0, err
    assert set(snapshot(bg)) == set(first)
    # ... but not when a user's file is in it
    (bg / "my_lst_notes.txt").write_text("checked against the buoy\n")
    kept = snapshot(proj)
    code, err = _main(argv + ["--force"], proj, monkeypatch, capsys)
    _one_line_error(code, err, "--out", ["my_lst_notes.txt"])
    assert snapshot(proj) == kept
    (bg / "my_lst_notes.txt").unlink()
    # a failure while building leaves the earlier output as it was
    import imaging.background.background as bgb

    def fails(*a, **k):
        raise InputError("roi_path", "x", "must hold polygons")

    monkeypatch.setattr(bgb, "build_overpass", fails)
    kept = snapshot(proj)
    code, err = _main(argv + ["--force"], proj, monkeypatch, capsys)
    _one_line_error(code, err, "--roi")   # the flag the user typed
    assert snapshot(proj) == kept
    assert not [p for p in (proj / "scene").iterdir() if ".part-" in p.name]


def test_background_into_an_empty_folder_given_as_dot(tmp_path, monkeypatch, capsys):
    """`cd empty && shipthermal background ... --out .`: the products go into the folder
    (the folder itself stays: the shell's working folder is not swapped away)."""
    empty = tmp_path / "empty"
    empty.mkdir()
    inode = empty.stat().st_ino
    code, err = _main(["-q", "background", "--mtl", str(SCENE / MTL), "--roi",
                       str(SCENE / ROIS), "--out", "."], empty, monkeypatch, capsys)
    assert code == 0, err
    assert empty.stat().st_ino == inode and (empty / "class_map.tif").is_file()
    assert read_signature(empty).kind == "background"
    assert sorted(os.listdir(tmp_path)) == ["empty"]


# ---------------------------------------------------------------------------------------
# RunDir on its own
# ---------------------------------------------------------------------------------------
def test_discard_leaves_a_file_the_user_put_in_meanwhile(tmp_path):
    r = tmp_path / "r"
    with pytest.raises(InputError):
        with RunDir(r, command=["test"]) as run:
            with run.stage("thermal/a") as d:
                (d / "x.csv").write_text("1")
            (r / "notes.txt").write_text("mine")        # the user, during the run
            raise InputError("weather.source", "w.csv", "must have a temp_air column")
    assert sorted(os.listdir(r)) == ["notes.txt"]


def test_claim_never_writes_over_a_users_file(tmp_path):
    r = tmp_path / "r"
    with RunDir(r, command=["test"]):
        pass
    (r / "report.html").write_text("my report")
    with RunDir(r, command=["test"], resume=True) as run:
        with pytest.raises(InputError, match="holds report.html, which shipthermal did not"):
            run.claim("report.html")
        with pytest.raises(InputError, match="holds report.html"):
            with run.stage("report.html"):
                pass
    assert (r / "report.html").read_text() == "my report"


def test_a_lock_of_ours_alone_is_our_debris_a_strangers_is_not(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    ours = tmp_path / "ours"
    ours.mkdir()
    (ours / ".lock").write_text(f"{dead} {socket.gethostname()} shipthermal")
    notes = []
    with RunDir(ours, command=["test"], log=notes.append):
        pass
    assert "took over the stale lock" in notes[0]
    for text in (f"{dead} {socket.gethostname()}", "", "locked by alice"):
        other = tmp_path / "other"
        other.mkdir(exist_ok=True)
        (other / ".lock").write_text(text)
        with pytest.raises(InputError, match="not a shipthermal run directory"):
            RunDir(other, command=["test"], force=True)
        assert (other / ".lock").read_text() == text


def test_a_signed_manifest_with_a_strange_entry_is_not_ours(tmp_path):
    for entries in (["../x"], ["a/b"], "thermal", [".lock"], [3]):
        r = tmp_path / "r"
        r.mkdir(exist_ok=True)
        (r / "manifest.json").write_text(json.dumps({"tool": "shipthermal", "kind": "run",
                                                     "entries": entries}))
        assert read_signature(r) is None
