"""The ship's footprint at its berth against the port's class map (imaging.mooring and
shipthermal.app.mooring): areas and depths measured on a lattice of 1 m, checked against
hand-computed overlaps of a rectangle ship with a pier."""

import numpy as np
import pytest

from imaging.mooring import clear_shift, footprint_overlap, hull_outline
from imaging.scene import ShipPlacement
from shipthermal.app.mooring import builtin_class_map, check_mooring, scenario_ship_outline
from shipthermal.app.scenario import default_scenario, load_scenario
from shipthermal.errors import InputError

RES = 30.0


def _port():
    """30 x 30 pixels of water with a pier: columns 10-12 (x 300-390 m) from row 0 (north)
    to row 19 (y 300-900 m)."""
    cm = np.ones((30, 30), np.uint8)
    cm[:20, 10:13] = 3
    return cm


RECT = np.array([[-60.0, -10.0], [60.0, -10.0], [60.0, 10.0], [-60.0, 10.0]])   # 120 x 20 m


def test_overlap_of_a_rectangle_with_a_pier():
    cm = _port()
    # bow north, centre 395 m east: the hull spans x 385-405 m, 5 m onto the pier (x < 390)
    # over its whole 120 m length (y 540-660 m, all beside the pier, which ends at 300 m)
    place = ShipPlacement(395.0, 600.0, 0.0)
    r = footprint_overlap(cm, RES, place, RECT)
    assert r["area_m2"] == pytest.approx(120 * 20)
    assert r["dry_m2"] == pytest.approx(5 * 120)
    assert r["depth_m"] == pytest.approx(5.0)
    assert r["classes"] == {"land": pytest.approx(600.0)}
    # the smallest shift that clears it: 5 m east, i.e. to starboard with the bow north
    shift, moved = clear_shift(cm, RES, place, RECT)
    assert shift == pytest.approx(-5.0) and moved.x_m == pytest.approx(400.0)
    assert footprint_overlap(cm, RES, moved, RECT)["dry_m2"] == 0.0
    # half off the scene's east edge (x 900 m)
    r = footprint_overlap(cm, RES, ShipPlacement(895.0, 600.0, 0.0), RECT)
    assert r["classes"] == {"outside the scene": pytest.approx(5 * 120)}


def test_heading_turns_the_footprint():
    cm = _port()
    # bow east: the ship lies along x (330-450 m), 20 m wide in y (340-360 m, where the
    # pier is); it crosses the pier (x 300-390)
    r = footprint_overlap(cm, RES, ShipPlacement(390.0, 350.0, 90.0), RECT)
    # pier columns x 300-390 under the ship (x 330-450): 60 m of its length, full beam
    assert r["dry_m2"] == pytest.approx(60 * 20) and r["depth_m"] == pytest.approx(20.0)


def test_check_mooring_refuses_beyond_half_a_pixel():
    cm = _port()
    sc = load_scenario({"background": {"size_px": 60}, "ship": {"mooring_position": [0.0, 0.0]}})

    class Ship:             # a 120 x 20 m box hull
        vertices = np.array([[x, y, z] for x in (-60, 60) for y in (-10, 10) for z in (-4, 6)],
                            float)
        faces = np.array([[0, 1, 2], [3, 4, 5], [5, 6, 7]])
        face_part = np.array([0, 0, 0])
        part_names = ("hull_dry",)
        name = "box"

    assert hull_outline(Ship.vertices, Ship.faces, Ship.face_part,
                        Ship.part_names).shape == (4, 2)
    # scene centre (450, 450) + mooring; heading 0: hull x from mx + 440 to mx + 460
    sc = sc.updated({"ship.heading": 0.0, "ship.mooring_position": [-55.0, 150.0]})
    warn = check_mooring(sc, Ship, cm, RES)           # 5 m onto the pier: warned
    assert warn and "5 m into its beam" in warn[0] and "ship.mooring_position" in warn[0]
    sc = sc.updated({"ship.mooring_position": [-70.0, 150.0]})   # 20 m onto the pier
    with pytest.raises(InputError, match=r"ship.mooring_position = \[-70.0, 150.0\].*"
                                         r"20 m into its beam.*half a 30 m pixel.*Move the ship "
                                         r"20 m to starboard: ship.mooring_position = \[-50, 150\]"):
        check_mooring(sc, Ship, cm, RES)
    sc = sc.updated({"ship.mooring_position": [-20.0, 150.0]})   # clear water
    assert check_mooring(sc, Ship, cm, RES) == []


@pytest.mark.parametrize("builtin", ["frigate", "patrol_boat", "cargo_ship"])
def test_builtin_ships_float_at_the_default_berth(builtin):
    sc = default_scenario("summer").updated({"ship.builtin": builtin})
    cm, res = builtin_class_map(sc)
    assert check_mooring(sc, scenario_ship_outline(sc), cm, res) == []
