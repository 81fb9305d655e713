"""Default plate layups, compartment air temperatures and outer media per ship part.

Layups run from the outer surface inwards (see :class:`shipthermal.materials.Layup`).

Defaults (all overridable, see :func:`default_layups`)
------------------------------------------------------
========================  =====================================================  ==========
part                      layup (outer → inner)                                   ρ·t [kg/m²]
========================  =====================================================  ==========
hull_wetted, hull_dry     0.3 mm marine paint + 14 mm mild steel                  110.26
deck                      3 mm epoxy non-skid deck covering + 10 mm mild steel   82.10
superstructure (and sub)  0.3 mm paint + 6 mm steel + 50 mm mineral wool          52.46
superstructure_mast       0.3 mm paint + 8 mm steel (no insulation, no rooms)     63.16
========================  =====================================================  ==========

Why these numbers:

* Hull shell plating of frigates and corvettes is 10–16 mm mild/high-tensile steel
  (bottom and side shell of ~130 m warships; Lloyd's Register *Rules for Naval Ships*
  give minimum shell thicknesses of this order); 14 mm is the middle of that band.
* Weather-deck plating 8–10 mm with a 2–6 mm epoxy non-skid covering (flight and
  weather decks; e.g. MIL-PRF-24667 non-skid systems are applied 2–6 mm thick).
* Deckhouse plating 5–8 mm steel (or 5083 aluminium on lighter ships) lined inside with
  50 mm mineral wool (A-60 fire insulation of accommodation boundaries, SOLAS II-2).
* Paint: a typical marine coating system is 250–350 µm dry film; 0.3 mm is used.

Cells through the thickness: paint and coverings 1 cell; steel 1 cell (the Biot number of a
14 mm steel plate is ≈ 0.004 and heat crosses it in t²/α ≈ 15 s, twenty times less than a
300 s step: the plate is isothermal to what the steps can see, and a cell's two-point
conductances carry its steady through-thickness drop exactly); mineral wool 4 cells (its
diurnal penetration depth √(αP/π) ≈ 0.1 m exceeds the 50 mm thickness, 4 cells keep the
through-thickness profile to a few percent). Measured on the built-in frigate summer day at
0.5 m: 2 steel cells instead of 1 change the surface temperatures by at most 6.4e-3 K
(part means 1.0e-3 K) and cost 23 % more cells (257 k against 197 k) and 20 % more time.

Compartment air temperature
---------------------------
Inside every part the default air temperature is **22 °C (295.15 K)**, the winter indoor
design condition of ISO 7547:2002 (*Ships and marine technology — Air-conditioning and
ventilation of accommodation spaces — Design conditions*); its summer condition is
27 °C, available as ``compartment_temperatures(..., season="summer")``. 22 °C is also inside
the ASHRAE 55 comfort band. The outer side of ``hull_wetted`` faces the sea; all other
parts face the air (:func:`outer_media`).
"""

from __future__ import annotations

from typing import Mapping, Sequence

from ..errors import InputError, check_range, require
from ..materials import Layer, Layup
from ..units import ZERO_CELSIUS
from .parts import main_part

__all__ = ["PAINT_THICKNESS", "HULL_LAYUP", "DECK_LAYUP", "SUPERSTRUCTURE_LAYUP", "MAST_LAYUP",
           "superstructure_layup", "default_layups", "ISO7547_INDOOR_C",
           "compartment_temperatures", "outer_media"]

PAINT_THICKNESS = 0.3e-3
"""Dry film thickness of the outer coating system [m]."""

HULL_LAYUP = Layup((Layer("marine_paint", PAINT_THICKNESS, 1), Layer("mild_steel", 0.014, 1)),
                   name="hull")
DECK_LAYUP = Layup((Layer("deck_covering", 0.003, 1), Layer("mild_steel", 0.010, 1)), name="deck")
MAST_LAYUP = Layup((Layer("marine_paint", PAINT_THICKNESS, 1), Layer("mild_steel", 0.008, 1)),
                   name="superstructure_mast")


def superstructure_layup(material: str = "mild_steel", plate: float = 0.006,
                         insulation: float = 0.050) -> Layup:
    """Painted deckhouse plating with mineral wool inside.

    Parameters
    ----------
    material : str
        ``'mild_steel'`` or ``'aluminium_5083'`` (or any known material).
    plate : float
        Plate thickness [m].
    insulation : float
        Mineral wool thickness [m]; 0 for none.
    """
    layers = [Layer("marine_paint", PAINT_THICKNESS, 1), Layer(material, plate, 1)]
    if insulation > 0:
        layers.append(Layer("mineral_wool", insulation, 4))
    return Layup(tuple(layers), name="superstructure")


SUPERSTRUCTURE_LAYUP = superstructure_layup()

_BY_MAIN = {"hull_wetted": HULL_LAYUP, "hull_dry": HULL_LAYUP, "hull": HULL_LAYUP,
            "deck": DECK_LAYUP, "superstructure": SUPERSTRUCTURE_LAYUP}

HULL_ALIASES = ("hull_wetted", "hull_dry")

ISO7547_INDOOR_C = {"winter": 22.0, "summer": 27.0}
"""ISO 7547:2002 indoor design air temperatures of ship accommodation [°C]."""


def _as_layup(value, field: str) -> Layup:
    if isinstance(value, Layup):
        return value
    if isinstance(value, (list, tuple)):
        return Layup.from_list(value, name=field)
    raise InputError(field, value, "must be a Layup or a list of (material, thickness_m, cells)")


def default_layups(part_names: Sequence[str], overrides: Mapping | None = None,
                   superstructure_material: str = "mild_steel") -> dict[str, Layup]:
    """Layup of every part: defaults by main part, then ``overrides``.

    Parameters
    ----------
    part_names : sequence of str
        Parts of the ship.
    overrides : mapping, optional
        ``{part: Layup | [(material, thickness_m, cells), ...]}``. A main-part key
        (``'superstructure'``) also applies to its sub-parts unless they are given too.
    superstructure_material : str
        Plate material of the default superstructure layup (``'aluminium_5083'`` option).
    """
    overrides = dict(overrides or {})
    for key in overrides:
        require(key in part_names or key in ("hull",) + tuple(_BY_MAIN), f"layups[{key!r}]",
                key, f"unknown part; parts are {', '.join(part_names)}")
    sup = (SUPERSTRUCTURE_LAYUP if superstructure_material == "mild_steel"
           else superstructure_layup(superstructure_material))
    out: dict[str, Layup] = {}
    for name in part_names:
        main = main_part(name)
        if name in overrides:
            out[name] = _as_layup(overrides[name], f"layups[{name!r}]")
            continue
        if main in overrides:
            out[name] = _as_layup(overrides[main], f"layups[{main!r}]")
        elif main in HULL_ALIASES and "hull" in overrides:
            out[name] = _as_layup(overrides["hull"], "layups['hull']")
        elif name == "superstructure_mast":
            out[name] = MAST_LAYUP
        elif main == "superstructure":
            out[name] = sup
        else:
            out[name] = _BY_MAIN[main]
    return out


def compartment_temperatures(part_names: Sequence[str], overrides: Mapping | None = None,
                             season: str = "winter") -> dict[str, float]:
    """Air temperature inside each part [K].

    Parameters
    ----------
    part_names : sequence of str
    overrides : mapping, optional
        ``{part: temperature [K]}``; a main-part key applies to its sub-parts too.
    season : {'winter', 'summer'}
        ISO 7547 indoor design condition used as default: 22 °C (winter), 27 °C (summer).
    """
    require(season in ISO7547_INDOOR_C, "season", season, "must be 'winter' or 'summer'")
    overrides = dict(overrides or {})
    base = ISO7547_INDOOR_C[season] + ZERO_CELSIUS
    out = {}
    for name in part_names:
        main = main_part(name)
        temp = overrides.get(name, overrides.get(main, base))
        check_range(f"compartment_temperature[{name!r}]", temp, 200.0, 400.0, "K")
        out[name] = float(temp)
    for key in overrides:
        require(key in out or key in _BY_MAIN, f"compartment_temperature[{key!r}]", key,
                f"unknown part; parts are {', '.join(part_names)}")
    return out


def outer_media(part_names: Sequence[str]) -> dict[str, str]:
    """What the outer face of each part sees: ``'sea'`` for the wetted hull, else ``'air'``."""
    return {name: ("sea" if main_part(name) == "hull_wetted" else "air") for name in part_names}
