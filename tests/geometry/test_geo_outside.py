"""The outside of a ship surface by ray casting, and the mesh checks that follow from it.

Evidence:

* the built-in ships (consistently outward by construction) have no interior, inside-out
  or stray triangle; turned inside-out they are one inside-out piece;
* a messy export of the cargo ship (tests/messy_ship.py: a crack, a flipped deck patch,
  an inside-out closed box inside the hull holding 36 % of the area, an inside-out
  container on deck) read as users read it: the interior shell is removed, the container
  turned, and the rule-based deck lands on the real deck (its area within 1 % of the
  built-in deck's) instead of the box;
* a repaired surface is computed once: two reads give byte-identical meshes;
* parts that make no sense (a deck facing down, a hull without a wetted part) are refused,
  a superstructure below the deck and a mesh of slivers warned about with the key that
  fixes it.
"""

import json

import numpy as np
import pytest
import trimesh
from messy_ship import DRAUGHT, messy_cargo_ship, write_messy_cargo_ship

from shipthermal.errors import InputError
from shipthermal.geometry import ReadShipSettings, cargo_ship, frigate, patrol_boat, read_ship
from shipthermal.geometry.cad import assign_parts
from shipthermal.geometry.outside import (classify_pieces, hemisphere_fan, part_sense,
                                          sliver_share)
from shipthermal.geometry.parts import face_areas, signed_volume
from shipthermal.geometry.surface_ops import fix_winding


def _deck_area(ship):
    a = face_areas(ship.vertices, ship.faces)
    return float(a[ship.face_part == ship.part_names.index("deck")].sum())


def test_fan_is_even_over_the_hemisphere():
    d = hemisphere_fan(512)
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0) and (d[:, 2] > 0).all()
    # equal solid angle per direction: the mean height of a uniform hemisphere is 1/2, and
    # a cone of half-angle 45 deg holds 1 - cos 45 = 29.3 % of it (midpoint rule: exact to
    # 1/n)
    assert abs(d[:, 2].mean() - 0.5) < 1e-12
    assert abs(np.mean(d[:, 2] > np.cos(np.pi / 4)) - (1 - np.cos(np.pi / 4))) < 1.0 / 512


@pytest.mark.parametrize("build", [frigate, patrol_boat, cargo_ship])
def test_builtin_ships_face_out_everywhere(build):
    ship = build(edge_length=build().length / 40.0)
    rep = classify_pieces(ship.vertices, ship.faces)
    assert rep.interior_pieces == () and rep.inverted_pieces == ()
    assert rep.stray_inward == 0 and rep.stray_enclosed == 0
    turned = classify_pieces(ship.vertices, ship.faces[:, ::-1])
    assert turned.inverted_pieces == (0,) and turned.inward.all()


def test_messy_export_without_repair(tmp_path):
    """Inner box and inside-out container found by the rays; a flipped patch by winding."""
    # what the winding and volume checks let through: every piece consistently wound,
    # the total volume positive
    v, f, info, ref = messy_cargo_ship(crack=False, flipped_patch=False)
    path = tmp_path / "messy.stl"
    trimesh.Trimesh(v, f, process=False).export(path)
    with pytest.raises(InputError, match=r"1 separate piece\(s\) \(48 triangles.*inside-out.*"
                                         r"ship.files.fix_normals = true"):
        read_ship(path, units="m", part_map="auto", settings=ReadShipSettings(draught=DRAUGHT,
                                                                              clean=True))
    v, f, info, ref = messy_cargo_ship(crack=False)
    trimesh.Trimesh(v, f, process=False).export(path)
    ship, rep = read_ship(path, units="m", part_map="auto",
                          settings=ReadShipSettings(draught=DRAUGHT, clean=True, fix_normals=True))
    out = rep["outside"]
    assert out["interior_pieces"] == 1 and out["interior_faces_removed"] == info["inner_box_faces"]
    assert out["interior_area_removed_m2"] == pytest.approx(info["inner_box_area"], rel=1e-9)
    assert out["inverted_pieces"] == 1 and out["inverted_faces_turned"] == info["inside_out_faces"]
    assert any("interior shells removed" in line for line in rep["repairs"])
    # the rule-based deck is the real deck: the built-in's deck area (the container's top,
    # 30 m2, lies above the deck's tolerance band and goes to the superstructure)
    assert _deck_area(ship) == pytest.approx(_deck_area(ref), rel=0.01)
    assert ship.n_faces == ref.n_faces + info["inside_out_faces"]


def test_messy_export_repaired_once_and_identically(tmp_path, monkeypatch):
    """The tetwild repair of the messy export: its cavity (the inside-out box) removed,
    the deck on the deck, and the same mesh on every read (the cache)."""
    monkeypatch.setenv("SHIPTHERMAL_CACHE", str(tmp_path / "cache"))   # empty: a first repair
    path = tmp_path / "messy.stl"
    write_messy_cargo_ship(path, inside_out=False)
    kw = dict(units="m", part_map="auto", settings=ReadShipSettings(
        draught=DRAUGHT, clean=True, fix_normals=True, repair="tetwild"))
    ship, rep = read_ship(path, **kw)
    assert rep["repair"]["reused"] is False and rep["repair"]["cache"]
    out = rep["outside"]
    assert out["interior_pieces"] == 1
    # the cavity's walls: the box's area, remeshed (tetwild's surface tolerance, 1e-3 of
    # the bounding-box diagonal, moves its faces by < 0.2 m on a 24 x 12.5 m section)
    assert out["interior_area_removed_m2"] == pytest.approx(9360.0, rel=0.02)
    ref = cargo_ship(edge_length=4.0)
    # the remesh moves the part borders: triangles straddling the deck edge and the
    # deckhouse foot (about 450 m of border) go either way, up to half a tetwild triangle
    # (~0.5 m) wide: 225 m2, 5 % of the deck
    assert _deck_area(ship) == pytest.approx(_deck_area(ref), rel=0.05)
    deck = ship.face_part == ship.part_names.index("deck")
    a = face_areas(ship.vertices, ship.faces)
    assert a[deck & (ship.face_normals[:, 2] > 0.9)].sum() > 0.99 * a[deck].sum()   # sky
    assert abs(np.median(ship.face_centroids[deck, 2]) - ref.freeboard) < 0.1
    again, rep2 = read_ship(path, **kw)
    assert rep2["repair"]["reused"] is True
    assert again.vertices.tobytes() == ship.vertices.tobytes()
    assert again.faces.tobytes() == ship.faces.tobytes()
    assert again.face_part.tobytes() == ship.face_part.tobytes()
    # without the ray check, the rules would have put most of the deck on the cavity's
    # ceiling (the lowest upward faces above the waterline; 75-92 % over our repairs)
    cached = np.load(rep["repair"]["cache"])
    v, f = cached["vertices"], cached["faces"]
    v = v - [0.0, 0.0, DRAUGHT]
    lab, names, _ = assign_parts(v, f)
    a = face_areas(v, f)
    inner = classify_pieces(v, f).interior_faces
    deck_inner = a[(lab == names.index("deck")) & inner].sum() / a[lab == names.index("deck")].sum()
    assert deck_inner > 0.5


def _barge(nx=200):
    """A closed 100 x 12 x 10 m barge whose long sides are strips of needles (0.5 m by
    10-12 m triangles: smallest angle 2.4-2.9 deg)."""
    x = np.linspace(-50.0, 50.0, nx + 1)
    ring = [(-6.0, -4.0), (6.0, -4.0), (6.0, 6.0), (-6.0, 6.0)]
    v = np.array([[xi, y, z] for (y, z) in ring for xi in x])
    n = nx + 1
    faces = []
    for k in range(4):
        a, b = k * n, ((k + 1) % 4) * n
        for i in range(nx):
            faces += [[a + i, a + i + 1, b + i + 1], [a + i, b + i + 1, b + i]]
    faces += [[0, 3 * n, 2 * n], [0, 2 * n, n],
              [nx, nx + n, nx + 2 * n], [nx, nx + 2 * n, nx + 3 * n]]
    f, _ = fix_winding(np.array(faces))              # consistent
    if signed_volume(v, f) < 0:                      # and outward
        f = f[:, ::-1]
    return v, f


def test_sliver_share_of_a_needle_barge():
    v, f = _barge()
    share, edge = sliver_share(v, f)
    assert share == pytest.approx(1600 / 1604)
    # equilateral triangles of the same count and area: 4640 m2 / 1604 = 2.89 m2 each
    assert edge == pytest.approx(np.sqrt(4 * 4640.0 / 1604 / np.sqrt(3)), rel=1e-9)
    cube = trimesh.creation.box((10.0, 10.0, 10.0))          # right isosceles: 45 deg
    assert sliver_share(cube.vertices, cube.faces)[0] == 0.0


def test_sliver_mesh_warned_with_the_key(tmp_path):
    from shipthermal.app.scenario import load_scenario

    v, f = _barge()
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "needles.stl")
    sc = load_scenario({"ship": {"files": {"mesh": "needles.stl", "units": "m",
                                           "part_map": "auto", "draught": 2.0}}},
                       base_dir=tmp_path)
    _, rep = sc.ship.read_files()
    warn = [w for w in rep["warnings"] if "slivers" in w]
    # the waterline cut splits needles into a needle and two wider triangles: 75 % left
    assert rep["sliver_share"] == pytest.approx(0.75, abs=0.01)
    assert warn and "75 % of the triangles are slivers" in warn[0]
    assert "Set ship.edge_length (e.g. 1.8 m" in warn[0]
    assert any(line.startswith("warning:") and "slivers" in line for line in rep["repairs"])


def test_parts_that_make_no_sense():
    box = trimesh.creation.box((100.0, 12.0, 10.0))
    v = np.asarray(box.vertices) + [0.0, 0.0, 1.0]            # keel at -4, deck at +6
    f = np.asarray(box.faces)
    n = box.face_normals
    up, down = n[:, 2] > 0.5, n[:, 2] < -0.5
    side = ~up & ~down
    names = ("hull_wetted", "hull_dry", "deck", "superstructure")
    good = np.where(up, 2, 0)
    assert part_sense(v, f, good, names, 6.0) == ([], [])
    sides_as_deck = np.where(side, 2, 0)
    ref, _ = part_sense(v, f, sides_as_deck, names, 6.0)
    assert ref and "0 % of the deck's area faces the sky" in ref[0]
    dry_only = np.where(up, 2, 1)
    ref, _ = part_sense(v, f, dry_only, names, 6.0)
    assert ref and "wetted hull" in ref[0]
    low_sup = np.where(up, 3, 0)
    ref, warn = part_sense(v, f, low_sup, ("hull_wetted", "hull_dry", "deck", "superstructure"),
                           20.0)
    assert warn and "below the deck" in warn[0]


def test_read_ship_refuses_a_deck_facing_down(tmp_path):
    box = trimesh.creation.box((100.0, 12.0, 10.0))
    box.apply_translation([0.0, 0.0, 1.0])
    down = box.face_normals[:, 2] < -0.5
    f = np.vstack([box.faces[~down], box.faces[down]])
    trimesh.Trimesh(box.vertices, f, process=False).export(tmp_path / "b.stl")
    (tmp_path / "p.json").write_text(json.dumps({"hull": [[0, 10]], "deck": [[10, 12]]}))
    with pytest.raises(InputError, match=r"ship.files.part_map .*0 % of the deck's area faces "
                                         r"the sky .*100 % faces down"):
        read_ship(tmp_path / "b.stl", units="m", part_map=tmp_path / "p.json",
                  settings=ReadShipSettings(draught=4.0))


def test_edge_length_that_would_exhaust_memory(tmp_path):
    from shipthermal.app.scenario import ScenarioError, load_scenario

    with pytest.raises(ScenarioError, match=r"ship.edge_length = 0.02: would give about "
                                            r"41,458,368 surface triangles"):
        load_scenario({"ship": {"edge_length": 0.02}})
    box = trimesh.creation.box((100.0, 12.0, 10.0))
    box.apply_translation([0.0, 0.0, 1.0])
    box.export(tmp_path / "b.stl")
    sc = load_scenario({"ship": {"edge_length": 0.001, "files": {
        "mesh": "b.stl", "units": "m", "part_map": "auto", "draught": 4.0}}}, base_dir=tmp_path)
    # 4640 m2 at 1 mm: 1.07e10 triangles; refused before any remeshing
    with pytest.raises(InputError, match=r"ship.edge_length = 0.001: would give about "
                                         r"10,715,...,... surface triangles.*>= 0.074 m"):
        sc.ship()
