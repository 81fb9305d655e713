"""User meshes: round trips, part maps, and each kind of bad mesh gets its own answer."""

import json

import numpy as np
import pytest
import trimesh

from shipthermal.errors import InputError
from shipthermal.geometry import frigate
from shipthermal.geometry.io import (ReadShipSettings, check_surface, read_part_map, read_ship,
                                    write_ship)


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    d = tmp_path_factory.mktemp("ships")
    s = frigate(2.0)
    write_ship(s, d)
    return s, d


def _box(tmp_path, name="box.stl", scale=1.0, drop=0, flip=False, extra=None):
    """A 100 m x 12 m x 10 m box barge, keel at z = -4 (so z = 0 is a waterline)."""
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    v = np.array(m.vertices) + [0.0, 0.0, 1.0]
    f = np.array(m.faces)
    top = np.flatnonzero(m.face_normals[:, 2] > 0.5)
    if drop:
        f = np.delete(f, top[:drop], axis=0)
    if flip:
        f = f[:, ::-1]
    if extra is not None:
        f = np.vstack([f, extra(f)])
    path = tmp_path / name
    trimesh.Trimesh(v * scale, f, process=False).export(path)
    return path, len(f)


def test_roundtrip_ply_with_json_part_map(written):
    s, d = written
    u, rep = read_ship(d / "frigate.ply", units="m", part_map=d / "frigate_parts.json")
    assert u.part_names == s.part_names
    # PLY stores float32 coordinates: relative area error ~1e-7.
    for name, a in s.part_areas().items():
        assert u.part_areas()[name] == pytest.approx(a, rel=1e-5)
    assert rep["flipped_faces"] == 0 and rep["removed_degenerate"] == 0
    meta = json.loads((d / "frigate_parts.json").read_text())
    assert meta["units"] == "m" and set(meta["parts"]) == set(s.part_names)


def test_roundtrip_one_stl_per_part(written):
    s, d = written
    files = {n: d / "frigate_parts" / f"{n}.stl" for n in s.part_names}
    u, _ = read_ship(files, units="m")
    assert u.is_watertight and u.signed_volume > 0
    assert u.total_area == pytest.approx(s.total_area, rel=1e-5)
    assert u.n_faces == s.n_faces


def test_hull_part_is_split_at_given_draught(tmp_path):
    path, n = _box(tmp_path)
    # Keel at z = -4 in the file: draught 3 puts the waterline at z = -1.
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, n]]},
                       settings=ReadShipSettings(draught=3.0))
    areas = u.part_areas()
    # Box 100 x 12, wetted to 3 m: bottom 1200 + sides 2*(100+12)*3 = 1872 m2 exactly.
    assert areas["hull_wetted"] == pytest.approx(1200 + 2 * 112 * 3.0, rel=1e-12)
    assert areas["hull_wetted"] + areas["hull_dry"] == pytest.approx(1200 * 2 + 2 * 112 * 10, rel=1e-12)
    assert rep["translation"][2] == pytest.approx(1.0)
    assert u.vertices[u.faces[u.part_mask("hull_wetted")], 2].max() <= 0.0


def test_open_box_is_rejected(tmp_path):
    path, n = _box(tmp_path, drop=2)
    with pytest.raises(InputError, match="open edges"):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})


def test_open_box_repaired_with_tetwild_reports_change(tmp_path):
    """fTetWild is not deterministic, even on one thread (5 runs on this box: 259-273
    vertices; one run in many closes the lid with folds, +119 % area instead of +35 %). So
    the test asserts what every run must give: a refusal naming the change and the value
    that accepts it, then a closed, outward, box-sized solid whose report is consistent."""
    import re

    path, n = _box(tmp_path, drop=2)
    with pytest.raises(InputError, match=r"tetwild repair changed the area by \+\d+\.\d\d %") \
            as info:
        read_ship(path, units="m", part_map={"hull": [[0, n]]},
                  settings=ReadShipSettings(repair="tetwild"))
    accept = float(re.search(r"max_repair_change = ([\d.]+) or more", str(info.value)).group(1))
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, n]]},
                       settings=ReadShipSettings(repair="tetwild",
                                                 max_repair_change=max(accept, 5.0)))
    r = rep["repair"]
    assert rep["open_edges"] == 0 and u.signed_volume > 0
    # the missing 100 x 12 m lid is closed: more area than the open 3440 m2, and the solid
    # holds about the closed box's 12 000 m3 (not a collapsed or inflated shell)
    assert r["area_before"] == pytest.approx(3440.0, rel=1e-12)
    assert r["area_after"] > 3440.0 + 0.9 * 1200.0
    assert r["area_change"] == pytest.approx((r["area_after"] - 3440.0) / 3440.0, rel=1e-12)
    assert 0.8 * 12000.0 < r["volume_after"] < 1.2 * 12000.0
    assert u.total_area == pytest.approx(r["area_after"], rel=1e-9)


def test_inverted_normals_error_and_reported_fix(tmp_path):
    path, n = _box(tmp_path, flip=True)
    with pytest.raises(InputError, match="normals point into the ship"):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, n]]},
                       settings=ReadShipSettings(fix_normals=True))
    assert rep["flipped_faces"] == n
    assert u.signed_volume == pytest.approx(12000.0, rel=1e-12)


def test_zero_area_face_error_and_clean(tmp_path):
    # A triangle with a repeated vertex (zero area) appended to the closed box.
    path, n = _box(tmp_path, extra=lambda f: np.array([[f[0, 0], f[0, 1], f[0, 1]]]))
    with pytest.raises(InputError, match="zero-area"):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, n]]},
                       settings=ReadShipSettings(clean=True))
    assert rep["removed_degenerate"] == 1 and u.n_faces >= 12


def test_duplicate_face_error_and_clean(tmp_path):
    path, n = _box(tmp_path, extra=lambda f: f[:1])
    with pytest.raises(InputError, match="duplicate"):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})
    _, rep = read_ship(path, units="m", part_map={"hull": [[0, n]]},
                       settings=ReadShipSettings(clean=True))
    assert rep["removed_duplicate"] == 1


def test_mm_declared_as_m_gets_a_question(tmp_path):
    path, n = _box(tmp_path, scale=1000.0)
    with pytest.raises(InputError, match='ship.files.units = "mm" \\(it looks like millimetres\\)'):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})
    u, _ = read_ship(path, units="mm", part_map={"hull": [[0, n]]})
    assert u.length == pytest.approx(100.0)


def test_centimetre_ship_and_wrong_axes(tmp_path):
    path, n = _box(tmp_path, scale=1e-4)              # a 1 cm "ship"
    with pytest.raises(InputError, match="outside the plausible"):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})
    m = trimesh.creation.box((12.0, 100.0, 10.0))
    p2 = tmp_path / "sideways.stl"
    m.export(p2)
    with pytest.raises(InputError, match="longest dimension must lie along x"):
        read_ship(p2, units="m", part_map={"hull": [[0, 12]]})


def test_units_must_be_declared(tmp_path):
    path, n = _box(tmp_path)
    with pytest.raises(InputError, match="must be declared"):
        read_ship(path, units=None, part_map={"hull": [[0, n]]})


def test_part_map_must_cover_each_face_once():
    with pytest.raises(InputError, match="overlaps"):
        read_part_map({"hull": [[0, 8]], "deck": [[6, 12]]}, 12)
    with pytest.raises(InputError, match="uncovered: face 10"):
        read_part_map({"hull": [[0, 8]], "deck": [[8, 10]]}, 12)
    labels, names = read_part_map(np.array(["deck", "hull", "hull"]), 3)
    assert names == ("deck", "hull") and labels.tolist() == [0, 1, 1]



def test_unknown_part_name_in_a_part_map(tmp_path):
    # 'funnel' is neither a main part nor '<main>_<detail>': named in the error, with the
    # allowed names and the sub-part form as the fix.
    path, n = _box(tmp_path)
    with pytest.raises(InputError, match=r"part name = 'funnel'.*superstructure_funnel"):
        read_ship(path, units="m", part_map={"hull": [[0, n - 2]], "funnel": [[n - 2, n]]})


def test_check_surface_on_builtin_ship_is_clean():
    s = frigate(2.0)
    v, f, lab, rep = check_surface(s.vertices, s.faces, face_part=s.face_part)
    assert rep["open_edges"] == 0 and rep["flipped_faces"] == 0
    assert rep["signed_volume"] == pytest.approx(s.signed_volume)


def test_vtu_with_part_cell_array_and_obj_with_face_array(tmp_path):
    from shipthermal.geometry.pictures import write_parts_vtu

    s = frigate(3.0)
    write_parts_vtu(s, tmp_path)
    u, _ = read_ship(tmp_path / "all_parts.vtu", units="m")     # parts from the 'part' array
    assert u.part_names == s.part_names
    for n, a in s.part_areas().items():
        assert u.part_areas()[n] == pytest.approx(a, rel=1e-9)
    obj = tmp_path / "ship.obj"
    s.to_trimesh().export(obj)
    names = np.array(s.part_names)[s.face_part]
    u2, _ = read_ship(obj, units="m", part_map=names)
    assert u2.total_area == pytest.approx(s.total_area, rel=1e-6)
    assert u2.main_part_areas()["deck"] == pytest.approx(s.main_part_areas()["deck"], rel=1e-6)


def test_one_flipped_face_is_inconsistent_winding(tmp_path):
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    f = np.array(m.faces)
    f[3] = f[3, ::-1]
    path = tmp_path / "one_flipped.ply"
    trimesh.Trimesh(np.array(m.vertices), f, process=False).export(path)
    with pytest.raises(InputError, match=r"inconsistent winding\) \(fix: ship.files.fix_normals = true"):
        read_ship(path, units="m", part_map={"hull": [[0, 12]]})
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, 12]]},
                       settings=ReadShipSettings(fix_normals=True))
    assert rep["flipped_faces"] == 1
    assert u.signed_volume == pytest.approx(12000.0, rel=1e-12)


def test_waterline_must_cut_the_ship(tmp_path):
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    path = tmp_path / "keel_at_zero.stl"
    trimesh.Trimesh(np.array(m.vertices) + [0, 0, 5.0], np.array(m.faces), process=False).export(path)
    with pytest.raises(InputError, match="draught"):
        read_ship(path, units="m", part_map={"hull": [[0, 12]]})
    u, _ = read_ship(path, units="m", part_map={"hull": [[0, 12]]},
                     settings=ReadShipSettings(draught=4.0))
    assert u.draught == pytest.approx(4.0) and u.part_areas()["hull_wetted"] == pytest.approx(1200 + 2 * 112 * 4.0)


def test_overlapping_solids_rejected_then_united_by_repair(tmp_path):
    a = trimesh.creation.box((60.0, 10.0, 8.0))
    b = trimesh.creation.box((60.0, 10.0, 8.0))
    b.apply_translation((30.0, 0.0, 3.0))
    v = np.vstack([a.vertices, b.vertices])
    f = np.vstack([a.faces, b.faces + 8])
    path = tmp_path / "two_blocks.ply"
    trimesh.Trimesh(v, f, process=False).export(path)
    with pytest.raises(InputError, match="2 separate pieces that overlap"):
        read_ship(path, units="m", part_map={"hull": [[0, 24]]})
    # the union is exact: 9600 - 30 x 10 x 5 = 8100 m3
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, 24]]},
                       settings=ReadShipSettings(repair="union", max_repair_change=0.5))
    assert u.signed_volume == pytest.approx(8100.0, rel=1e-12)
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, 24]]},
                       settings=ReadShipSettings(repair="tetwild", max_repair_change=0.5))
    r = rep["repair"]
    # Before: two boxes counted twice, 2 x 4800 m3; the union is 9600 - 30x10x5 = 8100 m3.
    # fTetWild follows the input surfaces within its envelope here (no open lid to guess),
    # so 1 % covers its non-determinism.
    assert r["volume_before"] == pytest.approx(9600.0, rel=1e-12)
    assert r["volume_after"] == pytest.approx(8100.0, rel=1e-2)
    assert u.signed_volume == pytest.approx(r["volume_after"], rel=1e-9)


def test_json_part_map_carries_layups_and_temperatures(tmp_path):
    s = frigate(3.0).with_layups({"deck": [("mild_steel", 0.008, 2)]}).with_compartment_temperature(
        {"superstructure": 300.0})
    write_ship(s, tmp_path)
    u, _ = read_ship(tmp_path / "frigate.ply", units="m", part_map=tmp_path / "frigate_parts.json")
    assert u.layups["deck"].thickness == pytest.approx(0.008)
    assert u.layups["hull_dry"].thickness == pytest.approx(s.layups["hull_dry"].thickness)
    assert u.compartment_temperature["superstructure_mast"] == pytest.approx(300.0)
    assert (u.face_outer_medium[u.part_mask("hull_wetted")] == "sea").all()
    assert (u.face_outer_medium[~u.part_mask("hull_wetted")] == "air").all()


def _t_junction_box(tmp_path, n_needles=1):
    """Closed box with T-junctions: an edge (p, q) of one triangle is split at its midpoint m,
    and a zero-area needle (p, q, m) of three distinct collinear vertices closes the gap --
    what CAD exports leave where a face was split on one side of an edge only."""
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    v = list(np.array(m.vertices) + [0.0, 0.0, 1.0])
    f = [list(t) for t in np.array(m.faces)]
    done = set()
    for t in range(len(m.faces)):
        if len(done) == n_needles:
            break
        p, q, r = f[t]
        if t in done or any(t2 in done for t2 in range(len(f)) if {p, q} <= set(f[t2])):
            continue
        v.append(0.5 * (v[p] + v[q]))
        k = len(v) - 1
        f[t] = [p, k, r]
        f.append([k, q, r])
        f.append([p, q, k])                               # the needle
        done.add(t)
    path = tmp_path / "t_junction.stl"
    trimesh.Trimesh(np.array(v), np.array(f), process=False).export(path)
    return path, len(f)


def test_collinear_needle_error_and_reported_flip(tmp_path):
    path, n = _t_junction_box(tmp_path, n_needles=2)
    # Three distinct vertices, zero area: its own error (not "open edges" or "winding").
    with pytest.raises(InputError, match=r"2 zero-area triangles.*clean = true"):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})
    u, rep = read_ship(path, units="m", part_map={"hull": [[0, n]]},
                       settings=ReadShipSettings(clean=True))
    # The flip keeps the surface closed and every area: hand values of the 100 x 12 x 10 box.
    assert rep["degenerate_faces"] == 2 and rep["needles_flipped"] == 2 and rep["removed_degenerate"] == 0
    assert rep["open_edges"] == 0 and rep["flipped_faces"] == 0
    assert u.is_watertight and u.to_trimesh().is_winding_consistent
    assert u.total_area == pytest.approx(2 * (1200 + 1000 + 120), rel=1e-12)
    assert u.signed_volume == pytest.approx(12000.0, rel=1e-12)
    assert u.face_areas.min() > 1.0                     # no sliver left (smallest: half a 12x10 end)


def test_one_km_ship_gets_a_question(tmp_path):
    path, n = _box(tmp_path, scale=10.0)               # a 1 km "ship" declared in metres
    with pytest.raises(InputError, match=r"ship length of 1000 m, outside the plausible 5.500 m \(fix: rescale the file"):
        read_ship(path, units="m", part_map={"hull": [[0, n]]})
    u, _ = read_ship(path, units="m", part_map={"hull": [[0, n]]},
                     settings=ReadShipSettings(check_scale=False, draught=40.0))
    assert u.length == pytest.approx(1000.0)


def test_legacy_vtk_with_part_array(tmp_path):
    # The legacy .vtk format (what older CAD/CFD tools export) through pyvista, parts from
    # the 'part' cell array and names from field data.
    from shipthermal.geometry.pictures import ship_polydata

    s = frigate(4.0)
    ship_polydata(s).save(tmp_path / "ship.vtk", binary=False)
    u, rep = read_ship(tmp_path / "ship.vtk", units="m")
    assert u.part_names == s.part_names and u.n_faces == s.n_faces
    # ASCII legacy VTK keeps ~6-7 significant digits: areas to ~1e-6.
    for n, a in s.part_areas().items():
        assert u.part_areas()[n] == pytest.approx(a, rel=1e-5)
    assert rep["open_edges"] == 0 and u.signed_volume > 0
