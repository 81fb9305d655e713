"""Reading a user ship: load, diagnose and repair, the outside test, position, parts, and
the particulars, each a named stage of :func:`read_ship`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from ...errors import InputError, require
from ..cad import (FIXED_BY, MAX_REPAIR_CHANGE, assign_parts, diagnose_surface, part_ranges,
                   problems_message, repair_change_check)
from ..layups import compartment_temperatures, default_layups, outer_media
from ..outside import part_sense, sliver_share
from ..parts import MAIN_PARTS, face_areas, main_part, split_at_waterline
from ..ship_geometry import ShipGeometry
from .checks import check_surface
from .load import UNITS
from .repairs import outside_checked, repair_once
from .sources import load_source

__all__ = ["ReadShipSettings", "read_ship"]


@dataclass(frozen=True)
class ReadShipSettings:
    """How :func:`read_ship` places a user ship, what it overrides, and which problems of
    the mesh it may fix (the scenario's ``ship.files.*`` keys).

    Attributes
    ----------
    draught : float, optional
        Keel depth below the waterline [m]: the waterline is ``min z + draught``.
    waterline_z : float, optional
        Height of the waterline in the file's frame [m, after unit conversion]. Without
        either, the file's z = 0 is taken as the waterline.
    name : str, optional
    layups, compartment_temperature : mapping, optional
        Overrides of the defaults (:mod:`..layups`).
    clean : bool
        Drop zero-area and duplicate triangles (reported) instead of failing.
    fix_normals : bool
        Fix inconsistent / inward normals (reported) instead of failing.
    repair : {None, 'union', 'tetwild'}
        Before the checks: ``'union'`` unites closed overlapping pieces exactly
        (manifold3d, seconds); ``'tetwild'`` remeshes through pytetwild (closes gaps,
        resolves self-intersections; minutes for large soups). Area and volume change
        are reported and limited by ``max_repair_change``.
    repair_edge_length : float, optional
        Target edge length of the repair [m] (default: pytetwild's, 5 % of the bounding
        box diagonal; finer is much slower, e.g. ~50 s at 1 m for a 100 m box).
    check_scale : bool
        Reject implausible ship sizes (units mistakes).
    recentre : bool
        Move the origin amidships on the centreline (x, y of the bounding-box centre).
    max_repair_change : float, optional
        Largest relative change of area or volume a repair may make (default
        :data:`..cad.MAX_REPAIR_CHANGE`).
    """

    draught: float | None = None
    waterline_z: float | None = None
    name: str | None = None
    layups: Mapping | None = None
    compartment_temperature: Mapping | None = None
    clean: bool = False
    fix_normals: bool = False
    repair: str | None = None
    repair_edge_length: float | None = None
    check_scale: bool = True
    recentre: bool = True
    max_repair_change: float | None = None


def read_ship(source, units: str | None = None, part_map=None,
              part_names: Sequence[str] | None = None,
              settings: ReadShipSettings | None = None):
    """Read a user ship and return it checked, positioned and split into parts.

    Parameters
    ----------
    source : path or mapping part → path
        One mesh file (with ``part_map`` or a ``part`` cell array), or one file per part.
    units : {'m', 'mm'}
        Unit of the file coordinates (required).
    part_map : array, dict, path or 'auto', optional
        See :func:`.part_map.read_part_map`. ``'auto'``: parts by rules
        (:func:`..cad.assign_parts`); the report's ``auto_parts`` then holds the face ranges
        to edit and reuse. Without a part map, OBJ groups / GLB named meshes name the parts.
    part_names : sequence of str, optional
        Names for an integer part map.
    settings : ReadShipSettings, optional
        Placement, overrides, and the problems the read may fix (default: none).

    Returns
    -------
    ship : ShipGeometry
    report : dict
        What was checked and changed (``removed_degenerate``, ``removed_duplicate``,
        ``flipped_faces``, ``repair`` (area/volume before and after), ``translation`` [m]);
        ``repairs``: one line per change made, for the console.

    Raises
    ------
    InputError
        Every problem found, in one error naming the options (the scenario keys
        ``ship.files.*``) that fix each one.
    """
    s = ReadShipSettings() if settings is None else settings
    require(units in UNITS, "ship.files.units", units, "must be declared: 'm' or 'mm'",
            'Set ship.files.units = "m" or "mm" (the unit the file\'s coordinates are in)')
    require(s.repair in (None, "union", "tetwild"), "ship.files.repair", s.repair,
            "must be 'none', 'union' or 'tetwild'")
    max_change = MAX_REPAIR_CHANGE if s.max_repair_change is None else float(s.max_repair_change)
    auto = isinstance(part_map, str) and part_map == "auto"
    report: dict = {"units": units}
    src = load_source(source, units, part_map, part_names, s.name, s.layups,
                      s.compartment_temperature)
    v, f, labels, names = src.vertices, src.faces, src.labels, src.names
    where = source if not isinstance(source, Mapping) else ", ".join(
        str(x) for x in source.values())
    n_file_faces = len(f)
    v, f, labels = _diagnose_and_repair(v, f, labels, units, where, s, max_change, report)

    # The outside, by ray casting: interior shells removed, inside-out pieces turned.
    v, f, labels, outside = outside_checked(v, f, labels, s.fix_normals, source,
                                            report["repairs"])
    report["outside"] = outside
    v = _position(v, s, report)
    if auto:
        labels, names = _auto_parts(v, f, units, n_file_faces, report)
    v, f, face_part, keep = _final_parts(v, f, labels, names, report)
    return _particulars(v, f, face_part, keep, units, auto, isinstance(source, Mapping),
                        src, report), report


def _diagnose_and_repair(v, f, labels, units: str, where, s: ReadShipSettings,
                         max_change: float, report: dict):
    """Every problem at once, each with the keys that fix it (an error naming those the
    settings leave unfixed); the ones the settings handle are repaired (``s.repair``),
    cleaned and re-oriented (:func:`.checks.check_surface`), one line each in
    ``report["repairs"]``."""
    enabled = {"clean": s.clean, "fix_normals": s.fix_normals, "repair": s.repair is not None,
               "check_scale": not s.check_scale}
    problems = diagnose_surface(v, f, units, check_scale=s.check_scale)
    report["problems_found"] = [str(p) for p in problems]
    left = [p for p in problems if not enabled.get(FIXED_BY.get(p.kind, ""), False)]
    if left:
        raise problems_message(where, left)
    lines = report["repairs"] = []
    report["warnings"] = []
    if s.repair is not None and any(p.kind in ("open", "nonmanifold", "intersecting")
                                    for p in problems):
        if s.clean and s.repair == "tetwild":      # no zero-area / duplicate triangles
            # (and consistently wound: fTetWild's inside test uses the winding number)
            v, f, labels, _ = check_surface(v, f, units, check_scale=False, clean=True,
                                            fix_normals=True, face_part=labels,
                                            require_closed=False)
        v, f, labels, rep = repair_once(v, f, labels, s.repair, s.repair_edge_length, lines)
        report["repair"] = rep
        lines.append(f"repair ({rep['method']}, {rep['seconds']:.1f} s): area "
                     f"{rep['area_before']:.6g} -> {rep['area_after']:.6g} m2 "
                     f"({100 * rep['area_change']:+.2f} %), volume {rep['volume_before']:.6g} -> "
                     f"{rep['volume_after']:.6g} m3 ({100 * rep['volume_change']:+.2f} %)")
        repair_change_check(rep, max_change)
    a_before = float(face_areas(v, f).sum())
    v, f, labels, chk = check_surface(v, f, units, check_scale=False, clean=s.clean,
                                      fix_normals=s.fix_normals, face_part=labels,
                                      allow_nonmanifold=s.repair is not None)
    report.update(chk)
    if chk["removed_degenerate"] or chk["removed_duplicate"] or chk.get("needles_flipped"):
        lines.append(f"clean: {chk['removed_duplicate']} duplicate and "
                     f"{chk['removed_degenerate']} zero-area triangles removed, "
                     f"{chk.get('needles_flipped', 0)} needles flipped; area {a_before:.6g} -> "
                     f"{chk['area']:.6g} m2 ({100 * (chk['area'] / a_before - 1):+.4f} %)")
    if chk["flipped_faces"]:
        lines.append(f"fix_normals: {chk['flipped_faces']} triangles re-oriented (area and "
                     f"volume unchanged, volume {chk['signed_volume']:.6g} m3)")
    return v, f, labels


def _position(v, s: ReadShipSettings, report: dict):
    """Position: waterline at z = 0, origin amidships on the centreline (``s.recentre``);
    the shift goes to ``report["translation"]``."""
    draught, waterline_z = s.draught, s.waterline_z
    height = float(np.ptp(v[:, 2]))
    if draught is not None:
        require(0 < draught < height, "ship.files.draught", draught,
                f"must lie between 0 and the height of the mesh ({height:.3f} m)",
                "It is the keel depth below the waterline")
        z_wl = float(v[:, 2].min() + draught)
    elif waterline_z is not None:
        z_wl = float(waterline_z)
    else:
        z_wl = 0.0
    if not v[:, 2].min() < z_wl < v[:, 2].max():
        key = "ship.files.waterline_z" if waterline_z is not None and draught is None else \
            "waterline (z = 0 of the file)" if draught is None else "ship.files.draught"
        raise InputError(key, z_wl, f"must cut the ship (z from {v[:, 2].min():.3f} to "
                         f"{v[:, 2].max():.3f} m)", "Set ship.files.draught (keel depth "
                         "below the waterline) or ship.files.waterline_z")
    shift = np.array([0.0, 0.0, -z_wl])
    if s.recentre:
        mid = 0.5 * (v.min(axis=0) + v.max(axis=0))
        shift[:2] = -mid[:2]
    v = v + shift
    report["translation"] = shift.tolist()
    return v


def _auto_parts(v, f, units: str, n_file_faces: int, report: dict):
    """Parts by rules (:func:`..cad.assign_parts`); their face ranges go to
    ``report["auto_parts"]`` to edit and reuse. Returns ``(labels, names)``."""
    labels, names, info = assign_parts(v, f)
    report["auto_parts"] = dict(
        parts=part_ranges(labels, names), units=units, rules=info,
        faces_as_in_file=bool(len(f) == n_file_faces and "repair" not in report),
        note="parts assigned by rules (hull below the waterline and on the sides, deck "
             "= upward faces at deck level, superstructure above): check the picture; "
             "edit the face ranges and give this file as ship.files.part_map")
    return labels, names


def _final_parts(v, f, labels, names, report: dict):
    """Parts: split 'hull' at the waterline; other parts keep their faces; main parts
    first, then sub-parts; empty parts dropped. Returns ``(v, f, face_part, part names)``."""
    v, f, labels, _ = split_at_waterline(v, f, labels, 0.0, tol=1e-9 * float(np.ptp(v[:, 0])))
    zc = v[f, 2].mean(axis=1)
    final = [n for n in MAIN_PARTS if n in names or (n.startswith("hull_") and "hull" in names)]
    final += sorted(n for n in names if n not in final and n != "hull")
    new_lab = np.empty(len(f), np.int64)
    for k, n in enumerate(names):
        sel = labels == k
        if n == "hull":
            new_lab[sel & (zc < 0)] = final.index("hull_wetted")
            new_lab[sel & (zc >= 0)] = final.index("hull_dry")
        else:
            new_lab[sel] = final.index(n)
    counts = np.bincount(new_lab, minlength=len(final))
    keep = [n for k, n in enumerate(final) if counts[k] > 0]
    remap = np.array([keep.index(n) if n in keep else -1 for n in final])
    face_part = remap[new_lab]
    wet = [k for k, n in enumerate(keep) if main_part(n) == "hull_wetted"]
    report["wetted_faces_above_waterline"] = int(np.sum(np.isin(face_part, wet) & (zc > 1e-9)))
    return v, f, face_part, keep


def _particulars(v, f, face_part, keep, units: str, auto: bool, per_part_files: bool,
                 src, report: dict) -> ShipGeometry:
    """The particulars (length, beam, draught, freeboard from the deck amidships), a
    sense check of the parts (an error, or warnings in ``report``), the sliver share, and
    the :class:`ShipGeometry`."""
    length = float(np.ptp(v[:, 0]))
    deck_k = [k for k, n in enumerate(keep) if main_part(n) == "deck"]
    deck_z = v[f[np.isin(face_part, deck_k)]].reshape(-1, 3)
    mid = np.abs(deck_z[:, 0]) < 0.1 * length
    freeboard = float(np.median(deck_z[mid, 2])) if mid.any() else float("nan")
    refusals, warnings = part_sense(v, f, face_part, keep, freeboard)
    if refusals:
        fix = ("The parts were assigned by rules (part_map = \"auto\"): check the mesh "
               "(ship.files.draught, inside shells) or give ship.files.part_map"
               if auto else "Check ship.files.part_map (or the part names in the file) and "
               "ship.files.draught / waterline_z")
        raise InputError("ship.files.part_map" if not per_part_files
                         else "ship.files.parts", "auto" if auto else "as given",
                         "; ".join(refusals), fix)
    for w in warnings:
        report["warnings"].append(f"{w} (check ship.files.part_map)")
    share, edge = sliver_share(v, f)
    report["sliver_share"] = share
    report["equilateral_edge_m"] = edge
    hull_k = [k for k, n in enumerate(keep) if main_part(n) in ("hull_wetted", "hull_dry")]
    hull_v = v[f[np.isin(face_part, hull_k)]].reshape(-1, 3) if hull_k else v
    return ShipGeometry(
        vertices=v, faces=f, face_part=face_part, part_names=tuple(keep),
        layups=default_layups(keep, src.layups), compartment_temperature=compartment_temperatures(
            keep, src.compartment_temperature), outer_medium=outer_media(keep),
        length=length, beam=float(np.ptp(hull_v[:, 1])), draught=float(-v[:, 2].min()),
        freeboard=freeboard, name=src.name, provenance=f"user mesh ({units})",
        edge_length=float(np.median(np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1))))
