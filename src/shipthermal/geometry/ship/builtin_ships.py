"""The built-in ships: a frigate (the default), a patrol boat and a cargo ship.

Particulars and their provenance are in each builder's docstring and in
``ShipParameters.provenance``; hull forms and superstructure layouts are generic.
"""

from __future__ import annotations

from typing import Sequence

from ..ship_geometry import ShipGeometry
from .build import build_ship
from .parameters import Block, ShipParameters

__all__ = ["frigate_parameters", "frigate", "patrol_boat_parameters", "patrol_boat",
           "cargo_ship_parameters", "cargo_ship", "BUILTIN_SHIPS"]


def frigate_parameters(length: float = 132.0, beam: float = 15.0, draught: float = 4.5,
                       freeboard: float = 5.0, blocks: Sequence[Block] | None = None) -> ShipParameters:
    """Parameters of the default frigate (blocks scale with the length unless given)."""
    k = length / 132.0
    kb = beam / 15.0
    default_blocks = (
        Block("superstructure_gun", 38 * k, 44 * k, 4.5 * kb, 2.6, incline_deg=20.0),
        Block("superstructure", 8 * k, 30 * k, 12.0 * kb, 5.6, incline_deg=8.0),      # fwd house
        Block("superstructure", 15 * k, 27 * k, 10.0 * kb, 3.0, base=5.6, incline_deg=8.0),  # bridge
        Block("superstructure_mast", 19 * k, 22.5 * k, 2.6 * kb, 12.0, base=8.6, incline_deg=3.0),
        Block("superstructure", -14 * k, 8.5 * k, 12.0 * kb, 5.6, incline_deg=8.0),  # midships
        Block("superstructure_funnel", -6 * k, 1 * k, 4.5 * kb, 5.0, base=5.6, incline_deg=6.0,
              top_shift_x=-1.0),
        Block("superstructure", -34 * k, -13.5 * k, 13.0 * kb, 6.6, incline_deg=8.0),  # hangar
    )
    return ShipParameters(
        name="frigate", length=length, beam=beam, draught=draught, freeboard=freeboard,
        sheer_bow=1.5, flare_deg=8.0, stem_rake_deg=30.0, bow_fraction=0.5, stern_fraction=0.35,
        transom_width=0.7, keel_rise=0.8, forefoot=0.3, section_mid=2.0, section_bow=1.6,
        blocks=tuple(default_blocks if blocks is None else blocks),
        provenance=("Frigate of the size of the Type 054A Jiangkai II (about 134 m x 16 m x 5 m), "
                    "the Type 23 Duke class (about 133 m x 16.1 m) and FREMM (about 142-144 m x "
                    "19.7-20 m x 5 m), approximate published particulars (Jane's Fighting Ships, "
                    "class articles); rounded to 132 m overall, 15 m beam, 4.5 m hull draught "
                    "(no sonar dome), 5 m freeboard amidships. Hull form and superstructure layout are generic."))


def frigate(edge_length: float | None = None, length: float = 132.0, beam: float = 15.0,
            draught: float = 4.5, freeboard: float = 5.0, blocks: Sequence[Block] | None = None,
            **kwargs) -> ShipGeometry:
    """The default built-in ship: a ~132 m frigate (see :func:`frigate_parameters`).

    Extra keyword arguments go to :func:`build_ship` (``layups``, ``compartment_temperature``,
    ``superstructure_material``).
    """
    return build_ship(frigate_parameters(length, beam, draught, freeboard, blocks), edge_length, **kwargs)


def patrol_boat_parameters(length: float = 56.0, beam: float = 9.5, draught: float = 2.7,
                           freeboard: float = 3.0) -> ShipParameters:
    k = length / 56.0
    kb = beam / 9.5
    return ShipParameters(
        name="patrol_boat", length=length, beam=beam, draught=draught, freeboard=freeboard,
        sheer_bow=1.0, flare_deg=10.0, stem_rake_deg=35.0, bow_fraction=0.5, stern_fraction=0.35,
        transom_width=0.7, keel_rise=0.8, forefoot=0.4, section_mid=2.0, section_bow=1.3,
        blocks=(
            Block("superstructure_gun", 17 * k, 19.5 * k, 1.8 * kb, 1.4, incline_deg=15.0),
            Block("superstructure", 0 * k, 14 * k, 7.0 * kb, 2.6, incline_deg=10.0),
            Block("superstructure", 4 * k, 12 * k, 6.0 * kb, 2.4, base=2.6, incline_deg=10.0),
            Block("superstructure_mast", 7 * k, 8.6 * k, 1.2 * kb, 6.0, base=5.0, incline_deg=3.0),
            Block("superstructure_funnel", -4 * k, -1.5 * k, 2.0 * kb, 3.0, incline_deg=5.0,
                  top_shift_x=-0.5),
        ),
        provenance=("Patrol boat of the size of the Armidale class (56.8 m x 9.5 m x 2.7 m, "
                    "published particulars); rounded to 56 m overall. Generic hull form."))


def patrol_boat(edge_length: float | None = None, **kwargs) -> ShipGeometry:
    """A ~56 m patrol boat (see :func:`patrol_boat_parameters`)."""
    dims = {k: kwargs.pop(k) for k in ("length", "beam", "draught", "freeboard") if k in kwargs}
    return build_ship(patrol_boat_parameters(**dims), edge_length, **kwargs)


def cargo_ship_parameters(length: float = 180.0, beam: float = 30.0, draught: float = 10.0,
                          freeboard: float = 5.5) -> ShipParameters:
    k = length / 180.0
    kb = beam / 30.0
    return ShipParameters(
        name="cargo_ship", length=length, beam=beam, draught=draught, freeboard=freeboard,
        sheer_bow=2.0, flare_deg=0.0, stem_rake_deg=20.0, bow_fraction=0.2, stern_fraction=0.2,
        transom_width=0.6, keel_rise=0.85, forefoot=0.2, section_mid=10.0, section_bow=2.5,
        blocks=(
            Block("superstructure", -80 * k, -66 * k, 20.0 * kb, 14.0),               # accommodation
            Block("superstructure", -78 * k, -68 * k, 24.0 * kb, 3.0, base=14.0),     # wheelhouse
            Block("superstructure_mast", -74 * k, -72.5 * k, 1.5 * kb, 6.0, base=17.0, incline_deg=2.0),
            Block("superstructure_funnel", -88 * k, -81.5 * k, 7.0 * kb, 20.0, incline_deg=2.0,
                  top_shift_x=-1.0),
        ),
        provenance=("Handymax bulk carrier of typical particulars (LOA 180 m, beam 30 m, design "
                    "draught 10 m, deck house aft), cf. Handymax/Supramax class ranges (LOA "
                    "150-200 m, 40-60 kt DWT). Generic hull form."))


def cargo_ship(edge_length: float | None = None, **kwargs) -> ShipGeometry:
    """A ~180 m cargo ship (see :func:`cargo_ship_parameters`)."""
    dims = {k: kwargs.pop(k) for k in ("length", "beam", "draught", "freeboard") if k in kwargs}
    return build_ship(cargo_ship_parameters(**dims), edge_length, **kwargs)


BUILTIN_SHIPS = {"frigate": frigate, "patrol_boat": patrol_boat, "cargo_ship": cargo_ship}
"""Built-in ship builders by name."""
