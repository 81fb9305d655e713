"""Catalogue of bad inputs through the command line (tests/scenario holds 69 more for the
scenario keys themselves): user meshes, weather files, background rasters, sweep files and
command-line misuse. Each case asserts

* exit code 2 (user error) and the message fragments (the key or file, what is allowed,
  and where given the fix), with no traceback;
* that nothing was left behind: the folder holds exactly the inputs it held before.
"""

import json
from pathlib import Path
import shutil

import numpy as np
import pytest
import rasterio
import trimesh
import xarray as xr
from cli_helpers import write_tiny

from shipthermal.app.cli import main


def _tree(root):
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


def _run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:                 # argparse's own usage errors
        code = exc.code
    return code, capsys.readouterr().err


# ---------------------------------------------------------------------------------------
# inputs the cases point at
# ---------------------------------------------------------------------------------------
def _box(path, scale=1.0, drop=0, flip=False, swap=False):
    """A 100 m x 12 m x 10 m box barge (keel at z = -4): hull faces first, deck last."""
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    v = np.array(m.vertices) + [0.0, 0.0, 1.0]
    f = np.array(m.faces)
    top = m.face_normals[:, 2] > 0.5
    f = np.vstack([f[~top], f[top]])
    if drop:
        f = f[:-drop]
    if flip:
        f = f[:, ::-1]
    if swap:
        v = v[:, [1, 0, 2]]
    trimesh.Trimesh(v * scale, f, process=False).export(path)


def _ship_toml(d, name, mesh="box.stl", part_map="parts.json", units='"m"', draught=4.0):
    lines = ["[ship.files]", f'mesh = "{mesh}"']
    if units:
        lines.append(f"units = {units}")
    if part_map:
        lines.append(f'part_map = "{part_map}"')
    lines.append(f"draught = {draught}")
    (d / f"{name}.toml").write_text("\n".join(lines) + "\n")
    return d / f"{name}.toml"


def _mesh_inputs(d):
    _box(d / "box.stl")
    _box(d / "open.stl", drop=1)
    _box(d / "flip.stl", flip=True)
    _box(d / "mm.stl", scale=1000.0)
    _box(d / "swap.stl", swap=True)
    (d / "garbage.stl").write_text("this is not a mesh\n")
    (d / "notes.txt").write_text("")
    for name, parts in {"parts": {"hull": [[0, 10]], "deck": [[10, 12]]},
                        "parts11": {"hull": [[0, 10]], "deck": [[10, 11]]},
                        "overlap": {"hull": [[0, 11]], "deck": [[10, 12]]},
                        "short": {"hull": [[0, 9]], "deck": [[10, 12]]},
                        "funnel": {"hull": [[0, 10]], "funnel": [[10, 12]]}}.items():
        (d / f"{name}.json").write_text(json.dumps({"parts": parts}))


HEADER = "time,temp_air,relative_humidity,wind_speed,wind_direction,cloud_cover,temp_sea"


def _weather_csv(d, name, header=HEADER, edit=None, hours=24, offset="+08:00"):
    rows = []
    for h in range(hours):
        rows.append(f"2023-07-15T{h:02d}:00:00{offset},{24 + 4 * np.sin(h / 4):.2f},75,4.0,"
                    f"180,0.3,23.5")
    if edit:
        rows = edit(rows)
    (d / name).write_text(header + "\n" + "\n".join(rows) + "\n")
    return name


def _weather_inputs(d):
    _weather_csv(d, "no_wind.csv", HEADER.replace(",wind_speed", ""),
                 lambda r: [",".join(x.split(",")[:3] + x.split(",")[4:]) for x in r])
    _weather_csv(d, "rh.csv", edit=lambda r: [r[0].replace(",75,", ",175,")] + r[1:])
    # ---- station weather: every row's temp_air empty (a column that is all missing)
    _weather_csv(d, "nan.csv", edit=lambda r: [x.split(",")[0] + ",," + ",".join(
        x.split(",")[2:]) for x in r])
    _weather_csv(d, "text.csv", edit=lambda r: [r[0].replace(",75,", ",humid,")] + r[1:])
    _weather_csv(d, "order.csv", edit=lambda r: [r[0], r[0]] + r[1:])
    _weather_csv(d, "gap.csv", edit=lambda r: r[:6] + r[15:])
    ndbc = "/".join(__file__.split("/")[:-2]) + "/data/weather/44009h2013_mar03-09.txt"
    shutil.copy(ndbc, d / "buoy.txt")
    _weather_csv(d, "short.csv", hours=12)
    _weather_csv(d, "clouds.csv", HEADER.replace("cloud_cover", "clouds"))
    _weather_csv(d, "kelvin.csv", edit=lambda r: [x.replace(",75,", ",75,").replace(
        x.split(",")[1], f"{float(x.split(',')[1]) + 273.15:.2f}", 1) for x in r])
    (d / "w.epw").write_text("")
    for name, src, extra in [("w_nowind", "no_wind.csv", ""), ("w_rh", "rh.csv", ""),
                             ("w_nan", "nan.csv", ""), ("w_text", "text.csv", ""),
                             ("w_order", "order.csv", ""), ("w_short", "short.csv", ""),
                             ("w_clouds", "clouds.csv", ""), ("w_kelvin", "kelvin.csv", ""),
                             ("w_epw", "w.epw", ""), ("w_gap", "gap.csv", ""),
                             ("w_buoy", "buoy.txt", "wind_height = 5.0"),
                             ("w_ends", "short.csv", 'day = "record"')]:
        write_tiny(d, name=name, extra="")
        t = (d / f"{name}.toml").read_text()
        if name == "w_buoy":
            t = t.replace("[time]\n", "[time]\ndate = 2013-03-04\n")
        (d / f"{name}.toml").write_text(t.replace("[ship]", f'[weather]\nsource = "{src}"\n'
                                                  f"{extra}\n[ship]"))


# ---------------------------------------------------------------------------------------
# the catalogue: (id, kind of inputs, argv with {d} for the folder, fragments)
# ---------------------------------------------------------------------------------------
def M(name, **kw):
    return lambda d: ["-q", "mesh", str(_ship_toml(d, name, **kw)), "--out", str(d / "out")]


def W(name):
    return lambda d: ["-q", "run", str(d / f"{name}.toml"), "--out", str(d / "out")]


CASES = [
    # ---- user meshes (ship.files) ---------------------------------------------------------
    ("mesh-open", "mesh", M("a", mesh="open.stl", part_map="parts11.json"),
     ["3 open edges", "must be closed (watertight)", 'ship.files.repair = "tetwild"']),
    ("mesh-inverted", "mesh", M("a", mesh="flip.stl"),
     ["signed volume", "the normals point into the ship", "fix_normals"]),
    ("mesh-millimetres", "mesh", M("a", mesh="mm.stl"),
     ["ship length of 100000 m", "outside the plausible 5–500 m", "ship.files.units = \"mm\""]),
    ("mesh-axes", "mesh", M("a", mesh="swap.stl"),
     ["extent x 12 m, y 100 m", "longest dimension must lie along x"]),
    ("mesh-partmap-overlap", "mesh", M("a", part_map="overlap.json"),
     ["part_map['deck'] = [10, 12]", "overlaps part 'hull' at face 10"]),
    ("mesh-partmap-uncovered", "mesh", M("a", part_map="short.json"),
     ["1 faces without a part", "first uncovered: face 9"]),
    ("mesh-not-stl", "mesh", M("a", mesh="garbage.stl"),
     ["garbage.stl", "is not an STL file", "does not start with 'solid'"]),
    ("mesh-draught-too-deep", "mesh", M("a", draught=40.0),
     ["draught = 40.0", "between 0 and the height of the mesh (10.000 m)"]),
    ("mesh-partmap-missing", "mesh", M("a", part_map=None),
     ["ship.files.part_map = None", "is required with a .stl mesh"]),
    ("mesh-units-missing", "mesh", M("a", units=None),
     ["ship.files.units = None", "'m' or 'mm'"]),
    ("mesh-bad-extension", "mesh", M("a", mesh="notes.txt"),
     ["ship.files.mesh", "must be a file ending in one of .glb"]),
    ("mesh-file-missing", "mesh", M("a", mesh="nowhere.stl"),
     ["ship.files.mesh", "must be an existing file"]),
    ("mesh-unknown-part", "mesh", M("a", part_map="funnel.json"),
     ["funnel"]),
    ("mesh-edge-negative", "mesh",
     lambda d: ["mesh", "summer", "--edge-length", "-1", "--out", str(d / "out")],
     ["ship.edge_length = -1.0", "must lie in"]),
    # ---- weather files (read when the run starts: before any folder is made) --------------
    ("weather-missing-column", "weather", W("w_nowind"),
     ["has no column for wind_speed", "Add a 'wind_speed' column (docs/WEATHER.md)"]),
    ("weather-humidity-range", "weather", W("w_rh"),
     ["relative_humidity", "must lie in [0, 100]"]),
    ("weather-column-all-missing", "weather", W("w_nan"),
     ["weather.source[temp_air]", "has no valid value of temp_air between 2023-07-15 00:00"]),
    ("weather-not-a-number", "weather", W("w_text"), ["relative_humidity", "humid"]),
    ("weather-duplicate-time", "weather", W("w_order"),
     ["2 rows sharing a time (first 2023-07-15 00:00 +08)", "Remove the repeated rows"]),
    ("weather-date-not-covered", "weather", W("w_short"),
     ["covers 2023-07-15 00:00 … 2023-07-15 11:00 +08", "not the span needed", "time.date"]),
    ("weather-record-ends-before-date", "weather", W("w_ends"),
     ["covers 2023-07-15 00:00 … 2023-07-15 11:00 +08", "not the span needed "
      "2023-07-15 00:00 … 2023-07-16 00:00 +08"]),
    ("weather-long-gap", "weather", W("w_gap"),
     ["6 problems", "has no valid temp_air from 2023-07-15 05:00 to 2023-07-15 15:00 +08 "
      "(10 h), longer than weather.max_gap_hours = 6 h", "raise weather.max_gap_hours"]),
    ("weather-ndbc-no-cloud", "weather", W("w_buoy"),
     ["has no column for cloud_cover", "Set weather.cloud_cover (a constant, fraction 0-1)"]),
    ("weather-unknown-column", "weather", W("w_clouds"), ["unknown column"]),
    ("weather-kelvin-as-celsius", "weather", W("w_kelvin"), ["temperature unit"]),
    ("weather-epw-needs-sea", "weather", W("w_epw"), ["weather.temp_sea", "required"]),
    # ---- background rasters (read before the thermal stage with --image) ------------------
    ("raster-mtl-json", "raster", None, ["background.mtl = ", "must be valid JSON"]),
    ("raster-mtl-time", "raster", None, ["SCENE_CENTER_TIME", "HH:MM:SS"]),
    ("raster-dem-not-geotiff", "raster", None,
     ["background.dem", "must be a readable raster", "not recognized"]),
    ("raster-dem-voids", "raster", None,
     ["land pixels without elevation", "dem_nodata='mask'"]),
    ("raster-met-variable", "raster", None,
     ["met[temperature] = 'missing'", "Variables present"]),
    ("raster-met-not-netcdf", "raster", None, ["background.met = ",
                                              "must be a readable NetCDF file"]),
    ("raster-roi-grid", "raster", None, ["background.roi = ", "must be on the scene grid",
                                        "Rasterise"]),
    ("raster-files-incomplete", "raster", None,
     ["background.roi = None", "is required with source = 'files'"]),
    # ---- sweep files ----------------------------------------------------------------------
    ("sweep-missing", "sweep", "", ["sweep = ", "must be an existing TOML file"]),
    ("sweep-not-toml", "sweep", "axes = [", ["must be valid TOML"]),
    ("sweep-unknown-key", "sweep", 'axis = {"ship.heading" = [0]}',
     ["sweep.axis", "unknown key", "axes"]),
    ("sweep-no-axes", "sweep", 'base = "summer"', ["sweep.axes", "must be a non-empty table"]),
    ("sweep-axis-not-list", "sweep", '[axes]\n"ship.heading" = 90',
     ["sweep.axes.ship.heading = 90", "must be a non-empty list"]),
    ("sweep-axis-empty", "sweep", '[axes]\n"ship.heading" = []', ["must be a non-empty list"]),
    ("sweep-stage", "sweep", 'stages = ["imaging"]\n[axes]\n"ship.heading" = [0]',
     ["sweep.stages", "['thermal', 'imaging']"]),
    ("sweep-base-missing", "sweep", 'base = "nowhere.toml"\n[axes]\n"ship.heading" = [0]',
     ["sweep.base", "must be 'summer', 'winter' or an existing scenario file"]),
    ("sweep-case-out-of-range", "sweep", '[axes]\n"ship.heading" = [90, 400]',
     ["case 1 (ship.heading=400): ship.heading = 400", "must lie in [0, 360) deg"]),
    ("sweep-unknown-scenario-key", "sweep", '[axes]\n"ship.headng" = [90]',
     ["ship.headng", "unknown key", "Did you mean 'heading'?"]),
    ("sweep-mixed-axis", "sweep", '[axes]\nx = [1, {"ship.heading" = 2}]',
     ["sweep.axes.x", "not both"]),
    ("sweep-name", "sweep", 'name = "a/b"\n[axes]\n"ship.heading" = [0]',
     ["sweep.name", "without slashes"]),
    ("sweep-imaging-custom-band", "sweep", '[axes]\n"imaging.bands" = [["8-14"], ["8-12"]]',
     ["case 1 (imaging.bands=8-12): imaging.bands", "'3-5', '8-14' and the sensor presets'"]),
    ("sweep-set-not-table", "sweep", 'set = 3\n[axes]\n"ship.heading" = [0]',
     ["sweep.set = 3", "must be a table"]),
    # ---- command-line misuse --------------------------------------------------------------
    ("cli-scenario-missing", "cli", lambda d: ["run", str(d / "nope.toml")],
     ["must be an existing TOML file"]),
    ("cli-scenario-syntax", "cli", lambda d: ["run", str(d / "broken.toml")],
     ["must be valid TOML"]),
    ("cli-image-not-a-run", "cli", lambda d: ["image", str(d)],
     ["must be a shipthermal run directory (with manifest.json)"]),
    ("cli-image-unfinished", "cli", lambda d: ["image", str(d / "unfinished")],
     ["is not finished (no COMPLETE marker)", "--resume"]),
    ("cli-crossover-no-imaging", "cli", lambda d: ["crossover", str(d / "finished")],
     ["has no imaging results", "shipthermal image"]),
    ("cli-report-not-a-run", "cli", lambda d: ["report", str(d)],
     ["must be a shipthermal run directory"]),
    ("cli-out-is-a-file", "cli", lambda d: ["run", "summer", "--out", str(d / "file.txt")],
     ["--out", "must be a folder"]),
    ("cli-out-foreign-folder", "cli", lambda d: ["run", "summer", "--out", str(d / "mine")],
     ["not a shipthermal run directory", "Choose a new or empty folder"]),
    ("cli-out-finished", "cli", lambda d: ["mesh", "summer", "--out", str(d / "finished")],
     ["is a finished run (COMPLETE exists)", "--force"]),
    ("cli-image-step", "cli", lambda d: ["image", str(d / "finished"), "--step-min", "0.5"],
     ["--step-min = 0.5", "must lie in [1, 180] min"]),
    ("cli-image-custom-band", "cli",
     lambda d: ["run", str(d / "custom.toml"), "--image", "--out", str(d / "out")],
     ["imaging.bands = ['8-12']", "the imaging stage takes the named bands",
      "'3-5', '8-14' and the sensor presets' bands"]),
    ("cli-workers-zero", "cli", lambda d: ["sweep", "x.toml", "--workers", "0"],
     ["--workers must be >= 1"]),
    ("cli-unknown-season", "cli", lambda d: ["demo", "--seasons", "autumn"],
     ["invalid choice: 'autumn'"]),
    ("cli-unknown-command", "cli", lambda d: ["simulate"], ["invalid choice: 'simulate'"]),
]


@pytest.fixture(scope="module")
def port(tmp_path_factory):
    from imaging.background.synthetic import write_synthetic_port

    return write_synthetic_port(tmp_path_factory.mktemp("port"), "summer", seed=5, size_px=90)


def _raster_case(d, case, port):
    """A copy of the synthetic port's files with one of them spoiled; the argv."""
    from imaging.background.landsat import north_up_transform

    src = d / "port"
    shutil.copytree(port.directory, src)
    files = {k: src / (getattr(port, k).rsplit("/", 1)[1]) for k in ("mtl_txt", "dem", "met",
                                                                    "roi")}
    mtl, dem, met, roi = files["mtl_txt"], files["dem"], files["met"], files["roi"]
    if case == "raster-mtl-json":
        mtl = src / "bad_MTL.json"
        mtl.write_text((src / port.mtl_json.rsplit("/", 1)[1]).read_text()[:-10])
    elif case == "raster-mtl-time":
        mtl = src / "T_MTL.txt"
        mtl.write_text(files["mtl_txt"].read_text().replace("SCENE_CENTER_TIME = ",
                                                            "SCENE_CENTER_TIME = 25:"))
    elif case == "raster-dem-not-geotiff":
        dem = d / "dem.tif"
        dem.write_text("not a tiff")
    elif case == "raster-dem-voids":
        with rasterio.open(files["dem"]) as s:
            profile, data = s.profile, s.read(1).astype("float32")
        profile.update(dtype="float32", nodata=None)
        dem = d / "dem_nan.tif"
        with rasterio.open(dem, "w", **profile) as out:
            out.write(np.full_like(data, np.nan), 1)
    elif case == "raster-met-variable":
        met = d / "met.nc"
        xr.open_dataset(files["met"]).load().rename({"temperature": "tair"}).to_netcdf(
            met, engine="h5netcdf")
    elif case == "raster-met-not-netcdf":
        met = d / "met.nc"
        met.write_text("nope")
    elif case == "raster-roi-grid":
        with rasterio.open(files["roi"]) as s:
            profile, data = s.profile, s.read(1)
        t = profile["transform"]
        profile.update(transform=north_up_transform(t.c + 30.0, t.f, 30.0))
        roi = d / "roi.tif"
        with rasterio.open(roi, "w", **profile) as out:
            out.write(data, 1)
    sc = write_tiny(d, name="r")
    bg = (f'[background]\nsource = "files"\nmtl = "{mtl}"\ndem = "{dem}"\nmet = "{met}"\n'
          + ("" if case == "raster-files-incomplete" else f'roi = "{roi}"\n'))
    sc.write_text(sc.read_text().replace("[background]\nsize_px = 100\n", "") + bg)
    return ["-q", "run", str(sc), "--image", "--out", str(d / "out")]


def _cli_inputs(d):
    (d / "broken.toml").write_text("[ship\nheading = 3\n")
    write_tiny(d, name="custom", extra='[imaging]\nbands = ["8-12"]\n')
    (d / "file.txt").write_text("a file")
    (d / "mine").mkdir()
    (d / "mine" / "thesis.tex").write_text("precious")
    for name, kind, done in (("unfinished", "run", False), ("finished", "mesh", True)):
        r = d / name
        r.mkdir()
        entries = ["manifest.json", "scenario.toml"] + (["COMPLETE"] if done else [])
        (r / "manifest.json").write_text(json.dumps({"tool": "shipthermal", "kind": kind,
                                                     "entries": entries, "cases": {},
                                                     "status": "running"}))
        (r / "scenario.toml").write_text("")
        if done:
            (r / "COMPLETE").write_text("x")


# ---- CAD meshes: named parts, every problem in one message, repair limit ---------------
def _cad_toml(d, name, mesh, **keys):
    lines = ["[ship.files]", f'mesh = "{mesh}"', 'units = "m"', "draught = 4.0"]
    lines += [f"{k} = {v}" for k, v in keys.items()]
    (d / f"{name}.toml").write_text("\n".join(lines) + "\n")
    return d / f"{name}.toml"


def _cad_box_parts(d):
    """The box barge as an OBJ with groups that name no ship part."""
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    m.apply_translation([0.0, 0.0, 1.0])
    top = m.face_normals[:, 2] > 0.5
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in m.vertices]
    for group, sel in (("Hull_Shell", ~top), ("Bridge Deck", top)):
        lines.append(f"g {group}")
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in m.faces[sel]]
    (d / "groups.obj").write_text("\n".join(lines) + "\n")


def _cad_lines_glb(d):
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.load_path(np.array([[0.0, 0, 0], [100.0, 0, 0]])), geom_name="deck")
    scene.export(d / "lines.glb")


def _cad_messy(d):
    """Millimetres, inverted, one triangle twice: three problems."""
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    f = np.vstack([m.faces[:, ::-1], m.faces[:1, ::-1]])
    trimesh.Trimesh((m.vertices + [0, 0, 1.0]) * 1000.0, f, process=False).export(d / "messy.stl")


def _cad_overlap(d):
    """A hull box and a deckhouse box sunk 2 m into it, exported as two pieces. By hand:
    areas 4640 + 768 = 5408 m2 before, 4640 - 160 + 336 + 160 = 4976 m2 united (-7.99 %);
    volumes 12000 + 1280 = 13280 m3 before, 13280 - 320 = 12960 m3 united (-2.41 %)."""
    hull = trimesh.creation.box((100.0, 12.0, 10.0))
    hull.apply_translation([0.0, 0.0, 1.0])
    house = trimesh.creation.box((20.0, 8.0, 8.0))
    house.apply_translation([-20.0, 0.0, 8.0])
    trimesh.util.concatenate([hull, house]).export(d / "overlap.stl")


def C(name, prepare, mesh, **keys):
    def make(d):
        prepare(d)
        return ["-q", "mesh", str(_cad_toml(d, name, mesh, **keys)), "--out", str(d / "out")]
    return make


CASES += [
    ("cad-obj-unknown-groups", "mesh", C("g", _cad_box_parts, "groups.obj"),
     ["groups.obj", "'Bridge Deck', 'Hull_Shell'", "which are no ship parts",
      'ship.files.part_map', '"auto"']),
    ("cad-glb-no-triangles", "mesh", C("l", _cad_lines_glb, "lines.glb"),
     ["lines.glb", "holds no triangles"]),
    ("cad-all-problems-at-once", "mesh", C("m", _cad_messy, "messy.stl", part_map='"auto"'),
     ["has 3 problems", 'ship.files.units = \"mm\"', "ship.files.check_scale = false",
      "1 duplicate triangles", "ship.files.clean = true", "normals point into the ship",
      "ship.files.fix_normals = true"]),
    ("cad-overlap-needs-repair", "mesh", C("o", _cad_overlap, "overlap.stl", part_map='"auto"'),
     ["2 separate pieces that overlap", 'ship.files.repair = \"union\"']),
    ("cad-repair-change-refused", "mesh",
     C("r", _cad_overlap, "overlap.stl", part_map='"auto"', repair='"union"'),
     ["ship.files.max_repair_change = 0.01", "the union repair changed the area by -7.99 % "
      "and the volume by -2.41 %", "set ship.files.max_repair_change = 0.08 or more"]),
]


@pytest.mark.parametrize("case, kind, make, fragments", CASES, ids=[c[0] for c in CASES])
def test_bad_input(case, kind, make, fragments, tmp_path, capsys, request):
    d = tmp_path
    if kind == "mesh":
        _mesh_inputs(d)
        argv = make(d)
    elif kind == "weather":
        _weather_inputs(d)
        argv = make(d)
    elif kind == "raster":
        argv = _raster_case(d, case, request.getfixturevalue("port"))
    elif kind == "sweep":
        write_tiny(d)
        if make:
            (d / "s.toml").write_text(make + "\n")
        argv = ["-q", "sweep", str(d / "s.toml"), "--out", str(d / "out")]
    else:
        _cli_inputs(d)
        argv = make(d)
    before = _tree(d)
    code, err = _run(argv, capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err
    assert _tree(d) == before        # nothing written, nothing removed


# =======================================================================================
# `shipthermal background` on real Landsat files (committed crops): one message, exit 2,
# nothing left behind
# =======================================================================================
_REPO = __import__("pathlib").Path(__file__).resolve().parents[2]
_MERSEY = _REPO / "examples/real_port/data"
_MERSEY_MTL = "LC08_L2SP_204023_20200927_20201006_02_T1_MTL.txt"
_PRE = _REPO / "tests/data/landsat8_pre_collection"


def _bg_case(d, case, port):
    import re

    scene = d / "scene"
    shutil.copytree(_MERSEY, scene)
    mtl, roi = scene / _MERSEY_MTL, scene / "mersey_rois.geojson"
    extra = []
    if case == "bg-truncated-tiff":
        b5 = scene / _MERSEY_MTL.replace("_MTL.txt", "_SR_B5.TIF")
        b5.write_bytes(b5.read_bytes()[:50_000])
    elif case == "bg-mtl-missing-key":
        mtl.write_text("\n".join(ln for ln in mtl.read_text().splitlines()
                                 if "TEMPERATURE_ADD_BAND_ST_B10" not in ln))
    elif case == "bg-rois-outside":
        roi.write_text(re.sub(r"\[\s*(-?\d+\.\d+),", lambda m: f"[{float(m.group(1)) + 20:.6f},",
                              roi.read_text()))
    elif case in ("bg-met-misses-scene", "bg-met-misses-overpass"):
        met = port.met
        if case == "bg-met-misses-scene":    # the synthetic port's grid (38.9 N 121.7 E) on the overpass day
            ds = xr.open_dataset(port.met).load()
            t = ds["time"].values
            ds = ds.assign_coords(time=t - t[0] + np.datetime64("2020-09-27T00:00:00"))
            met = d / "met_day.nc"
            ds.to_netcdf(met, engine="h5netcdf")
        extra = ["--dem", str(_REPO / "tests/data/dem_srtm/N49W124_crop.tif"), "--met", str(met)]
    elif case == "bg-dem-without-met":
        extra = ["--dem", str(_REPO / "tests/data/dem_srtm/N49W124_crop.tif")]
    elif case == "bg-band-files":
        shutil.copytree(_PRE, d / "pre")
        mtl, extra = d / "pre" / "l8_MTL.txt", ["--band-files", "x_{band}.tif"]
    elif case == "bg-level1-no-water-vapour":
        shutil.copytree(_PRE, d / "pre")
        mtl = d / "pre" / "l8_MTL.txt"
    elif case == "bg-out-not-empty":
        (d / "out").mkdir()
        (d / "out" / "keep.txt").write_text("mine")
    argv = ["-q", "background", "--mtl", str(mtl), "--out", str(d / "out"), *extra]
    return argv if case == "bg-no-roi" else argv + ["--roi", str(roi)]


BACKGROUND_CASES = [
    ("bg-truncated-tiff", ["FILE_NAME_BAND_5", "must be a readable GeoTIFF"]),
    ("bg-mtl-missing-key", ["TEMPERATURE_ADD_BAND_ST_B10", "Level-2 MTL must contain"]),
    ("bg-rois-outside", ["--roi = ", "polygons lie outside the scene"]),
    ("bg-met-misses-scene", ["met.extent", "misses the scene entirely", "around the port"]),
    ("bg-met-misses-overpass", ["met.time", "must contain the Landsat overpass",
                                "Use met data of the overpass day"]),
    ("bg-dem-without-met", ["--dem/--met", "go together"]),
    ("bg-band-files", ["FILE_NAME_BAND_2", "must be an existing GeoTIFF file"]),
    ("bg-level1-no-water-vapour", ["--water-vapour = None", "column water vapour", "ST_B10"]),
    ("bg-out-not-empty", ["--out", "exists and is not empty", "--force"]),
    ("bg-no-roi", ["--roi = None", "is required"]),
]


@pytest.mark.parametrize("case, fragments", BACKGROUND_CASES, ids=[c[0] for c in BACKGROUND_CASES])
def test_background_bad_input(case, fragments, tmp_path, capsys, request):
    argv = _bg_case(tmp_path, case, request.getfixturevalue("port"))
    before = _tree(tmp_path)
    code, err = _run(argv, capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err
    assert _tree(tmp_path) == before        # nothing written, nothing removed


def test_background_command_on_the_real_port(tmp_path, capsys):
    code, err = _run(["background", "--mtl", str(_MERSEY / _MERSEY_MTL), "--roi",
                      str(_MERSEY / "mersey_rois.geojson"), "--out", str(tmp_path / "bg")], capsys)
    assert code == 0, err
    names = {p.name for p in (tmp_path / "bg").iterdir()}
    assert {"lst_K.tif", "class_map.tif", "qa_mask.tif", "accuracy_splits.csv", "summary.json",
            "water_disagreement.tif", "jm_separability.txt"} <= names
    assert "georeferencing from the MTL" in err and "ST_B10" in err
    with rasterio.open(tmp_path / "bg" / "lst_K.tif") as src:
        assert src.crs.to_epsg() == 32630 and src.shape == (267, 433)
    assert [p.name for p in tmp_path.iterdir()] == ["bg"]          # no temporary folder left


def test_background_command_hourly_with_dem_and_met(port, tmp_path, capsys):
    code, err = _run(["-q", "background", "--mtl", port.mtl_txt, "--roi", port.roi, "--dem", port.dem,
                      "--met", port.met, "--out", str(tmp_path / "bg")], capsys)
    assert code == 0, err
    with rasterio.open(tmp_path / "bg" / "background_K.tif") as src:
        assert src.count == 24
    summary = json.loads((tmp_path / "bg" / "summary.json").read_text())
    assert summary["lst_source"] == "single_channel" and summary["accuracy_over_splits"]["n_splits"] == 10
    assert (tmp_path / "bg" / "qa_mask.tif").is_file()


# ---------------------------------------------------------------------------------------
# met grids (NetCDF / GRIB) and DEMs as users download them
# ---------------------------------------------------------------------------------------
_ERA5 = Path(__file__).resolve().parents[1] / "data" / "met" / "era5_t2m_2019-03-01_02_uk.grib"

MET_DEM_CASES = [
    ("met-grib-no-time-axis", ["met[t2m].time = 'no time axis (one time step)'", "24 hourly fields"]),
    ("met-grib-truncated", ["background.met = ", "truncated or damaged GRIB file",
                            "Download it again"]),
    ("met-misses-scene", ["met.extent", "misses the scene entirely"]),
    ("met-kelvin-labelled-celsius", ["met[temperature].units = '[C]'", "are kelvin",
                                     "met_units = 'K'"]),
    ("dem-no-overlap", ["background.dem.extent", "does not overlap the scene"]),
    ("dem-truncated", ["dem", "readable"]),
]


def _met_dem_case(d, case, port):
    import eccodes
    from affine import Affine

    src = d / "port"
    shutil.copytree(port.directory, src)
    files = {k: src / (getattr(port, k).rsplit("/", 1)[1]) for k in ("mtl_txt", "dem", "met",
                                                                    "roi")}
    mtl, dem, met, roi = files["mtl_txt"], files["dem"], files["met"], files["roi"]
    if case == "met-grib-no-time-axis":
        met = d / "one.grib"
        with open(_ERA5, "rb") as f:
            h = eccodes.codes_grib_new_from_file(f)
            met.write_bytes(eccodes.codes_get_message(h))
            eccodes.codes_release(h)
    elif case == "met-grib-truncated":
        met = d / "cut.grib"
        met.write_bytes(_ERA5.read_bytes()[:100_000])
    elif case == "met-misses-scene":
        met = d / "far.nc"
        ds = xr.open_dataset(files["met"]).load()
        ds.assign_coords(lon=ds.lon + 5.0).to_netcdf(met, engine="h5netcdf")
    elif case == "met-kelvin-labelled-celsius":
        met = d / "c.nc"
        ds = xr.open_dataset(files["met"]).load()
        ds["temperature"].attrs["units"] = "[C]"
        ds.to_netcdf(met, engine="h5netcdf")
    elif case == "dem-no-overlap":
        dem = d / "far.tif"
        with rasterio.open(files["dem"]) as s:
            profile, data = s.profile, s.read(1)
        profile.update(transform=Affine.translation(20.0, 0.0) @ profile["transform"])
        with rasterio.open(dem, "w", **profile) as out:
            out.write(data, 1)
    elif case == "dem-truncated":
        dem = d / "cut.tif"
        dem.write_bytes(files["dem"].read_bytes()[:3000])
    sc = write_tiny(d, name="r")
    bg = (f'[background]\nsource = "files"\nmtl = "{mtl}"\ndem = "{dem}"\nmet = "{met}"\n'
          f'roi = "{roi}"\n')
    sc.write_text(sc.read_text().replace("[background]\nsize_px = 100\n", "") + bg)
    return ["-q", "run", str(sc), "--image", "--out", str(d / "out")]


@pytest.mark.parametrize("case, fragments", MET_DEM_CASES, ids=[c[0] for c in MET_DEM_CASES])
def test_bad_met_or_dem(case, fragments, tmp_path, capsys, port):
    argv = _met_dem_case(tmp_path, case, port)
    before = _tree(tmp_path)
    code, err = _run(argv, capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err, err
    assert _tree(tmp_path) == before


# =======================================================================================
# pictures and report: the image panels' colour-scale choice (one message, exit 2, nothing
# written)
# =======================================================================================
@pytest.mark.parametrize("value, fragments", [
    ('"perpanel"', ["imaging.panel_colour_scale", "perpanel", "'shared', 'per_panel'"]),
    ("1", ["imaging.panel_colour_scale", "'shared', 'per_panel'"]),
])
def test_bad_panel_colour_scale(value, fragments, tmp_path, capsys):
    sc = write_tiny(tmp_path, extra=f"[imaging]\npanel_colour_scale = {value}\n")
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--image", "--out", str(tmp_path / "out")], capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err
    assert _tree(tmp_path) == before


# =======================================================================================
# `shipthermal calibrate`: measurement CSV, unknowns and cases; one message, exit 2,
# nothing left behind (every check comes before the first model run)
# =======================================================================================
_CAL_OK = "case,time,target,temperature_K\nmy.toml,12:00,deck,305.0\nmy.toml,15:00,deck,301\n"
CALIBRATE_CASES = [
    # (id, csv text or None, extra argv, fragments)
    ("cal-no-file", None, ["--unknown", "weather.cloud_cover_offset=-0.5:0.5"],
     ["measurement CSV", "--paper"]),
    ("cal-no-unknown", _CAL_OK, [], ["--unknown", "at least one unknown"]),
    ("cal-unknown-syntax", _CAL_OK, ["--unknown", "weather.cloud_cover_offset"],
     ["--unknown", "KEY=LOWER:UPPER"]),
    ("cal-unknown-not-numeric", _CAL_OK, ["--unknown", "weather.source=0:1"],
     ["weather.source", "numeric scenario key"]),
    ("cal-unknown-bound-rejected", _CAL_OK, ["--unknown", "ship.solar_absorptivity.deck=0.5:1.5"],
     ["ship.solar_absorptivity.deck", "not accepted by the scenario"]),
    ("cal-unknown-case", _CAL_OK, ["--unknown", "winter:weather.wind_speed_offset=-1:1"],
     ["winter:weather.wind_speed_offset", "case without measurements"]),
    ("cal-missing-column", "case,time,target\nmy.toml,12:00,deck\n",
     ["--unknown", "weather.wind_speed_offset=-1:1"], ["temperature_K", "missing"]),
    ("cal-bad-time", "case,time,target,temperature_K\nmy.toml,noon,deck,300\n",
     ["--unknown", "weather.wind_speed_offset=-1:1"], ["row 2: time", "HH:MM"]),
    ("cal-celsius-as-kelvin", "case,time,target,temperature_K\nmy.toml,12:00,deck,31.5\n",
     ["--unknown", "weather.wind_speed_offset=-1:1"], ["temperature_K", "temperature_C"]),
    ("cal-bad-case", "case,time,target,temperature_K\nautumn,12:00,deck,300\n",
     ["--unknown", "weather.wind_speed_offset=-1:1"], ["autumn", "scenario TOML"]),
    ("cal-bad-part", "case,time,target,temperature_K\nmy.toml,12:00,funnel,300\n",
     ["--unknown", "weather.wind_speed_offset=-1:1"], ["funnel", "must be a part", "point:x y z"]),
    ("cal-no-fit-rows", "case,time,target,temperature_K,split\nmy.toml,12:00,deck,300,holdout\n",
     ["--unknown", "weather.wind_speed_offset=-1:1"], ["split 'fit'"]),
    ("cal-paper-with-file", _CAL_OK, ["--paper"], ["--paper", "no measurement file"]),
]


@pytest.mark.parametrize("case, csv, extra, fragments", CALIBRATE_CASES,
                         ids=[c[0] for c in CALIBRATE_CASES])
def test_calibrate_bad_input(case, csv, extra, fragments, tmp_path, capsys, monkeypatch):
    write_tiny(tmp_path, name="my")
    argv = ["-q", "calibrate"]
    if csv is not None:
        (tmp_path / "m.csv").write_text(csv)
        argv.append(str(tmp_path / "m.csv"))
    argv += extra + ["--out", str(tmp_path / "out")]
    monkeypatch.chdir(tmp_path)
    before = _tree(tmp_path)
    code, err = _run(argv, capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert _tree(tmp_path) == before


# =======================================================================================
# `shipthermal ensemble`: members, distributions, scenario; one message, exit 2, nothing
# left behind (every member is validated before the first model run)
# =======================================================================================
ENSEMBLE_CASES = [
    # (id, argv after the scenario, fragments)
    ("ens-one-member", ["--members", "1"], ["--members", ">= 2"]),
    ("ens-negative-seed", ["--seed", "-1"], ["--seed = -1", "must be an integer in [0, "
                                             "4294967295]"]),
    ("ens-unknown-dist", ["--dist", "humidity=normal:0:5"], ["--dist", "humidity",
                                                              "cloud, wind, air"]),
    ("ens-dist-syntax", ["--dist", "wind=gauss:0:1"], ["--dist", "NAME=uniform:LOWER:UPPER"]),
    ("ens-dist-empty-range", ["--dist", "cloud=uniform:0.3:-0.3"], ["LOWER < UPPER"]),
    ("ens-dist-sd", ["--dist", "air=normal:0:0"], ["standard deviation > 0"]),
    ("ens-dist-out-of-scenario-range", ["--dist", "cloud=uniform:-2:-1.5"],
     ["weather.cloud_cover_offset", "must lie in"]),
]


@pytest.mark.parametrize("case, extra, fragments", ENSEMBLE_CASES,
                         ids=[c[0] for c in ENSEMBLE_CASES])
def test_ensemble_bad_input(case, extra, fragments, tmp_path, capsys, monkeypatch):
    sc = write_tiny(tmp_path, name="my")
    monkeypatch.chdir(tmp_path)
    before = _tree(tmp_path)
    code, err = _run(["-q", "ensemble", str(sc), "--serial", "--out", str(tmp_path / "out")]
                     + extra, capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err
    assert _tree(tmp_path) == before


def test_ensemble_missing_scenario(tmp_path, capsys):
    before = _tree(tmp_path)
    code, err = _run(["-q", "ensemble", str(tmp_path / "nope.toml"), "--out",
                      str(tmp_path / "out")], capsys)
    assert code == 2 and "nope.toml" in err and len(err.strip().splitlines()) == 1, err
    assert _tree(tmp_path) == before


# =======================================================================================
# atmosphere and sensor: unknown model / deck / preset names, a bad response table, a band
# outside the atmosphere tables (one message naming the key and the allowed, exit 2,
# nothing written)
# =======================================================================================
def _response(tmp_path, rows):
    f = tmp_path / "band.csv"
    f.write_text("wavelength_um,response\n" + "".join(f"{w},{r}\n" for w, r in rows))
    return f.name


@pytest.mark.parametrize("case, extra, fragments", [
    ("atm-model", '[imaging.atmosphere]\nmodel = "arctic"\n',
     ["imaging.atmosphere.model", "arctic", "'tropical'", "'subarctic_winter'",
      "'us_standard_1976'"]),
    ("atm-cloud", '[imaging.atmosphere]\ncloud_type = "cirrus"\n',
     ["imaging.atmosphere.cloud_type", "'stratus'", "'nimbostratus'"]),
    ("sensor-preset", '[imaging.sensor]\npreset = "landsat7"\n',
     ["imaging.sensor.preset", "landsat7", "'landsat8_tirs'", "'ecostress'", "'user'"]),
    ("sensor-user-no-file", '[imaging.sensor]\npreset = "user"\n',
     ["imaging.sensor.response_file", "is required with preset = 'user'"]),
    ("sensor-bands-of-another", '[imaging]\nbands = ["8-14"]\n[imaging.sensor]\n'
     'preset = "landsat8_tirs"\n', ["imaging.bands", "landsat8_tirs_b10", "Remove imaging.bands"]),
    ("band-outside-tables", '[imaging]\nbands = ["14-16"]\n',
     ["imaging.bands", "2.9 <= lo < hi <= 14.5"]),
])
def test_atmosphere_and_sensor_bad_input(case, extra, fragments, tmp_path, capsys):
    sc = write_tiny(tmp_path, extra=extra)
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--image", "--out", str(tmp_path / "out")], capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err
    assert _tree(tmp_path) == before


@pytest.mark.parametrize("case, extra, fragments", [
    ("material-without-k", '\n[materials.plate]\ndensity = 7850.0\nspecific_heat = 470.0\n'
     'source = "mill certificate"\n',
     ["materials.plate.conductivity", "is required", "[0.001, 500] W m-1 K-1",
      "e.g. [materials.my_steel]"]),
    ("layup-unknown-material", '\n[ship.layups]\ndeck = [{material = "plate", thickness = '
     '0.008}]\n', ["ship.layups.deck[0].material", "'mild_steel'", "[materials.plate]"]),
    ("layer-zero-thickness", '\n[ship.layups]\ndeck = [{material = "mild_steel", thickness = '
     '0.0}]\n', ["ship.layups.deck[0].thickness", "(0, 1] m", "in metres"]),
    ("convection-model-for-a-part", '\n[convection.parts]\ndeck = "doe-2"\n',
     ["convection.parts.deck", "'doe2'", "'flat_plate_turbulent'", "Did you mean 'doe2'?"]),
])
def test_bad_materials_and_convection_exit_2(case, extra, fragments, tmp_path, capsys):
    # a user's material, a layer and a part's convection model: exit 2 naming the key, the
    # allowed values and the fix; nothing written
    path = write_tiny(tmp_path, name="t", extra=extra)
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(path), "--out", str(tmp_path / "out")], capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert "Traceback" not in err
    assert _tree(tmp_path) == before


@pytest.mark.parametrize("rows, fragments", [
    ([(-1.0, 0.0), (10.0, 1.0)], ["response_file", "positive", "micrometres"]),
    ([(10.0, 0.5), (9.0, 1.0), (11.0, 0.0)], ["response_file", "increase", "Sort the table"]),
])
def test_bad_response_file(rows, fragments, tmp_path, capsys):
    name = _response(tmp_path, rows)
    sc = write_tiny(tmp_path, extra=f'[imaging.sensor]\npreset = "user"\nresponse_file = '
                                    f'"{name}"\n')
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--image", "--out", str(tmp_path / "out")], capsys)
    assert code == 2, err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"
    assert _tree(tmp_path) == before
