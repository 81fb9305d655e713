"""Particulars and hull-form parameters of a parametric ship, and its superstructure blocks.

Lengths [m], angles [deg], fractions of length or breadth [-]; x forward, 0 amidships.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...errors import check_positive, check_range, require
from ..parts import main_part

__all__ = ["Block", "ShipParameters", "DEFAULT_EDGE_LENGTH"]

DEFAULT_EDGE_LENGTH = 0.5
"""Default target surface edge length of the built-in frigate [m] (≈ 60 000 triangles)."""


@dataclass(frozen=True)
class Block:
    """A convex superstructure block (frustum) standing on the deck or on another block.

    Parameters
    ----------
    part : str
        Part name (``'superstructure'`` or ``'superstructure_<detail>'``).
    x_aft, x_fore : float
        Longitudinal extent of the footprint [m] (x forward, 0 amidships).
    width : float
        Athwartships width of the footprint [m].
    height : float
        Height of the block [m].
    base : float
        0: the block stands on the deck. > 0: it is stacked on the top of the highest
        earlier block under its centre (or, if there is none, stands ``base`` metres above
        the deck) [m].
    incline_deg : float
        Inward inclination of the side and end walls from vertical [deg] (stealthy
        deckhouses ≈ 8–10°, a mast ≈ 3°).
    top_shift_x : float
        Longitudinal shift of the top face [m] (negative: raked aft, as funnels are).
    """

    part: str
    x_aft: float
    x_fore: float
    width: float
    height: float
    base: float = 0.0
    incline_deg: float = 0.0
    top_shift_x: float = 0.0


@dataclass(frozen=True)
class ShipParameters:
    """Particulars and hull-form parameters of a parametric ship.

    Lengths [m], angles [deg], fractions of length or breadth [-].

    Parameters
    ----------
    name : str
    length : float
        Length overall at the deck [m].
    beam : float
        Maximum beam at the deck edge [m].
    draught : float
        Keel depth below the waterline amidships [m].
    freeboard : float
        Deck height above the waterline amidships [m].
    sheer_bow : float
        Extra deck height at the stem [m] (parabolic over the fore 35 % of the length).
    flare_deg : float
        Flare of the topsides amidships (outward from vertical) [deg].
    stem_rake_deg : float
        Rake of the stem from vertical [deg].
    bow_fraction, stern_fraction : float
        Fractions of the length over which the hull narrows to the stem / transom.
    transom_width : float
        Half-breadth at the transom as a fraction of the maximum.
    keel_rise : float
        Rise of the keel at the transom as a fraction of the draught (immersed transom
        depth = (1 - keel_rise)·draught).
    forefoot : float
        Rise of the keel at the stem as a fraction of the draught.
    section_mid, section_bow : float
        Superellipse exponents of the underwater sections amidships (2 ellipse, ≫2 boxy)
        and at the stem.
    blocks : tuple of Block
        Superstructure.
    provenance : str
        Source of the particulars.
    """

    name: str
    length: float
    beam: float
    draught: float
    freeboard: float
    sheer_bow: float = 1.5
    flare_deg: float = 8.0
    stem_rake_deg: float = 30.0
    bow_fraction: float = 0.3
    stern_fraction: float = 0.15
    transom_width: float = 0.8
    keel_rise: float = 0.7
    forefoot: float = 0.3
    section_mid: float = 3.0
    section_bow: float = 1.6
    blocks: tuple[Block, ...] = ()
    provenance: str = ""

    def validate(self) -> None:
        for attr in ("length", "beam", "draught", "freeboard"):
            check_positive(f"{self.name}.{attr}", getattr(self, attr), "m")
        check_range(f"{self.name}.length", self.length, 5.0, 500.0, "m")
        require(self.beam < 0.5 * self.length, f"{self.name}.beam", self.beam,
                f"must be below half the length ({0.5 * self.length:g} m)")
        require(self.draught < self.beam, f"{self.name}.draught", self.draught,
                f"must be below the beam ({self.beam:g} m)")
        check_range(f"{self.name}.sheer_bow", self.sheer_bow, 0.0, 0.1 * self.length, "m")
        check_range(f"{self.name}.flare_deg", self.flare_deg, 0.0, 30.0, "deg")
        check_range(f"{self.name}.stem_rake_deg", self.stem_rake_deg, 0.0, 60.0, "deg")
        check_range(f"{self.name}.bow_fraction", self.bow_fraction, 0.05, 0.6)
        check_range(f"{self.name}.stern_fraction", self.stern_fraction, 0.0, 0.4)
        require(self.bow_fraction + self.stern_fraction < 0.9, f"{self.name}.bow_fraction",
                self.bow_fraction, "bow_fraction + stern_fraction must be < 0.9")
        check_range(f"{self.name}.transom_width", self.transom_width, 0.05, 1.0)
        check_range(f"{self.name}.keel_rise", self.keel_rise, 0.0, 0.95)
        check_range(f"{self.name}.forefoot", self.forefoot, 0.0, 0.9)
        check_range(f"{self.name}.section_mid", self.section_mid, 1.0, 30.0)
        check_range(f"{self.name}.section_bow", self.section_bow, 1.0, 30.0)
        topside = self.freeboard * math.tan(math.radians(self.flare_deg))
        require(topside < 0.45 * self.beam, f"{self.name}.flare_deg", self.flare_deg,
                "too much flare for this beam and freeboard (waterline beam would vanish)")
        for i, b in enumerate(self.blocks):
            fld = f"{self.name}.blocks[{i}]"
            require(isinstance(b, Block), fld, b, "must be a Block")
            main_part(b.part)
            require(main_part(b.part) == "superstructure", f"{fld}.part", b.part,
                    "must be 'superstructure' or 'superstructure_<detail>'")
            require(b.x_fore > b.x_aft, f"{fld}.x_fore", b.x_fore, f"must exceed x_aft ({b.x_aft:g} m)")
            check_positive(f"{fld}.width", b.width, "m")
            check_positive(f"{fld}.height", b.height, "m")
            check_range(f"{fld}.base", b.base, 0.0, 100.0, "m")
            check_range(f"{fld}.incline_deg", b.incline_deg, 0.0, 45.0, "deg")
            shrink = 2 * b.height * math.tan(math.radians(b.incline_deg))
            require(shrink < min(b.width, b.x_fore - b.x_aft), f"{fld}.incline_deg", b.incline_deg,
                    "walls meet below the top: lower the inclination or the height")
            require(-0.5 * self.length < b.x_aft and b.x_fore < 0.5 * self.length, f"{fld}.x_aft",
                    (b.x_aft, b.x_fore), f"footprint must lie within ±{0.5 * self.length:g} m")

