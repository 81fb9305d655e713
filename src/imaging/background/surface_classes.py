"""Background surface classes of the port: the physical parameters of each land class.

Named, sourced data in the style of pvlib's ``TEMPERATURE_MODEL_PARAMETERS``: class name →
:class:`SurfaceClass` (short-wave albedo with the range a per-pixel fit may use, broadband
long-wave emissivity, the layers of its column from the surface down, the bottom boundary, the
latent-heat model and the aerodynamic roughness). The class codes and names are those of the
class map (:data:`imaging.background.classify.CLASS_NAMES`); water (code 1) is not a land
class: the sea skin model handles it.

Every number carries its source and a label in :attr:`SurfaceClass.sources`:
``SOURCED`` (taken from the reference named), ``DERIVED`` (computed from sourced numbers, the
computation stated) or ``ASSUMPTION`` (a choice, with the range it was chosen in).

References
----------
.. [1] Oke, T. R. (1987), *Boundary Layer Climates*, 2nd ed., Routledge. Radiative
   properties of natural and urban materials (albedo, emissivity: asphalt 0.05–0.20 / 0.95,
   tar-and-gravel roof 0.08–0.18 / 0.92, grass 0.16–0.26 / 0.90–0.95); Table 2.1 thermal
   properties of natural materials (sandy soil, dry and saturated).
.. [2] Allen, R. G., Pereira, L. S., Raes, D. & Smith, M. (1998), *Crop evapotranspiration*,
   FAO Irrigation and Drainage Paper 56 (FAO-56): reference grass (h = 0.12 m, r_s = 70
   s m-1, albedo 0.23), eq. 4 (aerodynamic resistance, z_om = 0.123 h, z_oh = 0.1 z_om,
   d = 2/3 h), eq. 5 (bulk surface resistance).
.. [3] Deru, M. et al. (2011), *U.S. Department of Energy commercial reference building
   models of the national building stock*, NREL/TP-5500-46861: material records (from the
   ASHRAE Handbook of Fundamentals) "Roof Membrane", "MAT-CC05 4 HW CONCRETE", "IEAD NonRes
   Roof Insulation".
.. [4] ISO 6946:2017, *Building components and building elements — Thermal resistance and
   thermal transmittance*, Table 7: R_si = 0.17 m2 K W-1 for downward heat flow.
.. [5] Garratt, J. R. (1992), *The Atmospheric Boundary Layer*, Cambridge University Press,
   §4.2: ln(z_0m / z_0h) ≈ 2 for bluff-rough and vegetated surfaces (z_0h ≈ z_0m / 10, as in
   FAO-56).
.. [6] Wieringa, J. (1993), "Representative roughness parameters for homogeneous terrain",
   Boundary-Layer Meteorol. 63, 323–363.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from shipthermal.errors import InputError

from .classify import CLASS_NAMES

__all__ = [
    "Layer",
    "SurfaceClass",
    "SURFACE_CLASSES",
    "BOTTOMS",
    "LATENT_MODELS",
    "PHYSICAL_RANGES",
    "LABELS",
    "surface_class",
    "apply_overrides",
]

BOTTOMS = ("deep", "room")
"""Bottom boundaries of a column: ``'deep'`` a fixed deep-ground temperature at the column's
bottom face (Dirichlet), ``'room'`` an indoor air space at a room temperature, reached through
the class's surface film coefficient. Both temperatures are supplied by the caller."""

LATENT_MODELS = ("none", "penman_monteith")
"""Latent-heat models: ``'none'`` (dry paving, roofs) or the Penman–Monteith resistance form
``λE = (ρ c_p / γ) (e_sat(T_s) − e_a) / (r_a + r_s)`` (vegetation)."""

LABELS = ("SOURCED", "DERIVED", "ASSUMPTION")

PHYSICAL_RANGES: dict[str, tuple[float, float, str]] = {
    "albedo": (0.0, 1.0, "-"),
    "emissivity": (0.5, 1.0, "-"),
    "thickness": (1.0e-4, 10.0, "m"),
    "conductivity": (0.005, 500.0, "W m-1 K-1"),
    "density": (1.0, 25000.0, "kg m-3"),
    "specific_heat": (100.0, 5000.0, "J kg-1 K-1"),
    "room_film_coefficient": (0.5, 100.0, "W m-2 K-1"),
    "surface_resistance": (0.0, 5000.0, "s m-1"),
    "roughness_length": (1.0e-6, 5.0, "m"),
    "roughness_length_heat": (1.0e-7, 5.0, "m"),
    "displacement_height": (0.0, 50.0, "m"),
    "code": (1, 255, "-"),
}
"""What a user value may be, per field: (low, high, unit). Wide physical bounds (an
insulation board to a metal, a gas film to a lead slab), not the typical ranges."""


@dataclass(frozen=True)
class Layer:
    """One homogeneous layer of a column.

    Attributes
    ----------
    name : str
        Material name.
    thickness : float
        [m].
    conductivity : float
        Thermal conductivity k [W m-1 K-1].
    density : float
        ρ [kg m-3].
    specific_heat : float
        c [J kg-1 K-1].
    source : str
        ``LABEL: reference`` of the four numbers.
    """

    name: str
    thickness: float
    conductivity: float
    density: float
    specific_heat: float
    source: str = ""

    @property
    def heat_capacity(self) -> float:
        """Volumetric heat capacity ρ c [J m-3 K-1]."""
        return self.density * self.specific_heat

    @property
    def diffusivity(self) -> float:
        """k / (ρ c) [m2 s-1]."""
        return self.conductivity / self.heat_capacity


@dataclass(frozen=True)
class SurfaceClass:
    """Physical parameters of one background surface class.

    Attributes
    ----------
    code : int
        Class code in the class map (:data:`~imaging.background.classify.CLASS_NAMES`).
    name : str
        Class name.
    albedo : float
        Broadband short-wave albedo [-].
    albedo_range : tuple of float
        Physical range of the albedo [-] (a per-pixel fit to a Landsat LST stays inside it).
    emissivity : float
        Broadband long-wave emissivity [-] (also the long-wave absorptivity, Kirchhoff).
    layers : tuple of Layer
        The column from the surface down.
    bottom : {'deep', 'room'}
        Bottom boundary (:data:`BOTTOMS`).
    room_film_coefficient : float or None
        Combined convective + radiative film coefficient of the room side [W m-2 K-1]
        (``bottom == 'room'`` only).
    latent : {'none', 'penman_monteith'}
        Latent-heat model (:data:`LATENT_MODELS`).
    surface_resistance : float or None
        Bulk surface (canopy) resistance r_s [s m-1] (``latent == 'penman_monteith'``).
    surface_resistance_range : tuple of float or None
        Its plausible range [s m-1].
    roughness_length : float
        Aerodynamic roughness length for momentum z_0m [m].
    roughness_length_heat : float
        Roughness length for heat and vapour z_0h [m].
    displacement_height : float
        Zero-plane displacement d [m].
    sources : Mapping[str, str]
        Field → ``LABEL: reference`` for every number above.
    """

    code: int
    name: str
    albedo: float
    albedo_range: tuple
    emissivity: float
    layers: tuple
    bottom: str
    room_film_coefficient: float | None
    latent: str
    surface_resistance: float | None
    surface_resistance_range: tuple | None
    roughness_length: float
    roughness_length_heat: float
    displacement_height: float
    sources: Mapping = dataclasses.field(default_factory=dict)

    @property
    def depth(self) -> float:
        """Total thickness of the column [m]."""
        return sum(layer.thickness for layer in self.layers)

    @property
    def thermal_resistance(self) -> float:
        """Conduction resistance of the layers Σ d/k [m2 K W-1]."""
        return sum(layer.thickness / layer.conductivity for layer in self.layers)


# ---------------------------------------------------------------------------------------------
# Materials
# ---------------------------------------------------------------------------------------------
_ASPHALT = Layer(
    "asphalt wearing course", 0.05, 1.20, 2300.0, 920.0,
    "ASSUMPTION: dense-graded asphalt concrete; measured k spans about 0.7-2.0 W m-1 K-1 with "
    "the aggregate and ρ 2200-2450 kg m-3, c 850-1000 J kg-1 K-1; mid values chosen, "
    "thickness a typical 5 cm surface course")
_CONCRETE_BASE = Layer(
    "concrete base", 0.20, 1.311, 2240.0, 836.8,
    "SOURCED: heavy-weight concrete of [3] (record '8IN CONCRETE HW': k 1.311, ρ 2240, "
    "c 836.8); thickness ASSUMPTION: a 20 cm slab or cement-bound base of port pavements")
_SOIL_MOIST = Layer(
    "moist sandy soil", 0.75, 1.25, 1800.0, 1180.0,
    "DERIVED: midway between dry and saturated sandy soil of [1] Table 2.1 (k 0.30 and 2.20 "
    "W m-1 K-1; ρ 1600 and 2000 kg m-3; ρc 1.28e6 and 2.96e6 J m-3 K-1 → ρ 1800, c = 2.12e6/1800)")
_SUBSOIL_MOIST = dataclasses.replace(_SOIL_MOIST, name="moist sandy soil", thickness=0.95)
_THATCH = Layer(
    "grass canopy and root mat", 0.03, 0.30, 600.0, 2500.0,
    "ASSUMPTION: a 3 cm layer standing for the grass canopy, thatch and rooted top soil "
    "(leaves, still air and wet organic matter: k between still air 0.025 and wet peat 0.5, "
    "ρc 1.5e6 J m-3 K-1 between dry and wet organic soil of [1] Table 2.1)")
_MEMBRANE = Layer("roof membrane", 0.0095, 0.16, 1121.29, 1460.0,
                  "SOURCED: [3] record 'Roof Membrane'")
_DECK = Layer("concrete deck", 0.1016, 1.311, 2240.0, 836.8,
              "SOURCED: [3] record 'MAT-CC05 4 HW CONCRETE'")
_INSULATION = Layer("roof insulation", 0.127, 0.049, 265.0, 836.8,
                    "SOURCED: [3] record 'IEAD NonRes Roof Insulation' (k, ρ, c; thickness "
                    "0.1273 m in the Chicago 2004 model, rounded)")

SURFACE_CLASSES: Mapping[str, SurfaceClass] = MappingProxyType({
    "vegetation": SurfaceClass(
        code=2, name="vegetation", albedo=0.23, albedo_range=(0.16, 0.26), emissivity=0.95,
        layers=(_THATCH, _SUBSOIL_MOIST), bottom="deep", room_film_coefficient=None,
        latent="penman_monteith", surface_resistance=70.0,
        surface_resistance_range=(30.0, 1000.0),
        roughness_length=0.123 * 0.12, roughness_length_heat=0.1 * 0.123 * 0.12,
        displacement_height=2.0 / 3.0 * 0.12,
        sources=MappingProxyType({
            "albedo": "SOURCED: [2] reference grass albedo 0.23 (eq. 38)",
            "albedo_range": "SOURCED: [1] grass, long (1.0 m) 0.16 to short (0.02 m) 0.26",
            "emissivity": "SOURCED: [1] grass 0.90-0.95 (upper end)",
            "layers": "see each layer",
            "bottom": "ASSUMPTION: 1 m column, deep-ground temperature below the diurnal wave "
                      "(damping depth of moist soil ≈ 0.1 m)",
            "latent": "SOURCED: [2] eq. 3, resistance form, unlimited water (irrigated grass)",
            "surface_resistance": "SOURCED: [2] eq. 5 / reference grass r_s = 70 s m-1",
            "surface_resistance_range": "ASSUMPTION: 30 s m-1 (well-watered dense crop) to "
                                        "1000 s m-1 (water-stressed, senescent lawn)",
            "roughness_length": "DERIVED: [2] eq. 4, z_om = 0.123 h, h = 0.12 m",
            "roughness_length_heat": "DERIVED: [2] eq. 4, z_oh = 0.1 z_om",
            "displacement_height": "DERIVED: [2] eq. 4, d = 2/3 h",
        })),
    "land": SurfaceClass(
        code=3, name="land", albedo=0.12, albedo_range=(0.05, 0.35), emissivity=0.95,
        layers=(_ASPHALT, _CONCRETE_BASE, _SOIL_MOIST), bottom="deep",
        room_film_coefficient=None, latent="none", surface_resistance=None,
        surface_resistance_range=(50.0, 5000.0), roughness_length=0.005,
        roughness_length_heat=0.0005, displacement_height=0.0,
        sources=MappingProxyType({
            "surface_resistance_range": "ASSUMPTION: dry by default; a scene may show it "
                                        "damp (wet paving after rain, wet intertidal sand "
                                        "classed as land): fitted between 50 s m-1 (between "
                                        "a wet bare soil's ~10 s m-1, van de Griend & Owe "
                                        "1994, and grass's 70) and 5000 s m-1 (about 1 % of "
                                        "the potential evaporation: dry)",
            "albedo": "ASSUMPTION: weathered asphalt, inside [1] asphalt 0.05-0.20",
            "albedo_range": "SOURCED: [1] asphalt 0.05-0.20 and concrete 0.10-0.35 (paved "
                            "yards of either)",
            "emissivity": "SOURCED: [1] asphalt 0.95",
            "layers": "see each layer",
            "bottom": "ASSUMPTION: 1 m column, deep-ground temperature below the diurnal wave",
            "latent": "ASSUMPTION: dry paving (no evaporation)",
            "roughness_length": "ASSUMPTION: paved yard with kerbs and small clutter; [6] gives "
                                "2e-4-5e-4 m for concrete and flat desert, larger for obstacles",
            "roughness_length_heat": "SOURCED: [5] z_0h = z_0m / 10",
            "displacement_height": "ASSUMPTION: none for a flat pavement",
        })),
    "building": SurfaceClass(
        code=4, name="building", albedo=0.30, albedo_range=(0.08, 0.80), emissivity=0.90,
        layers=(_MEMBRANE, _DECK, _INSULATION), bottom="room",
        room_film_coefficient=1.0 / 0.17, latent="none", surface_resistance=None,
        surface_resistance_range=None, roughness_length=0.005, roughness_length_heat=0.0005,
        displacement_height=0.0,
        sources=MappingProxyType({
            "albedo": "SOURCED: [3] roof membrane solar absorptance 0.70",
            "albedo_range": "SOURCED low: [1] tar-and-gravel roof 0.08; ASSUMPTION high: a "
                            "white single-ply membrane 0.80",
            "emissivity": "SOURCED: [3] roof membrane thermal absorptance 0.90 ([1] tar and "
                          "gravel 0.92)",
            "layers": "see each layer (membrane + deck + insulation, the deck above the "
                      "insulation)",
            "bottom": "ASSUMPTION: flat roof over a conditioned or sheltered indoor space",
            "room_film_coefficient": "SOURCED: [4] R_si = 0.17 m2 K W-1 (downward heat flow, "
                                     "the daytime case a thermal image sees)",
            "latent": "ASSUMPTION: dry roof",
            "roughness_length": "ASSUMPTION: as paved land (flat roof with parapets, kit)",
            "roughness_length_heat": "SOURCED: [5] z_0h = z_0m / 10",
            "displacement_height": "ASSUMPTION: heights taken from the roof",
        })),
})
"""Land background classes by name (codes of
:data:`~imaging.background.classify.CLASS_NAMES`); water is the sea skin model's."""


def surface_class(name: str, classes: Mapping[str, SurfaceClass] = SURFACE_CLASSES,
                  field: str = "background.classes") -> SurfaceClass:
    """Look a class up by name; an unknown name raises :class:`InputError` listing the known
    ones (and says where water went)."""
    if name in classes:
        return classes[name]
    fix = ("water is not a land class: the sea skin model computes it" if name == "water"
           else "Add it under [background.classes.NAME] with every property")
    raise InputError(f"{field}.{name}", name, f"must be one of {', '.join(classes)}", fix)


# ---------------------------------------------------------------------------------------------
# User overrides
# ---------------------------------------------------------------------------------------------
_SCALAR_FIELDS = ("code", "albedo", "emissivity", "room_film_coefficient", "surface_resistance",
                  "roughness_length", "roughness_length_heat", "displacement_height")
_FIELDS = _SCALAR_FIELDS + ("albedo_range", "surface_resistance_range", "layers", "bottom",
                            "latent")
_LAYER_FIELDS = ("thickness", "conductivity", "density", "specific_heat")


def _number(field: str, value, key: str) -> float:
    low, high, unit = PHYSICAL_RANGES[key]
    unit = "" if unit == "-" else f" {unit}"
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(field, value, f"must be a finite number in [{low:g}, {high:g}]{unit}")
    if not low <= value <= high:
        raise InputError(field, value, f"must lie in [{low:g}, {high:g}]{unit}",
                         "Check the unit (SI: m, W m-1 K-1, kg m-3, J kg-1 K-1, s m-1)"
                         if unit else "")
    return float(value)


def _pair(field: str, value, key: str) -> tuple:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise InputError(field, value, "must be a pair [low, high]")
    low = _number(f"{field}[0]", value[0], key)
    high = _number(f"{field}[1]", value[1], key)
    if low > high:
        raise InputError(field, value, "must have low <= high")
    return (low, high)


def _layers(field: str, value) -> tuple:
    if not isinstance(value, (list, tuple)) or not value:
        raise InputError(field, value, "must be a non-empty list of layers (surface first), "
                         "each with thickness, conductivity, density, specific_heat")
    out = []
    for i, item in enumerate(value):
        f = f"{field}[{i}]"
        if isinstance(item, Layer):
            item = dataclasses.asdict(item)
        if not isinstance(item, Mapping):
            raise InputError(f, item, "must be a table with thickness, conductivity, density, "
                             "specific_heat (and optionally name, source)")
        unknown = set(item) - set(_LAYER_FIELDS) - {"name", "source"}
        if unknown:
            raise InputError(f"{f}.{sorted(unknown)[0]}", item[sorted(unknown)[0]],
                             f"is not a layer property; allowed: {', '.join(_LAYER_FIELDS)}, "
                             "name, source")
        missing = [k for k in _LAYER_FIELDS if k not in item]
        if missing:
            raise InputError(f"{f}.{missing[0]}", None, "is required for every layer")
        nums = {k: _number(f"{f}.{k}", item[k], k) for k in _LAYER_FIELDS}
        out.append(Layer(str(item.get("name", f"layer {i}")), nums["thickness"],
                         nums["conductivity"], nums["density"], nums["specific_heat"],
                         str(item.get("source", "user input"))))
    return tuple(out)


def _validate_class(field: str, cls: SurfaceClass) -> None:
    """Cross-field checks of a complete class."""
    if not cls.albedo_range[0] <= cls.albedo <= cls.albedo_range[1]:
        raise InputError(f"{field}.albedo", cls.albedo,
                         f"must lie inside albedo_range {list(cls.albedo_range)}")
    if cls.bottom not in BOTTOMS:
        raise InputError(f"{field}.bottom", cls.bottom, f"must be one of {', '.join(BOTTOMS)}")
    if cls.latent not in LATENT_MODELS:
        raise InputError(f"{field}.latent", cls.latent,
                         f"must be one of {', '.join(LATENT_MODELS)}")
    if cls.bottom == "room" and cls.room_film_coefficient is None:
        raise InputError(f"{field}.room_film_coefficient", None,
                         "is required when bottom = 'room'")
    if cls.latent == "penman_monteith":
        if cls.surface_resistance is None:
            raise InputError(f"{field}.surface_resistance", None,
                             "is required when latent = 'penman_monteith'")
        rng = cls.surface_resistance_range
        if rng is not None and not rng[0] <= cls.surface_resistance <= rng[1]:
            raise InputError(f"{field}.surface_resistance", cls.surface_resistance,
                             f"must lie inside surface_resistance_range {list(rng)}")
    if cls.roughness_length_heat > cls.roughness_length:
        raise InputError(f"{field}.roughness_length_heat", cls.roughness_length_heat,
                         f"must not exceed roughness_length = {cls.roughness_length:g} m")


def apply_overrides(overrides: Mapping | None,
                    classes: Mapping[str, SurfaceClass] = SURFACE_CLASSES,
                    field: str = "background.classes") -> dict[str, SurfaceClass]:
    """The classes with a user's changes applied, every value validated.

    Parameters
    ----------
    overrides : mapping or None
        ``{class name: {property: value}}`` as read from a scenario's
        ``[background.classes.NAME]`` tables. Properties: ``albedo``, ``albedo_range``
        (``[low, high]``), ``emissivity``, ``layers`` (a list of tables with ``thickness``
        [m], ``conductivity`` [W m-1 K-1], ``density`` [kg m-3], ``specific_heat``
        [J kg-1 K-1], optionally ``name``; replaces all layers), ``bottom``,
        ``room_film_coefficient`` [W m-2 K-1], ``latent``, ``surface_resistance`` [s m-1],
        ``surface_resistance_range``, ``roughness_length``, ``roughness_length_heat``,
        ``displacement_height`` [m]. A new name adds a class: then ``code`` and every property
        are required.
    classes : mapping
        The classes to start from (default :data:`SURFACE_CLASSES`).
    field : str
        Dotted prefix of the keys in error messages.

    Returns
    -------
    dict
        Name → :class:`SurfaceClass`; a changed field's source reads ``user input``.

    Raises
    ------
    InputError
        Naming the key (e.g. ``background.classes.land.albedo``), the value, the physical
        range (:data:`PHYSICAL_RANGES`) and how to fix it.
    """
    out = dict(classes)
    if not overrides:
        return out
    if not isinstance(overrides, Mapping):
        raise InputError(field, overrides, "must be a table of classes")
    for name, props in overrides.items():
        f = f"{field}.{name}"
        if name == "water" or name == CLASS_NAMES.get(1):
            raise InputError(f, props, "water is not a land class",
                             "The sea skin model computes water; set its options there")
        if not isinstance(props, Mapping):
            raise InputError(f, props, "must be a table of class properties")
        unknown = [k for k in props if k not in _FIELDS]
        if unknown:
            raise InputError(f"{f}.{unknown[0]}", props[unknown[0]],
                             f"is not a class property; allowed: {', '.join(_FIELDS)}")
        changes: dict = {}
        for key, value in props.items():
            k = f"{f}.{key}"
            if key == "code":
                changes[key] = int(_number(k, value, "code"))
            elif key in ("room_film_coefficient", "surface_resistance") and value is None:
                changes[key] = None
            elif key in _SCALAR_FIELDS:
                changes[key] = _number(k, value, key)
            elif key == "albedo_range":
                changes[key] = _pair(k, value, "albedo")
            elif key == "surface_resistance_range":
                changes[key] = None if value is None else _pair(k, value, "surface_resistance")
            elif key == "layers":
                changes[key] = _layers(k, value)
            elif key == "bottom":
                if value not in BOTTOMS:
                    raise InputError(k, value, f"must be one of {', '.join(BOTTOMS)}")
                changes[key] = value
            elif key == "latent":
                if value not in LATENT_MODELS:
                    raise InputError(k, value, f"must be one of {', '.join(LATENT_MODELS)}")
                changes[key] = value
        if name in out:
            base = out[name]
            if "code" in changes and changes["code"] != base.code:
                raise InputError(f"{f}.code", changes["code"],
                                 f"must stay {base.code} for the existing class {name!r}")
            sources = dict(base.sources)
            sources.update({key: "user input" for key in changes})
            cls = dataclasses.replace(base, **changes, sources=MappingProxyType(sources))
        else:
            required = ("code", "albedo", "albedo_range", "emissivity", "layers", "bottom",
                        "latent", "roughness_length")
            missing = [key for key in required if key not in changes]
            if missing:
                raise InputError(f"{f}.{missing[0]}", None,
                                 f"is required for a new class (new classes need all of "
                                 f"{', '.join(required)})")
            taken = {c.code: n for n, c in out.items()}
            taken.update({code: n for code, n in CLASS_NAMES.items()})
            if changes["code"] in taken:
                raise InputError(f"{f}.code", changes["code"],
                                 f"is taken by {taken[changes['code']]!r}; choose a free code")
            z0 = changes["roughness_length"]
            cls = SurfaceClass(
                code=changes["code"], name=name, albedo=changes["albedo"],
                albedo_range=changes["albedo_range"], emissivity=changes["emissivity"],
                layers=changes["layers"], bottom=changes["bottom"],
                room_film_coefficient=changes.get("room_film_coefficient"),
                latent=changes["latent"], surface_resistance=changes.get("surface_resistance"),
                surface_resistance_range=changes.get("surface_resistance_range"),
                roughness_length=z0,
                roughness_length_heat=changes.get("roughness_length_heat", z0 / 10.0),
                displacement_height=changes.get("displacement_height", 0.0),
                sources=MappingProxyType({key: "user input" for key in changes}))
        _validate_class(f, cls)
        out[name] = cls
    return out
