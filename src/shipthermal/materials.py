"""Materials and plate layups.

Material properties are named data with their source, in the spirit of pvlib's
``TEMPERATURE_MODEL_PARAMETERS``. Values are for room temperature (about 20 °C), which
is adequate over the diurnal range of a ship's skin (roughly -20 … +70 °C): the
temperature dependence of k and c of carbon steel over that range is below 5 %
(EN 1993-1-2 §3.4).

A :class:`Layup` is an ordered stack of :class:`Layer` from the **outer** surface
inwards, e.g. paint / steel / mineral wool. Shell meshes extrude a surface through it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

from .errors import InputError, check_positive, check_range, require

__all__ = ["Material", "MATERIALS", "MATERIAL_RANGES", "get_material", "Layer", "Layup"]

MATERIAL_RANGES = {"conductivity": (1.0e-3, 500.0, "W m-1 K-1"),
                   "density": (1.0, 23000.0, "kg m-3"),
                   "specific_heat": (100.0, 5000.0, "J kg-1 K-1")}
"""Accepted range of each property of a material [unit]. ASSUMPTION bracketing the solids
(and the liquids a layer could hold) of engineering use, with Incropera et al., 6th ed.,
Tables A.1–A.3 at 300 K as the anchors: conductivity from vacuum insulation panels and
aerogels (0.004–0.02) to silver (429); density from aerogels and foams (a few kg m-3) to
the densest metals (osmium 22 590); specific heat from lead and tungsten (129, 132) to water
(4 179). A value outside is a unit mistake (k in mW m-1 K-1, c in kJ kg-1 K-1, ρ in
g cm-3)."""

_UNIT_HINTS = {"conductivity": "k in W m-1 K-1 (steel ~50, paint ~0.2, mineral wool ~0.04)",
               "density": "rho in kg m-3 (steel 7850; not g cm-3)",
               "specific_heat": "c in J kg-1 K-1 (steel ~450; not kJ kg-1 K-1)"}


@dataclass(frozen=True)
class Material:
    """An isotropic solid.

    Parameters
    ----------
    name : str
        Key in :data:`MATERIALS`.
    density : float
        Mass density ρ [kg m-3].
    specific_heat : float
        Specific heat capacity c [J kg-1 K-1].
    conductivity : float
        Thermal conductivity k [W m-1 K-1].
    source : str
        Where the numbers come from.
    """

    name: str
    density: float
    specific_heat: float
    conductivity: float
    source: str = ""

    def __post_init__(self):
        for attr, (lo, hi, unit) in MATERIAL_RANGES.items():
            field = f"material[{self.name!r}].{attr}"
            check_positive(field, getattr(self, attr), unit)
            try:
                check_range(field, getattr(self, attr), lo, hi, unit)
            except InputError as exc:
                raise InputError(exc.field, exc.value, exc.allowed,
                                 f"Give {_UNIT_HINTS[attr]}") from None

    @property
    def volumetric_heat_capacity(self) -> float:
        """ρ·c [J m-3 K-1]."""
        return self.density * self.specific_heat

    @property
    def diffusivity(self) -> float:
        """Thermal diffusivity k/(ρc) [m2 s-1]."""
        return self.conductivity / self.volumetric_heat_capacity


MATERIALS: dict[str, Material] = {m.name: m for m in (
    Material("mild_steel", 7850.0, 440.0, 53.3,
             "EN 1993-1-2:2005 §3.4 carbon steel at 20 °C: ρ = 7850, "
             "c = 425 + 0.773θ - 1.69e-3θ² + 2.22e-6θ³ = 439.8, k = 54 - 3.33e-2θ = 53.3"),
    Material("aluminium_5083", 2660.0, 900.0, 117.0,
             "Aluminum Association, Aluminum Standards and Data (2009) / ASM Handbook "
             "vol. 2: alloy 5083-O at 25 °C, ρ = 2660, c = 900, k = 117"),
    Material("mineral_wool", 100.0, 1030.0, 0.037,
             "ISO 10456:2007 Table 3, mineral wool: c = 1030; ρ = 100 and declared "
             "λ = 0.037 for marine A-60 slabs (typical manufacturer data sheets)"),
    Material("deck_covering", 1200.0, 1400.0, 0.20,
             "ISO 10456:2007 Table 3, epoxy resin (non-skid deck coverings are "
             "epoxy-based): ρ = 1200, λ = 0.20, c = 1400"),
    Material("marine_paint", 1200.0, 1800.0, 0.25,
             "ISO 10456:2007 Table 3, polyurethane solid (polyurethane/epoxy marine "
             "topcoat, dry film): ρ = 1200, λ = 0.25, c = 1800"),
    Material("sea_water", 1024.8, 3993.0, 0.596,
             "Sharqawy, Lienhard & Zubair (2010), Desalination and Water Treatment 16, "
             "354-380: S = 35 g/kg, 20 °C"),
    Material("air", 1.1614, 1007.0, 0.0263,
             "Incropera et al., Fundamentals of Heat and Mass Transfer, 6th ed., "
             "Table A.4, air at 300 K"),
)}
"""Built-in materials, keyed by name."""


def get_material(name: str | Material, field: str = "material",
                 table: Mapping[str, Material] | None = None) -> Material:
    """Look a material up by name; a :class:`Material` passes through.

    Raises :class:`InputError` naming the known materials when the name is unknown.
    """
    if isinstance(name, Material):
        return name
    table = MATERIALS if table is None else table
    if name not in table:
        raise InputError(field, name, f"unknown material; known: {', '.join(sorted(table))}",
                         "Use one of the known names or pass a Material(...)")
    return table[name]


@dataclass(frozen=True)
class Layer:
    """One layer of a plate layup.

    Parameters
    ----------
    material : str or Material
        Material name in :data:`MATERIALS` or a :class:`Material`.
    thickness : float
        Layer thickness [m].
    cells : int
        Number of finite-volume cells through the layer (≥ 1).
    """

    material: str | Material
    thickness: float
    cells: int = 1


@dataclass(frozen=True)
class Layup:
    """An ordered stack of layers, from the outer surface inwards.

    Validated on construction: every thickness > 0, cells ≥ 1, materials known.
    """

    layers: tuple[Layer, ...]
    name: str = "layup"

    def __post_init__(self):
        layers = tuple(self.layers)
        object.__setattr__(self, "layers", layers)
        require(len(layers) > 0, f"{self.name}.layers", layers, "must hold at least one layer")
        resolved = []
        for i, layer in enumerate(layers):
            field = f"{self.name}[{i}]"
            require(isinstance(layer, Layer), field, layer, "must be a Layer(material, thickness, cells)")
            check_positive(f"{field}.thickness", layer.thickness, "m")
            require(isinstance(layer.cells, (int,)) and not isinstance(layer.cells, bool) and layer.cells >= 1,
                    f"{field}.cells", layer.cells, "must be an integer ≥ 1")
            resolved.append(get_material(layer.material, f"{field}.material"))
        object.__setattr__(self, "_materials", tuple(resolved))

    @classmethod
    def from_list(cls, layers: Sequence, name: str = "layup") -> "Layup":
        """Build from ``[(material, thickness_m, cells), ...]`` or dicts with those keys."""
        out = []
        for i, item in enumerate(layers):
            if isinstance(item, Layer):
                out.append(item)
            elif isinstance(item, Mapping):
                unknown = set(item) - {"material", "thickness", "cells"}
                require(not unknown, f"{name}[{i}]", sorted(unknown),
                        "unknown keys; allowed: material, thickness, cells")
                out.append(Layer(item.get("material"), item.get("thickness"), item.get("cells", 1)))
            else:
                require(len(item) in (2, 3), f"{name}[{i}]", item,
                        "must be (material, thickness_m[, cells])")
                out.append(Layer(*item))
        return cls(tuple(out), name=name)

    @property
    def materials(self) -> tuple[Material, ...]:
        """Resolved :class:`Material` of each layer."""
        return self._materials  # type: ignore[attr-defined]

    @property
    def thickness(self) -> float:
        """Total thickness [m]."""
        return float(sum(layer.thickness for layer in self.layers))

    @property
    def areal_mass(self) -> float:
        """Mass per unit area Σρ·t [kg m-2]."""
        return float(sum(m.density * l.thickness for m, l in zip(self.materials, self.layers)))

    @property
    def areal_heat_capacity(self) -> float:
        """Heat capacity per unit area Σρ·c·t [J m-2 K-1]."""
        return float(sum(m.volumetric_heat_capacity * l.thickness
                         for m, l in zip(self.materials, self.layers)))

    @property
    def thermal_resistance(self) -> float:
        """Through-thickness conduction resistance Σt/k [m2 K W-1]."""
        return float(sum(l.thickness / m.conductivity for m, l in zip(self.materials, self.layers)))
