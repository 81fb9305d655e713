"""Surface maps: the view geometry (north, east, bow, sensor) and a PNG that decodes."""

import numpy as np
import pytest

from shipthermal.geometry.surface_maps import (_sensor_view, project, render_surface_map,
                                               ship_to_enu)


@pytest.mark.parametrize("heading, bow_enu", [(0.0, (0, 1, 0)), (90.0, (1, 0, 0)),
                                              (180.0, (0, -1, 0)), (270.0, (-1, 0, 0))])
def test_bow_and_port_in_east_north_up(heading, bow_enu):
    R = ship_to_enu(heading)
    assert R @ [1.0, 0.0, 0.0] == pytest.approx(bow_enu, abs=1e-12)
    # port is the bow turned 90 deg counter-clockwise seen from above
    assert R @ [0.0, 1.0, 0.0] == pytest.approx(np.cross([0, 0, 1], bow_enu), abs=1e-12)
    assert R.T @ R == pytest.approx(np.eye(3), abs=1e-12)


def test_nadir_view_is_a_plan_with_north_up_and_east_right():
    az, el = _sensor_view(0.0, 0.0)
    u, v, d = project(np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]), az, el)
    assert (u[0], v[0]) == pytest.approx((1.0, 0.0), abs=1e-12)       # east -> right
    assert (u[1], v[1]) == pytest.approx((0.0, 1.0), abs=1e-12)       # north -> up
    assert d[2] == pytest.approx(1.0)                                  # up -> toward sensor


def test_oblique_sensor_looks_from_its_azimuth():
    """A sensor 30 deg off nadir in the south-east: the point of the ship nearest to it
    (its south-east corner) is the one nearest to the viewer (largest depth)."""
    az, el = _sensor_view(30.0, 135.0)
    corners = np.array([[x, y, 0.0] for x in (-1, 1) for y in (-1, 1)])
    _, _, depth = project(corners, az, el)
    assert tuple(corners[np.argmax(depth)][:2]) == (1, -1)
    # the toward-viewer direction is the sensor direction (zenith 30, compass azimuth 135)
    th, ph = np.radians(30.0), np.radians(135.0)
    sensor = np.array([np.sin(th) * np.sin(ph), np.sin(th) * np.cos(ph), np.cos(th)])
    _, _, d = project(sensor[None, :], az, el)
    assert d[0] == pytest.approx(1.0, abs=1e-12)


def test_surface_map_png(tmp_path):
    from PIL import Image

    from shipthermal.raytrace.scenes import box

    V, F = box([-20.0, -3.0, -2.0], [20.0, 3.0, 4.0])
    vals = 290.0 + np.arange(len(F), dtype=float)
    p = render_surface_map(V, F, vals, tmp_path / "s.png", heading_deg=180.0,
                           sun_azimuth_deg=135.0, sun_elevation_deg=-5.0,
                           title="box, 06:00 local — summer")
    with Image.open(p) as im:
        im.load()
        assert im.width > 800 and im.height > 300
    assert [q.name for q in tmp_path.iterdir()] == ["s.png"]      # no temporary left
