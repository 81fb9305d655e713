"""Ship meshes as CAD exports them, made messy by the tests: named parts (OBJ groups, GLB
meshes), rule-based parts, every problem in one message, repairs and their limit.

The reference is always a built-in ship, whose parts, areas and volume are known exactly.
"""

import json

import numpy as np
import pytest
import trimesh

from shipthermal.errors import InputError
from shipthermal.geometry import cargo_ship, frigate
from shipthermal.geometry.cad import assign_parts, diagnose_surface, part_ranges
from shipthermal.geometry.io import ReadShipSettings, read_ship
from shipthermal.geometry.parts import face_areas, main_part


@pytest.fixture(scope="module")
def ship():
    return frigate(2.5)              # 3064 triangles, 7 parts (4 superstructure sub-parts)


def _soup(s):
    """Every triangle its own piece: three fresh vertices per triangle (as STL stores it)."""
    v = s.vertices[s.faces].reshape(-1, 3)
    return v, np.arange(len(v)).reshape(-1, 3)


def _main_areas(u):
    out = {}
    for name, a in u.part_areas().items():
        out[main_part(name)] = out.get(main_part(name), 0.0) + a
    return out


def _assert_same_ship(u, s, rel=1e-5):
    # float32 files (STL, GLB): ~1e-7 relative per coordinate, hence 1e-5 on sums
    for part, a in _main_areas(s).items():
        assert _main_areas(u)[part] == pytest.approx(a, rel=rel), part
    assert u.signed_volume == pytest.approx(s.signed_volume, rel=rel)
    assert u.is_watertight


# ---- named parts ---------------------------------------------------------------------
def test_obj_groups_name_the_parts(ship, tmp_path):
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in ship.vertices]
    for k, name in enumerate(ship.part_names):
        # CAD tools capitalise and number their groups: "Deck.001"
        lines.append(f"g {name.capitalize()}.00{k}")
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in ship.faces[ship.face_part == k]]
    (tmp_path / "ship.obj").write_text("\n".join(lines) + "\n")
    u, rep = read_ship(tmp_path / "ship.obj", units="m")
    assert set(u.part_names) == set(ship.part_names)
    for part, a in ship.part_areas().items():
        assert u.part_areas()[part] == pytest.approx(a, rel=1e-6), part
    assert u.signed_volume == pytest.approx(ship.signed_volume, rel=1e-6)


def test_glb_named_meshes_name_the_parts(ship, tmp_path):
    scene = trimesh.Scene()
    for k, name in enumerate(ship.part_names):
        sel = ship.faces[ship.face_part == k]
        used, inv = np.unique(sel, return_inverse=True)
        scene.add_geometry(trimesh.Trimesh(ship.vertices[used], inv.reshape(-1, 3), process=False),
                           geom_name=name)
    scene.export(tmp_path / "ship.glb")
    u, _ = read_ship(tmp_path / "ship.glb", units="m")
    assert set(u.part_names) == set(ship.part_names)
    for part, a in ship.part_areas().items():
        assert u.part_areas()[part] == pytest.approx(a, rel=1e-5), part


def test_unknown_group_names_are_listed_at_once(ship, tmp_path):
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in ship.vertices]
    for k, name in enumerate(("Shell", "Bridge") + ship.part_names[2:]):
        lines.append(f"g {name}")
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in ship.faces[ship.face_part == k]]
    (tmp_path / "ship.obj").write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match="'Bridge', 'Shell', which are no ship parts"):
        read_ship(tmp_path / "ship.obj", units="m")


# ---- rule-based parts ------------------------------------------------------------------
@pytest.mark.parametrize("build, edge", [(frigate, 1.0), (cargo_ship, 2.0)],
                         ids=["frigate", "cargo_ship"])
def test_rule_based_parts_agree_with_the_built_in_parts(build, edge, tmp_path):
    # The built-in generator knows every triangle's part; the rules see only the surface
    # (an STL soup: no part, no shared vertex). Measured agreement by area: frigate
    # 99.98 % (2 m2 of funnel-foot faces at deck level go to the deck), cargo ship 100 %.
    s = build(edge)
    v, f = _soup(s)
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "ship.stl")
    u, rep = read_ship(tmp_path / "ship.stl", units="m", part_map="auto",
                       settings=ReadShipSettings(draught=s.draught))
    assert u.n_faces == s.n_faces                   # same triangles in the same order
    truth = np.array([main_part(s.part_names[k]) for k in s.face_part])
    got = np.array([main_part(u.part_names[k]) for k in u.face_part])
    a = face_areas(s.vertices, s.faces)
    assert a[truth == got].sum() / a.sum() >= 0.999
    # the JSON is a part map of the file as it is: read back, the same parts
    auto = rep["auto_parts"]
    assert auto["faces_as_in_file"]
    (tmp_path / "auto.json").write_text(json.dumps(auto))
    w, _ = read_ship(tmp_path / "ship.stl", units="m", part_map=tmp_path / "auto.json",
                     settings=ReadShipSettings(draught=s.draught))
    np.testing.assert_array_equal([w.part_names[k] for k in w.face_part],
                                  [u.part_names[k] for k in u.face_part])


def test_part_ranges_round_trip():
    lab = np.array([0, 0, 2, 2, 1, 0, 0, 2])
    r = part_ranges(lab, ("hull", "deck", "superstructure"))
    assert r == {"hull": [[0, 2], [5, 7]], "deck": [[4, 5]], "superstructure": [[2, 4], [7, 8]]}


def test_rules_do_not_care_about_inverted_normals(ship):
    lab, names, _ = assign_parts(ship.vertices, ship.faces)
    lab2, _, _ = assign_parts(ship.vertices, ship.faces[:, ::-1])
    np.testing.assert_array_equal(lab, lab2)


# ---- messy exports, every problem at once -----------------------------------------------
def test_triangle_soup_of_thousands_of_pieces_reads_as_the_ship(ship, tmp_path):
    v, f = _soup(ship)
    assert len(v) == 3 * ship.n_faces                 # 3064 separate pieces
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "soup.stl")
    u, rep = read_ship(tmp_path / "soup.stl", units="m", part_map="auto",
                       settings=ReadShipSettings(draught=ship.draught))
    assert rep["problems_found"] == [] and rep["repairs"] == []
    _assert_same_ship(u, ship)


def test_every_problem_in_one_message(ship, tmp_path):
    # millimetres + duplicate faces + an inverted patch + zero-area triangles
    f = ship.faces.copy()
    patch = np.flatnonzero(ship.face_centroids[:, 0] > 40.0)
    f[patch] = f[patch, ::-1]
    dup = f[:50]
    zero = np.array([[0, 0, 1]] * 3)
    v = ship.vertices * 1000.0
    trimesh.Trimesh(v, np.vstack([f, dup, zero]), process=False).export(tmp_path / "m.stl")
    with pytest.raises(InputError) as exc:
        read_ship(tmp_path / "m.stl", units="m", part_map="auto",
                  settings=ReadShipSettings(draught=ship.draught * 1e3))
    msg = str(exc.value)
    for frag in ("has 4 problems", 'ship.files.units = "mm"', "ship.files.check_scale = false",
                 # 50 copies + the three identical zero-area triangles twice over
                 "3 zero-area triangles", "52 duplicate triangles", "ship.files.clean = true",
                 "inconsistent winding", "ship.files.fix_normals = true"):
        assert frag in msg, frag
    assert "\n" not in msg
    # the keys it names fix it: the same ship comes back, every repair reported
    u, rep = read_ship(tmp_path / "m.stl", units="mm", part_map="auto",
                       settings=ReadShipSettings(draught=ship.draught, clean=True,
                                                 fix_normals=True))
    _assert_same_ship(u, ship)
    assert rep["removed_duplicate"] == 50 and rep["removed_degenerate"] == 3
    assert rep["flipped_faces"] == len(patch)
    assert any(line.startswith("clean: 50 duplicate and 3 zero-area") for line in rep["repairs"])
    assert any(line.startswith(f"fix_normals: {len(patch)} triangles") for line in rep["repairs"])


def test_needles_at_t_junctions_are_flipped_without_changing_the_surface(tmp_path):
    # A T-junction as CAD leaves it: vertex m in the middle of edge ab; the triangle on
    # one side is split at m, the one on the other side is not, and the zero-area needle
    # (a, b, m) closes the surface. clean flips the needle into its neighbour: closed,
    # the same area and volume (box: 4640 m2, 12000 m3), nothing dropped.
    box = trimesh.creation.box((100.0, 12.0, 10.0))
    v, f = np.array(box.vertices) + [0.0, 0.0, 1.0], np.array(box.faces)
    a, b, c = f[0]
    m = len(v)
    v = np.vstack([v, 0.5 * (v[a] + v[b])])
    f = np.vstack([f[1:], [[a, m, c], [m, b, c], [a, b, m]]])
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "needle.stl")
    with pytest.raises(InputError, match=r"has 1 problem: \(1\) 1 zero-area triangles .*clean = true"):
        read_ship(tmp_path / "needle.stl", units="m", part_map="auto",
                  settings=ReadShipSettings(draught=4.0))
    u, rep = read_ship(tmp_path / "needle.stl", units="m", part_map="auto",
                       settings=ReadShipSettings(draught=4.0, clean=True))
    assert rep["needles_flipped"] == 1 and rep["removed_degenerate"] == 0
    assert u.is_watertight
    assert u.total_area == pytest.approx(4640.0, rel=1e-12)
    assert u.signed_volume == pytest.approx(12000.0, rel=1e-12)


def test_nonmanifold_edges_are_named_with_their_keys():
    a = trimesh.creation.box((20.0, 4.0, 4.0))
    b = trimesh.creation.box((20.0, 4.0, 4.0))
    b.apply_translation([20.0, 4.0, 0.0])             # touches a along one edge only
    m = trimesh.util.concatenate([a, b])
    m.merge_vertices()
    probs = diagnose_surface(np.array(m.vertices), np.array(m.faces), check_scale=False)
    (p,) = [p for p in probs if p.kind == "nonmanifold"]
    assert "edges shared by more than two triangles" in p.text and "ship.files.repair" in p.fix


def test_union_repair_of_overlapping_pieces_matches_hand_figures(tmp_path):
    # hull box 100 x 12 x 10 m, deckhouse 20 x 8 x 8 m sunk 2 m into it; by hand:
    # united area 4640 - 160 + 336 + 160 = 4976 m2, volume 12000 + 1280 - 320 = 12960 m3
    hull = trimesh.creation.box((100.0, 12.0, 10.0))
    hull.apply_translation([0.0, 0.0, 1.0])
    house = trimesh.creation.box((20.0, 8.0, 8.0))
    house.apply_translation([-20.0, 0.0, 8.0])
    trimesh.util.concatenate([hull, house]).export(tmp_path / "two.stl")
    with pytest.raises(InputError, match="max_repair_change"):
        read_ship(tmp_path / "two.stl", units="m", part_map="auto",
                  settings=ReadShipSettings(draught=4.0, repair="union"))
    u, rep = read_ship(tmp_path / "two.stl", units="m", part_map="auto",
                       settings=ReadShipSettings(draught=4.0, repair="union",
                                                 max_repair_change=0.1))
    assert u.total_area == pytest.approx(4976.0, rel=1e-9)
    assert u.signed_volume == pytest.approx(12960.0, rel=1e-9)
    assert rep["repair"]["pieces"] == 2
    assert rep["repairs"][0].startswith("repair (union")
    # the rules: deck at z = 6 m (freeboard 6 m), the deckhouse stands 6 m above it:
    # superstructure = its walls and roof, deck = the hull top less its footprint
    areas = u.part_areas()
    assert areas["superstructure"] == pytest.approx(336.0 + 160.0, rel=1e-9)
    assert areas["deck"] == pytest.approx(1200.0 - 160.0, rel=1e-9)


def test_scenario_validate_opens_the_mesh(ship, tmp_path, capsys):
    # a scenario whose mesh file exists but is a millimetre export with duplicates:
    # `shipthermal check` opens it and lists both problems
    from shipthermal.app.cli import main

    v, f = _soup(ship)
    trimesh.Trimesh(v * 1000.0, np.vstack([f, f[:7]]), process=False).export(tmp_path / "s.stl")
    (tmp_path / "sc.toml").write_text('[ship.files]\nmesh = "s.stl"\nunits = "m"\n'
                                      'part_map = "auto"\n')      # the file's z = 0 is the waterline
    assert main(["check", str(tmp_path / "sc.toml")]) == 2
    err = capsys.readouterr().err
    assert "has 2 problems" in err and 'units = "mm"' in err and "7 duplicate" in err
    (tmp_path / "sc.toml").write_text('[ship.files]\nmesh = "s.stl"\nunits = "mm"\n'
                                      'part_map = "auto"\nclean = true\n')
    assert main(["check", str(tmp_path / "sc.toml")]) == 0


def test_soup_of_overlapping_solids_is_united_fast(tmp_path, monkeypatch):
    # The frigate as a CAD tool exports an assembly: hull and seven deckhouse solids,
    # overlapping and stacked (touching face to face), never united, every triangle its
    # own piece. The union repair gives the generator's surface back (its own union of
    # the same solids; float32 STL, hence 1e-5), in seconds where a tetrahedral remesh
    # takes minutes.
    import shipthermal.geometry.ship as gs
    import shipthermal.geometry.ship.build as gb

    solids = {}
    real = gb.unite
    monkeypatch.setattr(gb, "unite", lambda m: (solids.setdefault("m", m), real(m))[1])
    s = gs.frigate(2.5)
    off, vs, fs = 0, [], []
    for v, f in solids["m"]:
        vs.append(v)
        fs.append(f + off)
        off += len(v)
    v, f = np.concatenate(vs), np.concatenate(fs)
    trimesh.Trimesh(v[f].reshape(-1, 3), np.arange(3 * len(f)).reshape(-1, 3),
                    process=False).export(tmp_path / "assembly.stl")
    with pytest.raises(InputError, match="separate pieces that overlap.*repair = \"union\""):
        read_ship(tmp_path / "assembly.stl", units="m", part_map="auto",
                  settings=ReadShipSettings(draught=s.draught, clean=True))
    u, rep = read_ship(tmp_path / "assembly.stl", units="m", part_map="auto",
                       settings=ReadShipSettings(draught=s.draught, repair="union",
                                                 max_repair_change=0.5))
    assert rep["repair"]["pieces"] >= len(solids["m"])
    assert u.is_watertight
    assert u.total_area == pytest.approx(s.total_area, rel=1e-5)
    assert u.signed_volume == pytest.approx(s.signed_volume, rel=1e-5)
    truth, got = _main_areas(s), _main_areas(u)
    for part in ("hull_wetted", "hull_dry", "superstructure"):
        assert got[part] == pytest.approx(truth[part], rel=0.01), part


def test_mesh_command_writes_the_part_picture_and_an_editable_json(tmp_path, capsys):
    # hull box with a deckhouse, one unlabelled STL: `shipthermal mesh` assigns parts by
    # rules, prints it, writes the pictures and the JSON; the JSON as part_map reproduces
    # the parts
    from shipthermal.app.cli import main

    hull = trimesh.creation.box((100.0, 12.0, 10.0))
    hull.apply_translation([0.0, 0.0, 1.0])
    house = trimesh.creation.box((20.0, 8.0, 6.0))
    house.apply_translation([-20.0, 0.0, 9.0])              # stands on the deck (z = 6)
    united = hull.union(house, engine="manifold")
    united.export(tmp_path / "barge.stl")
    (tmp_path / "a.toml").write_text('[ship.files]\nmesh = "barge.stl"\nunits = "m"\n'
                                     'part_map = "auto"\ndraught = 4.0\n')
    assert main(["mesh", str(tmp_path / "a.toml"), "--out", str(tmp_path / "m")]) == 0
    err = capsys.readouterr().err
    assert "parts assigned by rules" in err and "auto_parts.json" in err
    out = tmp_path / "m" / "mesh"
    assert (out / "auto_parts_iso.png").stat().st_size > 10_000
    assert (out / "auto_parts_side.png").stat().st_size > 10_000
    auto = json.loads((out / "auto_parts.json").read_text())
    assert set(auto["parts"]) == {"hull", "deck", "superstructure"}
    u, _ = read_ship(tmp_path / "barge.stl", units="m", part_map=out / "auto_parts.json",
                     settings=ReadShipSettings(draught=4.0))
    areas = u.part_areas()
    # by hand: deck 1200 - 160 = 1040 m2; deckhouse walls 2 (20 + 8) 6 + roof 160 = 496 m2
    assert areas["deck"] == pytest.approx(1040.0, rel=1e-9)
    assert areas["superstructure"] == pytest.approx(496.0, rel=1e-9)
    assert areas["hull_wetted"] + areas["hull_dry"] == pytest.approx(4640.0 - 1200.0, rel=1e-9)


def test_repairs_are_printed_on_the_console(tmp_path, capsys):
    from shipthermal.app.cli import main

    hull = trimesh.creation.box((100.0, 12.0, 10.0))
    hull.apply_translation([0.0, 0.0, 1.0])
    house = trimesh.creation.box((20.0, 8.0, 8.0))
    house.apply_translation([-20.0, 0.0, 8.0])
    trimesh.util.concatenate([hull, house]).export(tmp_path / "two.stl")
    (tmp_path / "a.toml").write_text('[ship.files]\nmesh = "two.stl"\nunits = "m"\n'
                                     'part_map = "auto"\ndraught = 4.0\nrepair = "union"\n'
                                     'max_repair_change = 0.1\n')
    assert main(["mesh", str(tmp_path / "a.toml"), "--out", str(tmp_path / "m")]) == 0
    err = capsys.readouterr().err
    # the hand figures of test_union_repair_of_overlapping_pieces_matches_hand_figures
    assert "mesh: repair (union" in err
    assert "area 5408 -> 4976 m2 (-7.99 %), volume 13280 -> 12960 m3 (-2.41 %)" in err
