"""The files in meshes/ are the current built-in ships and open as a user would open them."""

import importlib.util
import json
from pathlib import Path

import pytest

from shipthermal.geometry import cargo_ship, frigate, patrol_boat
from shipthermal.geometry.io import read_ship

ROOT = Path(__file__).resolve().parents[2]
MESHES = ROOT / "meshes"


def _coarse_edges():
    spec = importlib.util.spec_from_file_location("write_builtin_meshes", ROOT / "scripts" / "write_builtin_meshes.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.COARSE_EDGE


@pytest.mark.parametrize("build", [frigate, patrol_boat, cargo_ship], ids=lambda b: b.__name__)
def test_meshes_folder_matches_the_generator(build):
    # If the generator changes, the committed files must be rewritten
    # (python scripts/write_builtin_meshes.py): compare with a fresh build at the same size.
    name = build.__name__
    ship = build(_coarse_edges()[name])
    u, rep = read_ship(MESHES / f"{name}.ply", units="m", part_map=MESHES / f"{name}_parts.json")
    assert u.part_names == ship.part_names and u.n_faces == ship.n_faces
    assert rep["open_edges"] == 0 and rep["flipped_faces"] == 0 and rep["removed_degenerate"] == 0
    # PLY and STL store float32 coordinates: relative area / volume error ~1e-7 (measured
    # <= 4e-7 on the smallest part), hence 1e-5.
    for part, area in ship.part_areas().items():
        assert u.part_areas()[part] == pytest.approx(area, rel=1e-5), part
    assert u.signed_volume == pytest.approx(ship.signed_volume, rel=1e-5)
    stl = {p: MESHES / f"{name}_parts" / f"{p}.stl" for p in ship.part_names}
    assert sorted(q.name for q in (MESHES / f"{name}_parts").iterdir()) == sorted(f"{p}.stl" for p in ship.part_names)
    w, _ = read_ship(stl, units="m")
    assert w.is_watertight and w.total_area == pytest.approx(ship.total_area, rel=1e-5)
    meta = json.loads((MESHES / f"{name}_parts.json").read_text())
    assert meta["units"] == "m" and meta["length"] == ship.length and meta["provenance"] == ship.provenance
    assert (MESHES / f"{name}.png").stat().st_size > 10_000
