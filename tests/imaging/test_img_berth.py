"""The built-in scenario moors the ship at a real berth: alongside the synthetic port's first
pier, on water, with the pier face less than one pixel from the hull."""

import numpy as np
import pytest

from imaging.background import build_port_background
from imaging.render import SceneRenderer
from imaging.scene import ShipPlacement, as_scene_background
from imaging.thermal_history import ShipThermalHistory
from shipthermal.raytrace.scenes import box
from shipthermal.app.scenario import default_scenario

WIND_SPEED = 5.0    # m/s: the sea's Cox-Munk slopes (the coverage does not depend on it)


@pytest.mark.parametrize("season", ["summer", "winter"])
def test_default_mooring_is_alongside_a_pier(season):
    sc = default_scenario(season)
    bg = as_scene_background(build_port_background(season))
    ny, nx = bg.class_map.shape
    res = bg.resolution_m
    mx, my = sc.ship.mooring_position
    place = ShipPlacement(0.5 * nx * res + mx, 0.5 * ny * res + my, sc.ship.heading)
    # a frigate-sized box (132 m x 15 m, the built-in frigate's length and beam)
    V, F = box([-66.0, -7.5, -4.0], [66.0, 7.5, 8.0])
    hist = ShipThermalHistory(V, F, np.zeros(len(F), int), ("deck",), [0.0, 3600.0],
                              np.full((2, len(F)), 300.0))
    cov = SceneRenderer(hist, bg, place, samples_per_pixel=4, wind_speed=WIND_SPEED).coverage > 0
    assert cov.any() and np.all(bg.class_map[cov] == 1)          # the ship floats on water
    rows = np.flatnonzero(cov.any(axis=1))
    west = np.array([np.flatnonzero(cov[r])[0] for r in rows])
    # every ship row has a non-water pixel (the pier) immediately west of the hull...
    assert np.all(bg.class_map[rows, west - 1] != 1)
    # ...and the hull's west side lies within one pixel of the pier's east face
    hull_west = place.x_m - 7.5
    face = west * res                                           # east edge of the pier pixel
    assert np.all((hull_west - face >= 0) & (hull_west - face < res))
