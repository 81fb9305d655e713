"""Pictures and VTU files of the parts."""

import numpy as np
import pytest

from shipthermal.geometry import frigate
from shipthermal.geometry.pictures import render_parts_png, write_parts_vtu


@pytest.fixture(scope="module")
def ship():
    return frigate(3.0)


@pytest.mark.parametrize("backend", ["pyvista", "matplotlib"])
def test_png_coloured_by_part(ship, tmp_path, backend):
    import matplotlib.image as mpimg

    path = tmp_path / f"ship_{backend}.png"
    used = render_parts_png(ship, path, size=(640, 360), backend=backend)
    assert used == backend and path.exists()
    img = mpimg.imread(path)[..., :3]
    # A picture of the ship, not a blank frame: several distinct part colours present.
    colours = np.unique((img.reshape(-1, 3) * 255).astype(int) // 32, axis=0)
    assert len(colours) >= 6


def test_vtu_per_part_round_trip(ship, tmp_path):
    import pyvista as pv

    paths = write_parts_vtu(ship, tmp_path)
    assert {p.stem for p in paths} == set(ship.part_names) | {"all_parts"}
    total = 0
    for name in ship.part_names:
        grid = pv.read(tmp_path / f"{name}.vtu")
        total += grid.n_cells
        assert grid.compute_cell_sizes()["Area"].sum() == pytest.approx(ship.part_areas()[name], rel=1e-9)
    assert total == ship.n_faces
    all_parts = pv.read(tmp_path / "all_parts.vtu")
    assert np.array_equal(np.asarray(all_parts.cell_data["part"]), ship.face_part)


def test_falls_back_to_matplotlib_when_vtk_fails(ship, tmp_path, monkeypatch):
    import shipthermal.geometry.pictures as pics

    def broken(*args, **kwargs):
        raise RuntimeError("no OpenGL context")

    monkeypatch.setattr(pics, "_render_pyvista", broken)
    used = pics.render_parts_png(ship, tmp_path / "fallback.png", size=(320, 200))
    assert used == "matplotlib" and (tmp_path / "fallback.png").stat().st_size > 1000
