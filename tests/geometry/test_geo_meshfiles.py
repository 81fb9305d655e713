"""Mesh files judged from their header before their body is read: damaged, truncated,
mislabelled or oversized files are refused quickly, naming the file, never quoting it."""

import resource
import time

import numpy as np
import pytest
import trimesh

from shipthermal.errors import InputError
from shipthermal.geometry.io import load_surface
from shipthermal.geometry.meshfiles import (MAX_MESH_FILE_BYTES, MAX_MESH_TRIANGLES,
                                            sniff_mesh_file)


@pytest.fixture()
def box(tmp_path):
    m = trimesh.creation.box((100.0, 12.0, 10.0))
    m.export(tmp_path / "box.stl")
    m.export(tmp_path / "box.ply")
    m.export(tmp_path / "boxa.stl", file_type="stl_ascii")
    return tmp_path


def _sparse(path, size):
    with open(path, "wb") as fh:
        fh.truncate(size)


def test_binary_stl_header_matches_its_length(box):
    info = sniff_mesh_file(box / "box.stl")
    assert info == {"format": "stl_binary", "triangles": 12, "bytes": 84 + 50 * 12}
    assert sniff_mesh_file(box / "boxa.stl")["format"] == "stl_ascii"
    assert sniff_mesh_file(box / "box.ply") == {"format": "ply", "triangles": 12,
                                                "bytes": (box / "box.ply").stat().st_size}


def test_zeros_refused_from_the_header_without_reading(tmp_path):
    """2 GB of zeros named .stl (a header declaring 0 triangles): refused in
    milliseconds, the body never read (the resident memory does not grow by it)."""
    path = tmp_path / "zeros.stl"
    _sparse(path, 2 * 10 ** 9)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    with pytest.raises(InputError, match=r"zeros.stl.*more than the 1024 MiB"):
        load_surface(path, "m")
    assert time.perf_counter() - t0 < 1.0
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0 < 50_000    # kB
    small = tmp_path / "zeros_small.stl"
    _sparse(small, 10 ** 6)
    with pytest.raises(InputError, match=r"zeros_small.stl.*count \(0\) needs 84 bytes "
                                         r"where it has 1,000,000"):
        load_surface(small, "m")
    _sparse(small, 84)
    with pytest.raises(InputError, match=r"holds no triangles \(its header declares 0\)"):
        load_surface(small, "m")


def test_declared_triangles_over_the_limit(tmp_path):
    n = MAX_MESH_TRIANGLES + 1
    path = tmp_path / "huge.stl"
    with open(path, "wb") as fh:
        fh.write(b"\0" * 80 + np.uint32(n).tobytes())
        fh.truncate(84 + 50 * n)
    with pytest.raises(InputError, match=r"declares 5,000,001 triangles"):
        load_surface(path, "m")
    obj = tmp_path / "huge.obj"
    _sparse(obj, MAX_MESH_FILE_BYTES + 1)
    with pytest.raises(InputError, match=r"huge.obj.*more than the 1024 MiB"):
        load_surface(obj, "m")


@pytest.mark.parametrize("case, fragments", [
    ("truncated-ply", ["box_cut.ply", "is not a readable PLY file", "(12 faces)", "truncated"]),
    ("stl-bad-number", ["bad.stl", "ASCII STL (line 4: a vertex coordinate is not a number)"]),
    ("text-not-stl", ["notes.stl", "is not an STL file", "'solid'"]),
    ("ply-not-ply", ["fake.ply", "is not a PLY file"]),
    ("glb-not-gltf", ["fake.glb", "is not a binary glTF file"]),
    ("obj-binary", ["bin.obj", "is not a text OBJ file"]),
    ("nan-vertex", ["nan.stl", "not finite numbers"]),
])
def test_damaged_files(box, case, fragments):
    d = box
    secret = "root:$6$secret-hash:19000:0:99999:7:::"
    if case == "truncated-ply":
        b = (d / "box.ply").read_bytes()
        (d / "box_cut.ply").write_bytes(b[:len(b) // 2])
        path = d / "box_cut.ply"
    elif case == "stl-bad-number":
        lines = (d / "boxa.stl").read_text().splitlines()
        assert lines[3].split()[0] == "vertex"
        lines[3] = "      vertex 1.2.3 0 0"
        (d / "bad.stl").write_text("\n".join(lines) + "\n")
        path = d / "bad.stl"
    elif case == "text-not-stl":
        (d / "notes.stl").write_text(secret + "\n")
        path = d / "notes.stl"
    elif case == "ply-not-ply":
        (d / "fake.ply").write_text(secret + "\n")
        path = d / "fake.ply"
    elif case == "glb-not-gltf":
        (d / "fake.glb").write_text(secret)
        path = d / "fake.glb"
    elif case == "obj-binary":
        (d / "bin.obj").write_bytes(b"\0\1\2" * 100)
        path = d / "bin.obj"
    else:
        m = trimesh.creation.box((100.0, 12.0, 10.0))
        v = np.array(m.vertices)
        v[0, 0] = np.nan
        trimesh.Trimesh(v, m.faces, process=False).export(d / "nan.stl")
        path = d / "nan.stl"
    t0 = time.perf_counter()
    with pytest.raises(InputError) as err:
        load_surface(path, "m")
    assert time.perf_counter() - t0 < 2.0
    msg = str(err.value)
    assert msg.startswith("ship.files.mesh = ")
    for f in fragments:
        assert f in msg, msg
    assert "secret" not in msg and "root:" not in msg          # the file is never quoted
