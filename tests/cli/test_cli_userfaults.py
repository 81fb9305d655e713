"""Catalogue of user faults over every command: each refused with exit code 2 and one
clear line, nothing left behind and nothing of the user's changed.

Every case asserts

* exit code 2 (user error), never 1 and never a traceback;
* exactly one error line on stderr (``shipthermal check`` may add ``note:`` lines of what
  it read), holding the fragments listed: the key, flag or file, the value and what is
  allowed or how to fix it;
* that no ``out`` folder exists afterwards and every file the user had is there with the
  same bytes (a SHA-256 of each before and after), and no other file appeared.

The cases include each fault of the issue that asked for this catalogue: files that used to
end in exit 1 (a truncated PLY, an ASCII STL with a bad number, a garbage DEM, a negative
ensemble seed, deeply nested TOML, an edge length that exhausts the memory, a disk that
fills while a checkpoint is written), files too large to read (2 GB of zeros named .stl,
a scenario of megabytes), a weather file linked to a file whose contents must not be shown,
contradictions (a sweep key both fixed and an axis, repeated axis values), unclear
messages (UTF-16 / BOM / Latin-1 scenarios, semicolon CSVs, NDBC / TMY3 / EPW data named
.csv, files that are not meshes), inputs that make no physical sense (degF read as degC,
humidity as a fraction, a typical-year file of another city, a deck facing down, an
inside-out piece, a ship over the pier, a Level-1 scene without water vapour for
`shipthermal background`, a calibration time 12:61), and messages that named library
arguments instead of the user's keys.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import trimesh
from cli_helpers import write_tiny

from shipthermal.app.cli import main

ROOT = Path(__file__).resolve().parents[2]
NDBC = ROOT / "tests" / "data" / "weather" / "44009h2013_mar03-09.txt"
SECRET = "root:$6$x9Tq.secret-hash$Zm9v:19000:0:99999:7:::"


# ---------------------------------------------------------------------------------------
# the assertions
# ---------------------------------------------------------------------------------------
_HASHED_BYTES = 64 * 2 ** 20
"""Files up to this size are compared by their bytes' hash; larger ones (the sparse
gigabyte meshes) by size, modification time and inode: any write changes the time."""


def _snapshot(root: Path) -> dict:
    """Every file and link under ``root``: its bytes' SHA-256 (a link: its target; a file
    over :data:`_HASHED_BYTES`: its size, modification time and inode)."""
    out = {}
    for p in sorted(root.rglob("*")):
        rel = str(p.relative_to(root))
        if p.is_symlink():
            out[rel] = "link:" + os.readlink(p)
        elif p.is_file():
            st = p.stat()
            if st.st_size > _HASHED_BYTES:
                out[rel] = f"stat:{st.st_size}:{st.st_mtime_ns}:{st.st_ino}"
                continue
            try:
                out[rel] = hashlib.sha256(p.read_bytes()).hexdigest()
            except PermissionError:
                out[rel] = "unreadable"
        else:
            out[rel] = "dir"
    return out


def _run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:                   # argparse's own errors
        code = exc.code
    cap = capsys.readouterr()
    return code, cap.err


def _check_refusal(d: Path, argv, fragments, capsys, absent=()):
    before = _snapshot(d)
    code, err = _run(argv, capsys)
    assert code == 2, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    errors = [ln for ln in lines if ": note: " not in ln]
    assert len(errors) == 1, lines
    line = errors[0]
    for f in fragments:
        assert f in line, f"{f!r} not in {line!r}"
    assert "Traceback" not in err
    assert not (d / "out").exists()
    assert _snapshot(d) == before           # nothing written, removed or changed
    for text in absent:
        assert text not in err, err
    return line


# ---------------------------------------------------------------------------------------
# inputs
# ---------------------------------------------------------------------------------------
def _box_stl(path, **kw):
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    v = np.asarray(m.vertices) + [0.0, 0.0, 1.0]        # keel at -4 m, deck at +6 m
    f = np.asarray(m.faces)
    top = m.face_normals[:, 2] > (-0.5 if kw.get("bottom_last") else 0.5)
    if kw.get("bottom_last"):
        top = ~top                                      # the bottom's faces 10-11
    f = np.vstack([f[~top], f[top]])                    # hull faces 0-9, deck 10-11
    if kw.get("drop"):
        f = f[:-1]
    if kw.get("flip"):
        f = f[:, ::-1]
    if kw.get("scale"):
        v = v * kw["scale"]
    if kw.get("swap"):
        v = v[:, [1, 0, 2]]
    trimesh.Trimesh(v, f, process=False).export(path)
    return path


def _parts(d, name="parts.json", parts=None):
    (d / name).write_text(json.dumps({"parts": parts or {"hull": [[0, 10]],
                                                         "deck": [[10, 12]]}}))
    return name


def _mesh_toml(d, mesh="box.stl", name="s", part_map="parts.json", extra="", ship_extra="",
               draught="draught = 4.0"):
    lines = ["[ship]"] + ([ship_extra] if ship_extra else []) + \
        ["[ship.files]", f'mesh = "{mesh}"', 'units = "m"']
    if part_map:
        lines.append(f'part_map = "{part_map}"')
    if draught:
        lines.append(draught)
    (d / f"{name}.toml").write_text("\n".join(lines) + "\n" + extra)
    return str(d / f"{name}.toml")


def _mesh_case(writer, mesh_name, cmd="mesh", **toml):
    def make(d):
        _parts(d)
        _parts(d, "p11.json", {"hull": [[0, 10]], "deck": [[10, 11]]})
        writer(d / mesh_name)
        sc = _mesh_toml(d, mesh=mesh_name, **toml)
        return ["-q", cmd, sc] + (["--out", str(d / "out")] if cmd != "check" else [])
    return make


HEADER = "time,temp_air,relative_humidity,wind_speed,wind_direction,cloud_cover,temp_sea"


def _weather_csv(path, air=None, rh=75.0, sea=23.5, wind=4.0, header=HEADER, edit=None,
                 offset="+08:00"):
    rows = []
    for h in range(24):
        a = 24 + 4 * np.sin(h / 4) if air is None else air(h)
        rows.append(f"2023-07-15T{h:02d}:00:00{offset},{a:.2f},{rh},{wind},180,0.3,{sea}")
    if edit:
        rows = edit(rows)
    path.write_text(header + "\n" + "\n".join(rows) + "\n")
    return path


def _weather_scenario(d, source, weather_extra="", top="", name="w", date=None):
    sc = write_tiny(d, name=name)
    text = sc.read_text().replace("[ship]", f'[weather]\nsource = "{source}"\n'
                                  f"{weather_extra}\n[ship]")
    time = "[time]\n" + (f"date = {date}\n" if date else "")
    sc.write_text(text.replace("[time]\n", top + time))
    return str(sc)


def _weather_case(write, extra="", cmd="run", top="", date=None):
    def make(d):
        src = write(d)
        sc = _weather_scenario(d, src, extra, top, date=date)
        return ["-q", cmd, sc] + (["--out", str(d / "out")] if cmd in ("run", "calendar")
                                  else [])
    return make


def _scenario_case(text, cmd="run"):
    """A scenario file with one bad key: TOML text, or bytes as they are."""
    def make(d):
        p = d / "bad.toml"
        if isinstance(text, bytes):
            p.write_bytes(text)
        else:
            p.write_text(text)
        argv = ["-q", cmd, str(p)]
        return argv + (["--out", str(d / "out")] if cmd in ("run", "mesh") else [])
    return make


def _tiny_case(extra, cmd="run", **kw):
    def make(d):
        sc = write_tiny(d, name="t", **kw)
        sc.write_text(sc.read_text() + extra)
        return ["-q", cmd, str(sc)] + (["--out", str(d / "out")] if cmd in ("run", "mesh")
                                       else [])
    return make


def _epw(path, site="San Francisco", lat=37.62, lon=-122.40, tz=-8.0):
    head = [f"LOCATION,{site},CA,USA,SYNTHETIC,724940,{lat},{lon},{tz},5.0",
            "DESIGN CONDITIONS,0", "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0",
            "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0", "COMMENTS 1,written by the test suite",
            "COMMENTS 2,", "DATA PERIODS,1,1,Data,Friday, 7/14, 7/16"]
    rows = []
    for i in range(72):
        day, hour = 14 + i // 24, i % 24 + 1
        ghi = max(0.0, 800.0 * np.sin(2 * np.pi * (hour - 6) / 24))
        f = [2023, 7, day, hour, 0, "?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9?9?9",
             24 + (i % 24) / 4, 18.0, 80, 101000, 9999, 9999, 390 + i, round(ghi, 1), 0, 0,
             999999, 999999, 999999, 9999, (170 + i) % 360, 3.5, 5, 5, 9999, 99999, 9,
             999999999, 999, 0.999, 999, 99, 999, 0, 0]
        rows.append(",".join(str(x) for x in f))
    path.write_text("\n".join(head + rows) + "\n")
    return path


# ---------------------------------------------------------------------------------------
# the catalogue: (id, argv builder, fragments of the one error line)
# ---------------------------------------------------------------------------------------
CASES = []


def case(cid, make, fragments, **opts):
    CASES.append(pytest.param(make, fragments, opts, id=cid))


# ---- user meshes: files that used to crash the parser (exit 1) or pass silently ----------
def _truncated_ply(p):
    _box_stl(p.with_suffix(".tmp.ply"))
    b = p.with_suffix(".tmp.ply").read_bytes()
    p.with_suffix(".tmp.ply").unlink()
    p.write_bytes(b[:len(b) // 2])


def _bad_number_stl(p):
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    m.apply_translation([0.0, 0.0, 1.0])
    text = trimesh.exchange.stl.export_stl_ascii(m).splitlines()
    text[3] = "      vertex 1.2.3 0 0"
    p.write_text("\n".join(text) + "\n")


def _sparse(size, header=b""):
    def write(p):
        with open(p, "wb") as fh:
            fh.write(header)
            fh.truncate(size)
    return write


for cmd in ("mesh", "run", "check"):
    case(f"{cmd}-truncated-ply", _mesh_case(_truncated_ply, "ship.ply", cmd),
         ["ship.files.mesh = 'ship.ply'", "is not a readable PLY file", "truncated"])
    case(f"{cmd}-ascii-stl-bad-number", _mesh_case(_bad_number_stl, "ship.stl", cmd),
         ["ship.files.mesh = 'ship.stl'", "line 4: a vertex coordinate is not a number"])
case("mesh-2gb-of-zeros-stl", _mesh_case(_sparse(2 * 10 ** 9), "zeros.stl"),
     ["ship.files.mesh = 'zeros.stl'", "more than the 1024 MiB"])
case("mesh-zeros-stl-declares-nothing", _mesh_case(_sparse(10 ** 6), "zeros.stl"),
     ["zeros.stl", "count (0) needs 84 bytes where it has 1,000,000"])
case("mesh-stl-declares-too-many", _mesh_case(
    _sparse(84 + 50 * 6_000_000, b"\0" * 80 + np.uint32(6_000_000).tobytes()), "big.stl"),
     ["big.stl", "declares 6,000,000 triangles, more than the 5,000,000"])
case("mesh-text-not-stl", _mesh_case(lambda p: p.write_text("this is not a mesh\n"), "n.stl"),
     ["n.stl", "is not an STL file", "'solid'"])
case("mesh-secret-not-stl", _mesh_case(lambda p: p.write_text(SECRET + "\n"), "s.stl"),
     ["s.stl", "is not an STL file"], absent=("secret-hash", "root:"))
case("mesh-ply-not-ply", _mesh_case(lambda p: p.write_text(SECRET), "p.ply"),
     ["p.ply", "is not a PLY file"], absent=("secret-hash",))
case("mesh-glb-not-gltf", _mesh_case(lambda p: p.write_bytes(b"PK\3\4zipdata" * 10), "g.glb",
                                     part_map=None),
     ["g.glb", "is not a binary glTF file"])
case("mesh-obj-binary", _mesh_case(lambda p: p.write_bytes(b"\0\1\2\3" * 64), "b.obj",
                                   part_map=None),
     ["b.obj", "is not a text OBJ file"])
case("mesh-empty-file", _mesh_case(lambda p: p.write_bytes(b""), "e.stl"),
     ["e.stl", "is empty (0 bytes)"])


def _nan_stl(p):
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    v = np.array(m.vertices)
    v[0, 0] = np.nan
    trimesh.Trimesh(v, m.faces, process=False).export(p)


case("mesh-nan-vertex", _mesh_case(_nan_stl, "nan.stl"), ["nan.stl", "not finite numbers"])
case("mesh-open", _mesh_case(lambda p: _box_stl(p, drop=True), "open.stl",
                             part_map="p11.json"),
     ["open edges", "must be closed (watertight)", 'ship.files.repair = "tetwild"'])
case("mesh-inverted", _mesh_case(lambda p: _box_stl(p, flip=True), "flip.stl"),
     ["the normals point into the ship", "ship.files.fix_normals = true"])
case("mesh-millimetres", _mesh_case(lambda p: _box_stl(p, scale=1000.0), "mm.stl"),
     ["ship length of 100000 m", 'ship.files.units = "mm"'])
case("mesh-axes", _mesh_case(lambda p: _box_stl(p, swap=True), "swap.stl"),
     ["longest dimension must lie along x"])
case("mesh-draught-too-deep", _mesh_case(_box_stl, "box.stl", draught="draught = 40.0"),
     ["ship.files.draught = 40.0", "between 0 and the height of the mesh"])
case("mesh-waterline-outside", _mesh_case(_box_stl, "box.stl", draught="waterline_z = 50.0"),
     ["ship.files.waterline_z = 50.0", "must cut the ship"])
case("mesh-units-missing", lambda d: (_parts(d), _box_stl(d / "box.stl"),
                                      (d / "s.toml").write_text(
                                          '[ship.files]\nmesh = "box.stl"\npart_map = '
                                          '"parts.json"\n'),
                                      ["-q", "mesh", str(d / "s.toml"), "--out",
                                       str(d / "out")])[-1],
     ["ship.files.units = None", "'m' or 'mm'"])
case("mesh-partmap-missing", _mesh_case(_box_stl, "box.stl", part_map=None),
     ["ship.files.part_map = None", "is required with a .stl mesh"])
case("mesh-partmap-overlap", lambda d: (_box_stl(d / "box.stl"), _parts(d, "o.json", {
    "hull": [[0, 11]], "deck": [[10, 12]]}), ["-q", "mesh", _mesh_toml(d, part_map="o.json"),
                                            "--out", str(d / "out")])[-1],
     ["part_map['deck'] = [10, 12]", "overlaps part 'hull' at face 10"])
case("mesh-partmap-uncovered", lambda d: (_box_stl(d / "box.stl"), _parts(d, "u.json", {
    "hull": [[0, 9]], "deck": [[10, 12]]}), ["-q", "mesh", _mesh_toml(d, part_map="u.json"),
                                           "--out", str(d / "out")])[-1],
     ["1 faces without a part", "first uncovered: face 9"])
case("mesh-deck-facing-down", lambda d: (_box_stl(d / "box.stl", bottom_last=True), _parts(d),
    ["-q", "mesh", _mesh_toml(d), "--out", str(d / "out")])[-1],
     ["ship.files.part_map", "of the deck's area faces the sky", "Check ship.files.part_map"])
case("mesh-no-wetted-hull", lambda d: (_box_stl(d / "box.stl"), _parts(d, "dry.json", {
    "hull_dry": [[0, 10]], "deck": [[10, 12]]}),
    ["-q", "mesh", _mesh_toml(d, part_map="dry.json"), "--out", str(d / "out")])[-1],
     ["no triangle belongs to the wetted hull"])
case("mesh-edge-length-exhausts-memory", _mesh_case(_box_stl, "box.stl", cmd="run",
                                                    ship_extra="edge_length = 0.001"),
     ["ship.edge_length = 0.001", "surface triangles", "more than the 2,000,000",
      "Use ship.edge_length >= 0.074 m"])
case("mesh-cli-edge-length-exhausts-memory", lambda d: (
    _parts(d), _box_stl(d / "box.stl"),
    ["-q", "mesh", _mesh_toml(d), "--edge-length", "0.001", "--out", str(d / "out")])[-1],
     ["ship.edge_length = 0.001", "more than the 2,000,000"])
case("mesh-union-on-open-pieces", _mesh_case(lambda p: _box_stl(p, drop=True), "open.stl",
                                             part_map="p11.json",
                                             extra='repair = "union"\n'),
     ["ship.files.repair = 'union'", "needs closed pieces"])


def _inside_out_piece(p):
    """The box barge and a separate closed container above its deck, inside-out."""
    hull = trimesh.creation.box((100.0, 12.0, 10.0))
    hull.apply_translation([0.0, 0.0, 1.0])
    box = trimesh.creation.box((12.0, 2.5, 2.6))
    box.apply_translation([0.0, 0.0, 6.0 + 0.5 + 1.3])
    v = np.vstack([hull.vertices, box.vertices])
    f = np.vstack([hull.faces, box.faces[:, ::-1] + len(hull.vertices)])
    trimesh.Trimesh(v, f, process=False).export(p)


case("mesh-inside-out-piece", _mesh_case(_inside_out_piece, "io.stl", part_map='auto'),
     ["1 separate piece(s) (12 triangles", "inside-out", "ship.files.fix_normals = true"])
for cmd in ("run", "check"):
    case(f"{cmd}-mesh-missing", _mesh_case(lambda p: None, "nowhere.stl", cmd),
         ["ship.files.mesh = 'nowhere.stl'", "must be an existing file"])


# ---- scenario files: reading ----------------------------------------------------------
case("run-scenario-missing", lambda d: ["-q", "run", str(d / "nope.toml")],
     ["nope.toml", "must be an existing TOML file"])
case("check-deeply-nested", _scenario_case("a = " + "[" * 5000 + "]" * 5000 + "\n", "check"),
     ["bad.toml", "nests arrays or tables too deeply"])
case("run-deeply-nested", _scenario_case("a = " + "[" * 5000 + "]" * 5000 + "\n"),
     ["bad.toml", "nests arrays or tables too deeply"])
case("run-nested-beyond-limit", _scenario_case("a = " + "[" * 20 + "1" + "]" * 20 + "\n"),
     ["nests tables and arrays 16+ levels deep at a"])
case("check-oversized", _scenario_case("# " + "x" * (2 << 20) + "\n", "check"),
     ["bad.toml", "more than the 1,048,576"])
case("run-map-times-too-many", _scenario_case(
    "[time]\nmap_times = [" + ",".join('"12:00"' for _ in range(2000)) + "]\n"),
     ["time.map_times", "at most 1440 (one per minute)"])
case("check-list-too-long", _scenario_case(
    "description = \"x\"\nextra = [" + ",".join("1" for _ in range(12000)) + "]\n", "check"),
     ["has a list of 12,000 values at extra (at most 10,000)"])
case("run-not-toml", _scenario_case("[ship\nheading = 3\n"), ["must be valid TOML"])
case("check-utf16-bad-key", _scenario_case('[ship]\nheadng = 90\n'.encode("utf-16"), "check"),
     ["ship.headng", "unknown key", "Did you mean 'heading'?"], absent=("Invalid statement",))
case("run-bom-bad-value", _scenario_case(b"\xef\xbb\xbf[ship]\nheading = 400\n"),
     ["ship.heading = 400", "must lie in [0, 360) deg"], absent=("Invalid statement",))
case("check-latin1", _scenario_case('description = "Kr\xf8yer"\n'.encode("latin-1"), "check"),
     ["bad.toml", "must be UTF-8 text (byte 17 is not UTF-8)", "Save the file as UTF-8"])
case("mesh-binary-scenario", _scenario_case(b"\x89PNG\r\n\x1a\n\0\0\0", "mesh"),
     ["must be UTF-8 text"])

# ---- scenario keys: one bad key each, over run / check / mesh --------------------------
SCENARIO_FAULTS = [
    ("date-not-a-day", "[time]\ndate = \"2023-02-30\"\n", ["time.date", "check that the day "
                                                          "exists"]),
    ("map-time-minute-61", "[time]\nmap_times = [\"12:61\"]\n", ["time.map_times[0] = '12:61'",
                                                               "(00:00-23:59)"]),
    ("image-time-25h", "[imaging]\ntimes = [\"25:00\"]\n", ["imaging.times[0] = '25:00'"]),
    ("output-interval", "[time]\noutput_interval = 7.0\n", ["time.output_interval = 7.0",
                                                            "must divide 24 h"]),
    ("latitude", "[location]\nlatitude = 95.0\n", ["location.latitude = 95.0", "must lie in"]),
    ("time-zone", "[location]\ntime_zone = \"Mars/Olympus\"\n", ["location.time_zone",
                                                               "IANA time-zone name"]),
    ("season", "[time]\nseason = \"autumn\"\n", ["time.season = 'autumn'", "'summer', 'winter'"]),
    ("weather-file-missing", "[weather]\nsource = \"nowhere.csv\"\n",
     ["weather.source = 'nowhere.csv'", "must be an existing file"]),
    ("builtin-ship", "[ship]\nbuiltin = \"submarine\"\n", ["ship.builtin = 'submarine'"]),
    ("heading", "[ship]\nheading = 400\n", ["ship.heading = 400", "[0, 360) deg"]),
    ("edge-negative", "[ship]\nedge_length = -1.0\n", ["ship.edge_length = -1.0", "must lie in"]),
    ("builtin-edge-exhausts-memory", "[ship]\nedge_length = 0.02\n",
     ["ship.edge_length = 0.02", "41,458,368 surface triangles", ">= 0.092 m"]),
    ("mooring-outside-scene", "[ship]\nmooring_position = [1.0e6, 0.0]\n",
     ["ship.mooring_position", "must lie inside the port scene"]),
    ("time-step", "[solver]\ntime_step = 7.0\n", ["solver.time_step = 7.0", "must divide 24 h"]),
    ("seed-negative", "[solver]\nseed = -1\n", ["solver.seed = -1", "must lie in"]),
    ("band", "[imaging]\nbands = [\"2-3\"]\n", ["imaging.bands[0] = '2-3'"]),
    ("view-zenith", "[imaging.sensor]\nview_zenith_deg = 84.0\n",
     ["imaging.sensor.view_zenith_deg = 84.0", "'table' atmosphere backend"]),
    ("output-format", "[outputs]\nformats = [\"xls\"]\n", ["outputs.formats[0] = 'xls'"]),
    ("checkpoint-interval", "[outputs]\ncheckpoint_interval = 700.0\n",
     ["outputs.checkpoint_interval = 700.0", "multiple of solver.time_step"]),
    ("size-px", "[background]\nsize_px = 10\n", ["background.size_px = 10", "must lie in"]),
    ("unknown-key", "[ship]\nheadng = 90\n", ["ship.headng", "Did you mean 'heading'?"]),
    ("name", "name = \"a/b\"\n", ["name = 'a/b'", "It names the run directory"]),
    ("layup-empty", "[ship.layups]\ndeck = []\n", ["ship.layups.deck = []",
                                                   "non-empty list of layers"]),
    ("emissivity-over-one", "[ship.band_emissivity.deck]\n\"8-14\" = 1.5\n",
     ["ship.band_emissivity.deck.8-14 = 1.5", "must lie in (0, 1]"]),
    ("convection-model", "[convection]\nmodel = \"magic\"\n", ["convection.model = 'magic'"]),
    ("water-vapour-builtin", "[background]\nwater_vapour = 2.0\n",
     ["background.water_vapour = 2.0", "only applies with source = 'files'"]),
    ("weather-days-periodic", "[weather]\nsource = \"builtin\"\ndays = 3\n",
     ["weather.days = 3", "only applies to a weather file"]),
    ("ship-length", "[ship.parameters]\nlength = 1000.0\n",
     ["ship.parameters.length = 1000.0", "must lie in [5, 500] m"]),
    ("compartment-temperature", "[ship.compartment_temperature]\ndeck = 20.0\n",
     ["ship.compartment_temperature.deck = 20.0", "must lie in [200, 400] K"]),
    ("speed", "[ship]\nspeed = 100.0\n", ["ship.speed = 100.0", "must lie in"]),
]
for i, (cid, text, frags) in enumerate(SCENARIO_FAULTS):
    cmd = ("run", "check", "mesh")[i % 3]
    case(f"{cmd}-{cid}", _scenario_case(text, cmd), frags)

# ---- weather files: physical sense, formats, wording, leaks ---------------------------
case("run-fahrenheit-as-celsius", _weather_case(lambda d: _weather_csv(
    d / "f.csv", air=lambda h: 50 + 9 * np.sin(2 * np.pi * (h - 9) / 24), sea=10.0).name),
     ["weather.source[temp_air]", "50.0 degC over a 10.0 degC sea", "(+40.0 K)",
      "look like degrees Fahrenheit"])
case("check-fahrenheit-as-celsius", _weather_case(lambda d: _weather_csv(
    d / "f.csv", air=lambda h: 50 + 9 * np.sin(2 * np.pi * (h - 9) / 24), sea=10.0).name,
    cmd="check"), ["(+40.0 K)", "degrees Fahrenheit"])
case("run-air-40k-above-sea-kelvin", _weather_case(lambda d: _weather_csv(
    d / "k.csv", air=lambda h: 325.0, sea=285.0).name, 'temp_unit = "K"'),
     ["weather.source[temp_air]", "(+40.0 K)", "weather.temp_unit"])
case("run-humidity-as-fraction", _weather_case(lambda d: _weather_csv(
    d / "rh.csv", rh=0.86).name), ["weather.source[relative_humidity]", "never exceeds 0.86 %",
                                   "Multiply the column by 100"])
case("check-humidity-as-fraction", _weather_case(lambda d: _weather_csv(
    d / "rh.csv", rh=0.86).name, cmd="check"), ["never exceeds 0.86 %"])
case("run-humidity-over-100", _weather_case(lambda d: _weather_csv(
    d / "rh.csv", edit=lambda r: [r[0].replace(",75.0,", ",175.0,")] + r[1:]).name),
     ["relative_humidity", "must lie in [0, 100]"])
case("run-semicolons", _weather_case(lambda d: (d / "semi.csv").write_text(
    HEADER.replace(",", ";") + "\n2023-07-15T00:00:00+08:00;24,5;75;4;180;0,3;23,5\n")
    and "semi.csv"), ["weather.source = 'semi.csv'", "separated by semicolons",
                      "comma-separated"])
case("run-ndbc-named-csv", _weather_case(lambda d: (d / "buoy.csv").write_text(
    NDBC.read_text()) and "buoy.csv"),
     ["buoy.csv", "looks like an NDBC", 'weather.format = "ndbc"'])
case("check-tmy3-named-csv", _weather_case(lambda d: (d / "tmy.csv").write_text(
    '725033,"NEW YORK",NY,-5.0,40.783,-73.967,40\nDate (MM/DD/YYYY),Time (HH:MM),ETR\n') and
    "tmy.csv", cmd="check"), ["tmy.csv", "looks like a TMY3 file", 'weather.format = "tmy3"'])
case("run-epw-named-csv", _weather_case(lambda d: (d / "e.csv").write_text(
    "LOCATION,Dalian,LN,CHN,SYNTHETIC,546620,38.91,121.63,8.0,92.0\n") and "e.csv"),
     ["e.csv", "looks like an EPW file", "suffix .epw"])
case("run-ragged-rows", _weather_case(lambda d: _weather_csv(
    d / "r.csv", edit=lambda r: r[:3] + [r[3] + ",1,2"] + r[4:]).name),
     ["weather.source = 'r.csv'", "line 5 has 9 fields, the header 7"],
     absent=("Error tokenizing", "C error"))
case("run-bad-time", _weather_case(lambda d: _weather_csv(
    d / "t.csv", edit=lambda r: r[:2] + ["noon" + r[2][25:]] + r[3:]).name),
     ["weather.source (t.csv) row 4: time = 'noon'", "ISO 8601 instant"],
     absent=("format=", "doesn't match"))
case("run-text-in-number", _weather_case(lambda d: _weather_csv(
    d / "x.csv", edit=lambda r: [r[0].replace(",75.0,", ",humid,")] + r[1:]).name),
     ["row 2: relative_humidity = 'humid'", "must be a number"])
case("run-unknown-column", _weather_case(lambda d: _weather_csv(
    d / "c.csv", header=HEADER.replace("cloud_cover", "clouds")).name),
     ["column 6 = 'clouds'", "unknown column"])
case("run-duplicate-time", _weather_case(lambda d: _weather_csv(
    d / "dup.csv", edit=lambda r: [r[0], r[0]] + r[1:]).name),
     ["2 rows sharing a time", "Remove the repeated rows"])
case("run-date-not-covered", _weather_case(lambda d: _weather_csv(
    d / "short.csv", edit=lambda r: r[:12]).name), ["covers 2023-07-15 00:00", "not the span"])
case("run-epw-needs-sea", _weather_case(lambda d: _epw(d / "w.epw").name),
     ["weather.temp_sea", "is required for EPW files"])


def _secret_link(d):
    secret = d / "shadow"
    secret.write_text(SECRET + "\nmore:secret:lines\n")
    secret.chmod(0)
    (d / "weather.csv").symlink_to(secret)
    return "weather.csv"


case("run-weather-linked-to-protected-file", _weather_case(_secret_link),
     ["weather"], absent=("secret-hash", "root:", "more:secret"))


def _epw_of_another_city(d):
    _epw(d / "sf.epw")
    return "sf.epw"


MIAMI = ('[location]\nlatitude = 25.8\nlongitude = -80.27\ntime_zone = "Etc/GMT+5"\n')
case("run-epw-of-another-city", _weather_case(_epw_of_another_city, "temp_sea = 301.0",
                                              top=MIAMI),
     ["is the record of San Francisco at 37.62 N, -122.40 E (its header)",
      "weather.max_site_distance"])
case("check-epw-of-another-city", _weather_case(_epw_of_another_city, "temp_sea = 301.0",
                                                cmd="check", top=MIAMI),
     ["San Francisco", "km from the site [location] 25.80 N, -80.27 E"])
case("run-max-site-distance-on-csv", _weather_case(lambda d: _weather_csv(d / "a.csv").name,
                                                   "max_site_distance = 10.0"),
     ["weather.max_site_distance = 10.0", "only applies to EPW / TMY2 / TMY3"])
case("run-temp-unit-unknown", _weather_case(lambda d: _weather_csv(d / "a.csv").name,
                                            'temp_unit = "R"'),
     ["weather.temp_unit = 'R'", "'C', 'K', 'F'"])


# ---- the berth --------------------------------------------------------------------------
case("check-ship-over-the-pier", lambda d: (
    (d / "b.toml").write_text('[ship]\nbuiltin = "cargo_ship"\nmooring_position = '
                              "[-5.0, 100.0]\n"), ["check", str(d / "b.toml")])[-1],
     ["ship.mooring_position = [-5.0, 100.0]", "off the water (land", "20 m into its beam",
      "Move the ship 20 m to port: ship.mooring_position = [15, 100]"])

# ---- sweeps ------------------------------------------------------------------------------


def _sweep(text):
    def make(d):
        write_tiny(d)
        (d / "s.toml").write_text(text)
        return ["-q", "sweep", str(d / "s.toml"), "--out", str(d / "out")]
    return make


case("sweep-key-fixed-and-axis", _sweep('base = "tiny.toml"\n[set]\n"ship.heading" = 90\n'
                                        '[axes]\n"ship.heading" = [0, 180]\n'),
     ["sweep.axes.ship.heading = 'ship.heading'", "is also fixed in [set]"])
case("sweep-repeated-value", _sweep('base = "tiny.toml"\n[axes]\n"ship.heading" = [0, 90, 0]\n'),
     ["sweep.axes.ship.heading", "must not repeat a value: entries 0 and 2"])
case("sweep-repeated-group", _sweep('base = "tiny.toml"\n[[axes.site]]\n"ship.heading" = 0\n'
                                    '[[axes.site]]\n"ship.heading" = 0\n'),
     ["sweep.axes.site", "entries 0 and 1 are the same case"])
case("sweep-key-on-two-axes", _sweep('base = "tiny.toml"\n[axes]\n"ship.heading" = [0, 90]\n'
                                     '[[axes.g]]\n"ship.heading" = 180\n"ship.speed" = 1.0\n'
                                     '[[axes.g]]\n"ship.heading" = 270\n"ship.speed" = 2.0\n'),
     ["is also changed by the axis 'ship.heading'", "one grouped axis"])
case("sweep-deeply-nested", _sweep("a = " + "[" * 5000 + "]" * 5000 + "\n"),
     ["sweep = ", "nests arrays or tables too deeply"])
case("sweep-oversized", _sweep("# " + "x" * (2 << 20) + "\n"), ["sweep = ", "1,048,576"])
case("sweep-base-nested", lambda d: (
    (d / "base.toml").write_text("a = " + "[" * 5000 + "]" * 5000 + "\n"),
    (d / "s.toml").write_text('base = "base.toml"\n[axes]\n"ship.heading" = [0]\n'),
    ["-q", "sweep", str(d / "s.toml"), "--out", str(d / "out")])[-1],
     ["sweep.base = ", "nests arrays or tables too deeply"])
case("sweep-missing", lambda d: ["-q", "sweep", str(d / "no.toml"), "--out", str(d / "out")],
     ["must be an existing TOML file"])
case("sweep-unknown-key", _sweep('axis = {"ship.heading" = [0]}\n'),
     ["sweep.axis", "unknown key"])
case("sweep-case-out-of-range", _sweep('base = "tiny.toml"\n[axes]\n"ship.heading" = [400]\n'),
     ["case 0 (ship.heading=400): ship.heading = 400", "must lie in [0, 360) deg"])
case("sweep-workers-zero", lambda d: ["sweep", "x.toml", "--workers", "0"],
     ["--workers must be >= 1"])

# ---- ensembles ---------------------------------------------------------------------------


def _ens(*extra, scenario=None):
    def make(d):
        sc = write_tiny(d, name="my")
        return ["-q", "ensemble", scenario or str(sc), "--serial", "--out",
                str(d / "out"), *extra]
    return make


case("ensemble-seed-negative", _ens("--seed", "-1"), ["--seed = -1", "[0, 4294967295]"])
case("ensemble-seed-too-large", _ens("--seed", str(2 ** 32)), ["--seed = 4294967296"])
case("ensemble-members-one", _ens("--members", "1"), ["--members = 1", ">= 2"])
case("ensemble-members-too-many", _ens("--members", "5000"), ["--members = 5000",
                                                              "at most 1000"])
case("ensemble-members-not-int", _ens("--members", "x"), ["--members: invalid int value: 'x'"])
case("ensemble-scenario-missing", _ens(scenario="nope.toml"), ["nope.toml",
                                                              "must be 'summer', 'winter'"])
case("ensemble-dist-syntax", _ens("--dist", "wind=gauss:0:1"), ["--dist",
                                                                "NAME=uniform:LOWER:UPPER"])
case("ensemble-dist-unknown", _ens("--dist", "humidity=normal:0:5"), ["--dist", "humidity"])
case("ensemble-dist-empty-range", _ens("--dist", "cloud=uniform:0.3:-0.3"),
     ["LOWER < UPPER"])
case("ensemble-dist-sd", _ens("--dist", "air=normal:0:0"), ["standard deviation > 0"])
case("ensemble-season", _ens("--seasons", "autumn"), ["invalid choice: 'autumn'"])

# ---- calibration ---------------------------------------------------------------------------


def _cal(csv, *extra):
    def make(d):
        write_tiny(d, name="my")
        argv = ["-q", "calibrate"]
        if csv is not None:
            (d / "m.csv").write_text(csv)
            argv.append(str(d / "m.csv"))
        return argv + list(extra) + ["--out", str(d / "out")]
    return make


_U = ("--unknown", "weather.wind_speed_offset=-1:1")
_ROW = "case,time,target,temperature_K\n"
case("calibrate-time-12-61", _cal(_ROW + "my.toml,12:61,deck,300\n", *_U),
     ["row 2: time = '12:61'", "minutes and seconds 00-59"])
case("calibrate-time-1-digit-minute", _cal(_ROW + "my.toml,12:5,deck,300\n", *_U),
     ["row 2: time = '12:5'", "HH:MM"])
case("calibrate-time-noon", _cal(_ROW + "my.toml,noon,deck,300\n", *_U), ["row 2: time"])
case("calibrate-celsius-as-kelvin", _cal(_ROW + "my.toml,12:00,deck,31.5\n", *_U),
     ["temperature_K", "temperature_C"])
case("calibrate-bad-part", _cal(_ROW + "my.toml,12:00,funnel,300\n", *_U),
     ["funnel", "must be a part"])
case("calibrate-no-unknown", _cal(_ROW + "my.toml,12:00,deck,300\n"),
     ["--unknown", "at least one unknown"])
case("calibrate-unknown-syntax", _cal(_ROW + "my.toml,12:00,deck,300\n", "--unknown", "x"),
     ["--unknown", "KEY=LOWER:UPPER"])
case("calibrate-unknown-not-numeric", _cal(_ROW + "my.toml,12:00,deck,300\n", "--unknown",
                                           "weather.source=0:1"),
     ["weather.source", "numeric scenario key"])
case("calibrate-no-file", _cal(None, *_U), ["measurement CSV", "--paper"])
case("calibrate-missing-column", _cal("case,time,target\nmy.toml,12:00,deck\n", *_U),
     ["temperature_K", "missing"])

# ---- the detectability calendar ------------------------------------------------------------

case("calendar-of-a-periodic-day", lambda d: (
    write_tiny(d, name="c"), ["-q", "calendar", str(d / "c.toml"), "--out", str(d / "out")])[-1],
     ["weather.day", "must be 'record'"])
case("calendar-unknown-satellite", lambda d: (
    write_tiny(d, name="c", extra='[calendar]\nsatellites = ["landsat5"]\n'),
    ["-q", "calendar", str(d / "c.toml"), "--out", str(d / "out")])[-1],
     ["calendar.satellites[0] = 'landsat5'", "Did you mean 'landsat9'? For another satellite "
      "give its two-line elements: calendar.tle"])

BUOY = ('[location]\nlatitude = 38.46\nlongitude = -74.70\ntime_zone = "Etc/GMT+5"\n'
        '[weather]\nsource = "buoy.txt"\nday = "record"\ndays = {days}\nwind_height = 5.0\n'
        'cloud_cover = 0.5\n')
L8 = ("1 39084U 13008A   25225.93518726  .00000330  00000-0  83304-4 0  9991",
      "2 39084  98.2219 295.6904 0001221  90.8808 269.2530 14.57106224653150")


def _record(days=2, calendar="", tle=None, cmd="calendar", flags=()):
    """The NDBC crop (2013-03-02 … 03-09) as a record from 2013-03-04, a [calendar] and
    optionally a file of two-line elements ``sat.tle``."""
    def make(d):
        (d / "buoy.txt").write_text(NDBC.read_text())
        if tle is not None:
            (d / "sat.tle").write_text(tle)
        sc = write_tiny(d, name="c", season="winter")
        text = sc.read_text().replace("[time]\n", "[time]\ndate = 2013-03-04\n")
        sc.write_text(text.replace("[ship]", BUOY.format(days=days) + "[ship]") +
                      ("[calendar]\n" + calendar if calendar else ""))
        return ["-q", cmd, str(sc), *flags] + (["--out", str(d / "out")]
                                                if cmd != "check" else [])
    return make


_TLE = 'satellites = []\ntle = "sat.tle"\nswath = 185000.0\n'
case("calendar-record-shorter-than-asked", _record(days=10),
     ["weather.days = 10", "buoy.txt covers 5 whole day(s) from time.date 2013-03-04",
      "Set weather.days = 5 or less"])
case("check-record-shorter-than-asked", _record(days=10, cmd="check"),
     ["weather.days = 10", "Set weather.days = 5 or less"])
case("calendar-satellite-without-preset", _record(calendar='satellites = ["ecostress"]\n'),
     ["calendar.satellites[0] = 'ecostress'", "must be one of 'landsat8', 'landsat9'",
      "calendar.tle", "calendar.swath"])
case("calendar-flag-satellite-without-preset", _record(flags=("--satellites", "sentinel3")),
     ["calendar.satellites[0] = 'sentinel3'", "calendar.tle"])
case("calendar-satellites-not-yet-launched", _record(calendar='satellites = ["landsat9"]\n'),
     ["calendar.satellites = ['landsat9']", "none of them flies during the record",
      "landsat9 2021-09-27", "calendar.tle", "calendar.times"])
case("calendar-tle-line-cut", _record(calendar=_TLE, tle=f"LANDSAT 8\n{L8[0][:60]}\n{L8[1]}\n"),
     ["calendar.tle = 'sat.tle'", "line 1 has 60 characters; a two-line element line has 69"])
case("calendar-tle-checksum", _record(calendar=_TLE, tle=f"{L8[0][:-1]}2\n{L8[1]}\n"),
     ["calendar.tle = 'sat.tle'", "line 1 fails its checksum", "copy it again"])
case("calendar-tle-letters-in-a-number", _record(calendar=_TLE, tle=L8[0] + "\n" + (
    L8[1][:52] + "14.571O6224" + L8[1][63:]) + "\n"),
     ["calendar.tle = 'sat.tle'", "line 2 columns 53-63 (mean motion) must be a number"])
case("calendar-tle-not-elements", _record(calendar=_TLE, tle="LANDSAT 8 from 2025\n"),
     ["calendar.tle = 'sat.tle'", "must hold two-line elements"])
case("calendar-tle-decades-from-the-record", _record(calendar=_TLE, tle="\n".join(L8)),
     ["calendar.tle = 'sat.tle'", "holds elements of 2025-08-13, 4,546 days from the record",
      "366 days", "calendar.times"])
case("calendar-year-missing-for-the-dates", _record(calendar="years = [2012, 2013]\n"),
     ["calendar.years[0] = 2012", "needs buoy.txt (weather.source) over 2012-03-04",
      "covers 2013-03-02 18:50", "Drop the year, or give a file that covers its dates "
      "(calendar.year_sources)"])
case("calendar-year-sources-one-short", _record(
    calendar='years = [2012, 2013]\nyear_sources = ["buoy.txt"]\n'),
     ["calendar.year_sources = '1 files'", "one file per year of calendar.years (2)"])
case("calendar-year-source-missing", _record(
    calendar='years = [2012, 2013]\nyear_sources = ["b2012.txt", "buoy.txt"]\n'),
     ["calendar.year_sources[0] = 'b2012.txt'", "must be an existing file"])
case("calendar-years-repeated", _record(calendar="years = [2013, 2013]\n"),
     ["calendar.years = [2013, 2013]", "distinct years in [1950, 2100]"])
case("calendar-tle-without-swath", _record(calendar='tle = "sat.tle"\n', tle="\n".join(L8)),
     ["calendar.swath = None", "is required with calendar.tle"])


def _year_csv(path, edit=None):
    """A year of hourly weather at Dalian (2023, +08:00) in the CSV columns."""
    t = np.arange(365 * 24 + 1)
    air = 285.0 - 273.15 + 10 * np.sin(2 * np.pi * (t / 8760 - 0.3)) + 3 * np.sin(
        2 * np.pi * (t % 24 - 9) / 24)
    stamps = pd.date_range("2023-01-01", periods=len(t), freq="h").strftime("%Y-%m-%dT%H:%M")
    cols = {"temp_air": np.round(air, 2), "wind_speed": np.full(len(t), 4.0)}
    sea = np.round(air.mean() + 1.0, 2)
    if edit:
        edit(stamps, cols)
    rows = [f"{s}:00+08:00,{a},75,{w},180,0.3,{sea}".replace("nan", "")
            for s, a, w in zip(stamps, cols["temp_air"], cols["wind_speed"])]
    path.write_text(HEADER + "\n" + "\n".join(rows) + "\n")
    return path.name


def _gap(stamps, cols, field="temp_air", first="2023-07-15T08:00", hours=10):
    i = int(np.flatnonzero(stamps == first)[0])
    cols[field] = cols[field].astype(float)
    cols[field][i:i + hours] = np.nan


_YEAR = 'day = "record"\ndays = 365\n'
case("calendar-gap-inside-a-year", _weather_case(lambda d: _year_csv(d / "y.csv", _gap),
                                                 _YEAR, cmd="calendar", date="2023-01-01"),
     ["weather.source[temp_air]", "has no valid temp_air from 2023-07-15 07:00 to "
      "2023-07-15 18:00 +08 (11 h), longer than weather.max_gap_hours = 6 h",
      "raise weather.max_gap_hours, or fill the gap"])
case("run-wind-stops-inside-a-year", _weather_case(lambda d: _year_csv(
    d / "y.csv", lambda s, c: _gap(s, c, "wind_speed", "2023-10-01T00:00", 24 * 100)), _YEAR,
    date="2023-01-01"),
     ["weather.source[wind_speed]", "has no valid wind_speed after 2023-09-30 23:00 +08 (its "
      "last valid observation): the span runs 92.0 days longer, to 2024-01-01 00:00",
      "End the span before it (time.date, weather.days)"])

# ---- background from files ------------------------------------------------------------------


@pytest.fixture(scope="module")
def port(tmp_path_factory):
    from imaging.background.synthetic import write_synthetic_port

    return write_synthetic_port(tmp_path_factory.mktemp("port"), "summer", seed=5, size_px=90)


def _bg(case_id):
    def make(d, port):
        import shutil

        src = d / "port"
        shutil.copytree(port.directory, src)
        mtl = src / Path(port.mtl_txt).name
        roi = src / Path(port.roi).name
        dem = src / Path(port.dem).name
        met = src / Path(port.met).name
        out = ["--out", str(d / "out")]
        if case_id == "garbage-dem":
            (d / "dem.tif").write_bytes(bytes(range(256)) * 4)
            return ["-q", "background", "--mtl", str(mtl), "--roi", str(roi), "--dem",
                    str(d / "dem.tif"), "--met", str(met), *out]
        if case_id == "garbage-met":
            (d / "met.nc").write_text("not netcdf")
            return ["-q", "background", "--mtl", str(mtl), "--roi", str(roi), "--dem",
                    str(dem), "--met", str(d / "met.nc"), *out]
        if case_id == "level1-no-water-vapour-flag":
            return ["-q", "background", "--mtl", str(mtl), "--roi", str(roi), *out]
        sc = d / "bg.toml"
        text = f'[background]\nsource = "files"\nmtl = "{mtl}"\nroi = "{roi}"\n'
        if case_id == "dem-without-met-scenario":
            sc.write_text(text + f'dem = "{dem}"\n')
            return ["-q", "background", str(sc), *out]
        if case_id == "level1-no-water-vapour-scenario":
            sc.write_text(text)
            return ["-q", "background", str(sc), *out]
        if case_id == "check-level1-no-water-vapour":
            sc.write_text(text)
            return ["check", str(sc)]
        if case_id == "water-vapour-out-of-range":
            sc.write_text(text + "water_vapour = 9.0\n")
            return ["-q", "background", str(sc), *out]
        if case_id == "garbage-dem-scenario":
            (d / "dem.tif").write_text("not a tiff")
            sc.write_text(text + f'dem = "{d / "dem.tif"}"\nmet = "{met}"\n')
            return ["-q", "background", str(sc), *out]
        raise AssertionError(case_id)
    make.needs_port = True
    return make


case("background-garbage-dem", _bg("garbage-dem"), ["--dem = ", "must be a readable GeoTIFF"])
case("background-garbage-dem-scenario", _bg("garbage-dem-scenario"),
     ["background.dem = ", "must be a readable GeoTIFF"])
case("background-garbage-met", _bg("garbage-met"), ["--met = ", "must be a readable NetCDF"])
case("background-level1-no-water-vapour-flag", _bg("level1-no-water-vapour-flag"),
     ["--water-vapour = None", "column water vapour"], absent=("water_vapour =",))
case("background-level1-no-water-vapour-scenario", _bg("level1-no-water-vapour-scenario"),
     ["background.water_vapour = None", "column water vapour"])
case("check-level1-no-water-vapour", _bg("check-level1-no-water-vapour"),
     ["background.water_vapour = None", "Level-1 scene without a met grid",
      "shipthermal background"])
case("background-dem-without-met-scenario", _bg("dem-without-met-scenario"),
     ["background.dem/background.met", "go together"], absent=("--dem/--met",))
case("background-water-vapour-out-of-range", _bg("water-vapour-out-of-range"),
     ["background.water_vapour = 9.0", "must lie in [0.2, 6] g cm-2"])
case("background-no-roi", lambda d: ["-q", "background", "--mtl", str(d / "x_MTL.txt"),
                                     "--out", str(d / "out")], ["--roi = None", "is required"])
case("background-scenario-builtin", lambda d: (write_tiny(d, name="t"), [
    "-q", "background", str(d / "t.toml"), "--out", str(d / "out")])[-1],
     ["background.source = 'builtin'", "must be 'files'"])

# ---- run directories: image, crossover, report, validate, demo -----------------------------


def _fake_run(d, finished=True, kind="run"):
    """A run folder as shipthermal signs it (tool, kind, the entries it wrote)."""
    r = d / "run"
    r.mkdir()
    entries = ["manifest.json", "scenario.toml"] + (["COMPLETE"] if finished else [])
    (r / "manifest.json").write_text(json.dumps({"tool": "shipthermal", "kind": kind,
                                                 "entries": entries, "cases": {},
                                                 "status": "running"}))
    (r / "scenario.toml").write_text("")
    if finished:
        (r / "COMPLETE").write_text("x")
    return str(r)


case("image-not-a-run", lambda d: ["image", str(d)],
     ["must be a shipthermal run directory (with manifest.json)"])
case("image-unfinished", lambda d: ["image", _fake_run(d, False)],
     ["is not finished (no COMPLETE marker)", "--resume"])
case("image-step", lambda d: ["image", _fake_run(d), "--step-min", "0.5"],
     ["--step-min = 0.5", "must lie in [1, 180] min"])
case("image-no-scenario-copy", lambda d: ["image", _fake_run(d)],
     ["holds no scenario copy"])
case("crossover-not-a-run", lambda d: ["crossover", str(d)],
     ["must be a shipthermal run directory"])
case("crossover-no-imaging", lambda d: ["crossover", _fake_run(d)],
     ["has no imaging results", "shipthermal image"])
case("report-not-a-run", lambda d: ["report", str(d)], ["must be a shipthermal run directory"])
case("validate-into-not-a-run", lambda d: ["validate", "--into", str(d)],
     ["must be a shipthermal run directory"])
case("demo-out-is-a-file", lambda d: ((d / "f.txt").write_text("mine"),
                                      ["demo", "--out", str(d / "f.txt")])[-1],
     ["--out", "must be a folder"])
case("run-out-foreign-folder", lambda d: ((d / "mine").mkdir(),
                                          (d / "mine" / "thesis.tex").write_text("precious"),
                                          ["run", "summer", "--out", str(d / "mine")])[-1],
     ["not a shipthermal run directory", "Choose a new or empty folder"])
case("mesh-out-finished", lambda d: ["mesh", "summer", "--out", _fake_run(d, kind="mesh")],
     ["is a finished run (COMPLETE exists)", "--force"])
case("run-image-custom-band", lambda d: (
    write_tiny(d, name="c", extra='[imaging]\nbands = ["8-12"]\n'),
    ["-q", "run", str(d / "c.toml"), "--image", "--out", str(d / "out")])[-1],
     ["imaging.bands = ['8-12']", "'3-5', '8-14' and the sensor presets' bands"])

# ---- the command line itself ----------------------------------------------------------------
case("cli-unknown-command", lambda d: ["simulate"], ["invalid choice: 'simulate'"])
case("cli-run-without-scenario", lambda d: ["run"],
     ["the following arguments are required: scenario", "shipthermal run --help"])
case("cli-unknown-flag", lambda d: ["check", "--fast", "x.toml"],
     ["unrecognized arguments: --fast"])
case("cli-mesh-unknown-builtin", lambda d: ["mesh", "--builtin", "yacht"],
     ["invalid choice: 'yacht'"])
case("cli-edge-length-not-number", lambda d: ["mesh", "--edge-length", "fine"],
     ["--edge-length: invalid float value: 'fine'"])
case("cli-demo-season", lambda d: ["demo", "--seasons", "autumn"],
     ["invalid choice: 'autumn'"])
case("cli-quiet-and-verbose", lambda d: ["-q", "-v", "schema"], ["not allowed with argument"])
case("cli-background-bounds", lambda d: ["background", "--bounds", "1", "2"],
     ["--bounds: expected 4 arguments"])


# ---------------------------------------------------------------------------------------
# the test
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("make, fragments, opts", CASES)
def test_user_fault(make, fragments, opts, tmp_path, capsys, monkeypatch, request):
    d = tmp_path / "user"
    d.mkdir()
    monkeypatch.chdir(d)
    argv = make(d, request.getfixturevalue("port")) if getattr(make, "needs_port", False) \
        else make(d)
    _check_refusal(d, argv, fragments, capsys, opts.get("absent", ()))


def test_the_catalogue_is_large_and_covers_every_command():
    from shipthermal.app.cli import build_parser

    assert len(CASES) >= 120, len(CASES)
    ids = [c.id for c in CASES]
    assert len(set(ids)) == len(ids)
    commands = set(build_parser()._subparsers._group_actions[0].choices)
    seen = {i.split("-")[0] for i in ids}
    covered = {c for c in commands if c in seen or any(i.startswith(c) for i in ids)}
    # schema takes no input but --compact; its misuse is argparse's (cli-quiet-and-verbose)
    assert commands - covered <= {"schema"}, commands - covered


def test_disk_full_while_writing_a_checkpoint(tmp_path, capsys, monkeypatch):
    """ENOSPC in the middle of the thermal run, while the first checkpoint is written:
    exit 2 naming the checkpoint (not its temporary file), the fresh run folder removed."""
    import shipthermal.simulation as simulation

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    d = tmp_path / "user"
    d.mkdir()
    sc = write_tiny(d, name="tiny")
    monkeypatch.setattr(simulation.np, "savez", full)
    line = _check_refusal(d, ["-q", "run", str(sc), "--out", str(d / "out")],
                          ["checkpoints/tiny.npz", "no space left on the device (ENOSPC)",
                           "Free disk space"], capsys)
    assert ".tmp" not in line


def test_repaired_mesh_is_the_same_in_mesh_and_run(tmp_path, capsys):
    """The messy cargo ship (tests/messy_ship.py) repaired with tetwild: `shipthermal mesh`
    twice writes byte-identical ship files (the repair is computed once and reused)."""
    from messy_ship import DRAUGHT, write_messy_cargo_ship

    d = tmp_path
    write_messy_cargo_ship(d / "messy.stl", inside_out=False)
    (d / "m.toml").write_text(f'[ship.files]\nmesh = "messy.stl"\nunits = "m"\n'
                              f'part_map = "auto"\ndraught = {DRAUGHT}\nclean = true\n'
                              'fix_normals = true\nrepair = "tetwild"\n')
    for out in ("a", "b"):
        assert main(["-q", "mesh", str(d / "m.toml"), "--out", str(d / out)]) == 0, \
            capsys.readouterr().err
    a, b = (d / "a" / "mesh"), (d / "b" / "mesh")
    for name in ("ship.ply", "ship_parts.json"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    rep = json.loads((b / "mesh_report.json").read_text())["read_report"]
    assert rep["repair"]["reused"] is True and rep["outside"]["interior_pieces"] == 1


def test_two_runs_after_a_repair_are_identical(tmp_path, capsys):
    """A box barge with a crack along its deck repaired with tetwild, run twice: the same surface and the same
    surface temperatures to the last bit (the repair comes from the cache the second time;
    the thermal run is seeded)."""
    from shipthermal.app.pipeline import load_history

    d = tmp_path
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    v, f = np.asarray(m.vertices) + [0.0, 0.0, 1.0], np.array(m.faces)
    top = m.face_normals[:, 2] > 0.5                   # the deck lifted 1 mm: a crack
    used = np.unique(f[top])
    remap = np.arange(len(v))
    remap[used] = len(v) + np.arange(len(used))
    f[top] = remap[f[top]]
    v = np.vstack([v, v[used] + [0.0, 0.0, 0.001]])
    trimesh.Trimesh(v, f, process=False).export(d / "open.stl")
    sc = write_tiny(d, name="barge")
    sc.write_text(sc.read_text().replace(
        '[ship]\nbuiltin = "patrol_boat"\nedge_length = 5.6\nmooring_position = [90.0, 30.0]\n',
        '[ship]\nmooring_position = [90.0, 30.0]\n[ship.files]\nmesh = "open.stl"\n'
        'units = "m"\npart_map = "auto"\ndraught = 4.0\nrepair = "tetwild"\n'))
    hist = []
    for out in ("a", "b"):
        assert main(["-q", "run", str(sc), "--out", str(d / out)]) == 0, capsys.readouterr().err
        hist.append(load_history(d / out / "thermal" / "barge" / "history.npz"))
    a, b = hist
    assert a.vertices.tobytes() == b.vertices.tobytes() and a.faces.tobytes() == b.faces.tobytes()
    assert a.face_temperature.tobytes() == b.face_temperature.tobytes()
