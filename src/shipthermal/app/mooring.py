"""The ship's berth checked against the port: the footprint at ``ship.mooring_position``
and ``ship.heading`` must lie on water (:mod:`imaging.mooring`).

* :func:`check_mooring` — for a ship and a class map: refuses a footprint that reaches
  more than half a pixel into land, piers or buildings (or out of the scene), and warns
  about a smaller overlap (a pier face inside a mixed pixel); both name
  ``ship.mooring_position`` and a position that clears;
* :func:`builtin_class_map` — the built-in synthetic port's class map of a scenario,
  without building its background (for ``shipthermal check``).

The imaging stage calls :func:`check_mooring` with the background it built, for the
synthetic port and for real scenes alike.
"""

from __future__ import annotations

import functools

import numpy as np

from imaging.parameters import SYNTHETIC_PIXEL_M

from ..errors import InputError
from ..geometry import ship as gship

__all__ = ["check_mooring", "check_mooring_on", "builtin_class_map", "scenario_ship_outline"]


def _placement(scenario, shape, resolution_m):
    # deferred: loading a scenario imports no imaging module but its parameters
    # (test_load_is_lazy); imaging.scene adds 0.2 s (measured)
    from imaging.scene import ShipPlacement

    ny, nx = shape
    mx, my = scenario.ship.mooring_position
    return ShipPlacement(0.5 * nx * resolution_m + mx, 0.5 * ny * resolution_m + my,
                         scenario.ship.heading)


def check_mooring(scenario, ship, class_map, resolution_m: float) -> list:
    """Check the ship's footprint at its mooring against a class map.

    Parameters
    ----------
    scenario : Scenario
        Its ``ship.mooring_position`` [m east, north of the scene centre] and
        ``ship.heading`` [deg].
    ship : ShipGeometry-like
        ``vertices``, ``faces``, ``face_part``, ``part_names`` (ship frame).
    class_map : (ny, nx) int
        1 water, 2 vegetation, 3 land, 4 building; row 0 north.
    resolution_m : float
        Pixel side [m].

    Returns
    -------
    list of str
        Warnings (an overlap of at most half a pixel).

    Raises
    ------
    InputError
        ``ship.mooring_position`` when the footprint reaches more than half a pixel into
        anything but water, or leaves the scene.
    """
    # deferred: loading a scenario imports no imaging module but its parameters
    # (test_load_is_lazy); imaging.scene adds 0.2 s (measured)
    from imaging.mooring import clear_shift, footprint_overlap, hull_outline

    outline = hull_outline(ship.vertices, ship.faces, ship.face_part, ship.part_names)
    place = _placement(scenario, np.shape(class_map), resolution_m)
    res = footprint_overlap(class_map, resolution_m, place, outline)
    if res["dry_m2"] == 0.0:
        return []
    where = ", ".join(f"{k} {v:.0f} m2" for k, v in sorted(res["classes"].items()))
    shift, moved = clear_shift(class_map, resolution_m, place, outline)
    mx, my = scenario.ship.mooring_position
    if moved is not None:
        ny, nx = np.shape(class_map)
        nxy = [round(moved.x_m - 0.5 * nx * resolution_m, 1),
               round(moved.y_m - 0.5 * ny * resolution_m, 1)]
        fix = (f"Move the ship {abs(shift):.0f} m to {'port' if shift > 0 else 'starboard'}: "
               f"ship.mooring_position = [{nxy[0]:g}, {nxy[1]:g}] puts it on water")
    else:
        fix = "Choose ship.mooring_position (and ship.heading) on open water"
    name = getattr(ship, "name", "ship")
    what = (f"puts {res['dry_m2']:.0f} m2 of the {name}'s {res['area_m2']:.0f} m2 footprint "
            f"off the water ({where}), up to {res['depth_m']:.0f} m into its beam")
    if res["depth_m"] > 0.5 * resolution_m or "outside the scene" in res["classes"]:
        raise InputError("ship.mooring_position", [mx, my], f"{what}; at most half a "
                         f"{resolution_m:g} m pixel is accepted (a pier face inside a mixed "
                         "pixel)", fix)
    return [f"ship.mooring_position = [{mx:g}, {my:g}] {what}, within half a "
            f"{resolution_m:g} m pixel (a pier face inside a mixed pixel?). {fix}"]


def check_mooring_on(scenario, ship, background) -> list:
    """:func:`check_mooring` on the class map of a built background (a PortBackground or
    an imaging.scene.GriddedBackground: what the imaging stage renders)."""
    # deferred: loading a scenario imports no imaging module but its parameters
    # (test_load_is_lazy); imaging.scene adds 0.2 s (measured)
    from imaging.scene import as_scene_background

    bg = as_scene_background(background)
    return check_mooring(scenario, ship, bg.class_map, bg.resolution_m)


@functools.lru_cache(maxsize=4)
def _synthetic_classes(seed: int, size_px: int, lat: float, lon: float) -> np.ndarray:
    # deferred: imaging.background loads scikit-learn, pykrige and scipy.stats (2 s, measured);
    # loading a scenario imports no imaging module but its parameters (test_load_is_lazy)
    from imaging.background.synthetic import synthetic_surface

    return np.asarray(synthetic_surface(seed, size_px, lat, lon)["class_map"])


def builtin_class_map(scenario):
    """``(class_map, resolution_m)`` of the built-in synthetic port of a scenario, or None
    for a background from files (its classes come from the Landsat classification)."""
    bgs = scenario.background
    if bgs.source != "builtin":
        return None
    loc = scenario.location
    return _synthetic_classes(bgs.seed, bgs.size_px, loc.latitude, loc.longitude), \
        SYNTHETIC_PIXEL_M


def scenario_ship_outline(scenario):
    """The scenario's ship for the berth check: a built-in ship at a coarse mesh (5 % of
    its length: its plan outline does not depend on the mesh), a user ship as read."""
    s = scenario.ship
    if s.files is None:
        params = getattr(gship, f"{s.builtin}_parameters")(**s.parameters.given())
        return gship.build_ship(params, 0.05 * params.length)
    ship, _ = s.read_files()
    return ship
