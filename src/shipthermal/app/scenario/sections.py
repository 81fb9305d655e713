"""The [ship] sections of a scenario: the ship (built-in or user files), its particulars,
files, plate layups and user materials; each a frozen dataclass whose fields carry their
specification (type, default, unit, range, meaning), with its cross-field checks in
``_check``.

The other tables have their own modules (:mod:`.site_sections`, :mod:`.thermal_sections`,
:mod:`.imaging_sections`); their sections are importable from here as well.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, fields
from pathlib import Path
from types import MappingProxyType
from typing import Mapping, Optional

from ...errors import InputError
from ...geometry import BUILTIN_SHIPS, ReadShipSettings, read_ship, remesh_ship
from ...geometry import ship as gship
from ...geometry.layups import ISO7547_INDOOR_C
from ...geometry.limits import builtin_area_bound, check_surface_size
from ...geometry.outside import SLIVER_ANGLE_DEG, SLIVER_WARN_SHARE
from ...geometry.parts import MAIN_PARTS, face_areas, main_part, part_key, part_keys, part_value
from ...materials import MATERIAL_RANGES, MATERIALS, Material
from ...units import ZERO_CELSIUS
from .imaging_sections import (AtmosphereSettings, BackgroundSettings, CalendarSettings,
                               ImagingSettings, SensorSettings)
from .site_sections import Location, Time, WeatherSettings
from .spec import _Context, _default, _opt, _part_key, _suggest, _thaw, parse_band
from .thermal_sections import ConvectionSettings, OutputSettings, SolverSettings
from .values import (BAND_EMISSIVITY, BUILTIN_SHIP_NAMES, LONGWAVE_EMISSIVITY,
                     MAX_REPAIR_CHANGE, MESH_EXTENSIONS, MESH_WITH_PART_ARRAY,
                     MESH_WITH_PART_NAMES, SHIP_LENGTH_RANGE, SHIP_SPEED_MAX,
                     SOLAR_ABSORPTIVITY, UNITS)

__all__ = ["Location", "Time", "WeatherSettings", "LayerSpec", "MaterialSpec",
           "ShipParticulars", "ShipFiles", "ShipSettings", "SolverSettings",
           "ConvectionSettings", "OutputSettings", "BackgroundSettings", "SensorSettings",
           "AtmosphereSettings", "CalendarSettings", "ImagingSettings"]


@dataclass(frozen=True)
class LayerSpec:
    """One plate layer (outer layer first)."""

    material: str = _opt(None, "str", "Material name: a built-in one "
                         "(shipthermal.materials.MATERIALS) or one of [materials]",
                         allowed_text="one of " + ", ".join(repr(m) for m in sorted(MATERIALS))
                                      + " or a name of [materials]")
    thickness: float = _opt(None, "float", "Layer thickness", unit="m", lo=0.0, hi=1.0,
                            lo_open=True, fix="Give the thickness in metres (0.3 mm is "
                            "0.0003); leave a layer of no thickness out")
    cells: int = _opt(1, "int", "Finite-volume cells through the layer", lo=1, hi=50)
    solar_absorptivity: Optional[float] = _opt(None, "float", "Outer layer only (a paint): "
                                               "its solar absorptivity, the part's", lo=0.0,
                                               hi=1.0, lo_open=True, optional=True)
    longwave_emissivity: Optional[float] = _opt(None, "float", "Outer layer only (a paint): "
                                                "its broadband long-wave emissivity, the "
                                                "part's for the thermal stage", lo=0.0, hi=1.0,
                                                lo_open=True, optional=True)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        for key in ("material", "thickness"):
            if key not in raw:
                spec = LayerSpec.__dataclass_fields__[key].metadata["spec"]
                ctx.err(f"{path}.{key}", None, f"is required: {spec.allowed()}",
                        'e.g. {material = "mild_steel", thickness = 0.008}')
        return obj


@dataclass(frozen=True)
class MaterialSpec:
    """[materials.<name>]: a material of the user's, usable by name in ship.layups."""

    conductivity: float = _opt(None, "float", "Thermal conductivity k",
                               unit=MATERIAL_RANGES["conductivity"][2],
                               lo=MATERIAL_RANGES["conductivity"][0],
                               hi=MATERIAL_RANGES["conductivity"][1],
                          fix="Give k in W m-1 K-1 (steel ~50, paint ~0.2, mineral wool ~0.04)")
    density: float = _opt(None, "float", "Density rho", unit=MATERIAL_RANGES["density"][2],
                          lo=MATERIAL_RANGES["density"][0], hi=MATERIAL_RANGES["density"][1],
                          fix="Give rho in kg m-3 (steel 7850; not g cm-3)")
    specific_heat: float = _opt(None, "float", "Specific heat capacity c",
                                unit=MATERIAL_RANGES["specific_heat"][2],
                                lo=MATERIAL_RANGES["specific_heat"][0],
                                hi=MATERIAL_RANGES["specific_heat"][1],
                          fix="Give c in J kg-1 K-1 (steel ~450; not kJ kg-1 K-1)")
    source: str = _opt(None, "str", "Where the numbers come from (a data sheet, a handbook "
                       "table, a measurement)", allowed_text="a non-empty string")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        example = ("e.g. [materials.my_steel] conductivity = 50.0, density = 7850.0, "
                   "specific_heat = 470.0, source = \"mill certificate 2024\"")
        for key in ("conductivity", "density", "specific_heat", "source"):
            if key not in raw:
                spec = MaterialSpec.__dataclass_fields__[key].metadata["spec"]
                ctx.err(f"{path}.{key}", None, f"is required: {spec.allowed()}", example)
        if "source" in raw and isinstance(raw["source"], str) and not raw["source"].strip():
            ctx.err(f"{path}.source", raw["source"], "must name where the numbers come from",
                    example)
        return obj

    def material(self, name: str):
        """The :class:`shipthermal.materials.Material` of this entry."""
        return Material(name, self.density, self.specific_heat, self.conductivity, self.source)


@dataclass(frozen=True)
class ShipParticulars:
    """[ship.parameters]: main dimensions of a built-in ship (others scale with them)."""

    length: Optional[float] = _opt(None, "float", "Length overall (frigate 132, patrol_boat "
                                   "56, cargo_ship 180)", unit="m", lo=SHIP_LENGTH_RANGE[0], hi=SHIP_LENGTH_RANGE[1],
                                   optional=True)
    beam: Optional[float] = _opt(None, "float", "Maximum beam (15 / 9.5 / 30)", unit="m",
                                 lo=0.0, hi=100.0, lo_open=True, optional=True)
    draught: Optional[float] = _opt(None, "float", "Keel depth below the waterline "
                                    "(4.5 / 2.7 / 10)", unit="m", lo=0.0, hi=50.0,
                                    lo_open=True, optional=True)
    freeboard: Optional[float] = _opt(None, "float", "Deck height above the waterline "
                                      "amidships (5 / 3 / 5.5)", unit="m", lo=0.0, hi=50.0,
                                      lo_open=True, optional=True)

    def given(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)
                if getattr(self, f.name) is not None}


@dataclass(frozen=True)
class ShipFiles:
    """[ship.files]: a user ship — one mesh + part map, or one file per part."""

    units: str = _opt(None, "choice", "Unit of the file coordinates (required)",
                      choices=tuple(UNITS))
    mesh: Optional[str] = _opt(None, "mesh_file", "One surface mesh (STL/OBJ/PLY/OFF/GLB, "
                               "or VTK/VTP/VTU with a per-cell 'part' array)", optional=True,
                               allowed_text="existing " + "/".join(MESH_EXTENSIONS) + " file")
    part_map: Optional[str] = _opt(None, "part_map", "JSON file of face ranges per part "
                                   '({"hull": [[0, 5000]], ...}; write_ship writes one), or '
                                   '"auto": parts by rules (`shipthermal mesh` writes the '
                                   "picture and the JSON to check and edit); not needed when "
                                   "OBJ groups / GLB meshes are named after the parts",
                                   optional=True, allowed_text='existing .json file or "auto"')
    parts: Mapping = _opt({}, "part_files", "One file per part instead of mesh + part_map "
                          "(part = path)", allowed_text="part names: hull, hull_wetted, "
                          "hull_dry, deck, superstructure or <main>_<detail>")
    draught: Optional[float] = _opt(None, "float", "Keel depth below the waterline (else "
                                    "waterline_z, else the file's z = 0)", unit="m", lo=0.0,
                                    hi=50.0, lo_open=True, optional=True)
    waterline_z: Optional[float] = _opt(None, "float", "Height of the waterline in the "
                                        "file's frame", unit="m", optional=True)
    clean: bool = _opt(False, "bool", "Drop zero-area and duplicate triangles instead of failing")
    fix_normals: bool = _opt(False, "bool", "Fix inconsistent / inward normals instead of failing")
    repair: str = _opt("none", "choice", "Repair before the checks: union = boolean union of "
                       "closed overlapping pieces (manifold3d, seconds); tetwild = robust "
                       "remesh that also closes gaps (pytetwild, minutes)",
                       choices=("none", "union", "tetwild"))
    repair_edge_length: Optional[float] = _opt(None, "float", "Tet size of the tetwild "
                                               "repair (default pytetwild's: 5 % of the "
                                               "bounding-box diagonal; finer is slower)",
                                               unit="m", lo=0.0, hi=50.0, lo_open=True,
                                               optional=True)
    max_repair_change: float = _opt(MAX_REPAIR_CHANGE, "float", "Largest relative change of "
                                    "area or volume a repair may make (raise it to accept a "
                                    "larger one)", lo=0.0, hi=1.0, lo_open=True)
    check_scale: bool = _opt(True, "bool", "Refuse a ship length outside 5-500 m (a units "
                             "mistake); false for a deliberate model of another size")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "units" not in raw:
            ctx.err(f"{path}.units", None, "is required: 'm' or 'mm' (the unit of the file "
                    "coordinates)")
        has_mesh, has_parts = "mesh" in raw, "parts" in raw
        if has_mesh == has_parts:
            ctx.err(path, sorted(raw), "needs exactly one of 'mesh' (+ 'part_map') or 'parts'",
                    'e.g. mesh = "ship.stl" and part_map = "ship.json"')
        if has_parts and not has_mesh and "part_map" in raw:
            ctx.err(f"{path}.part_map", raw["part_map"], "only applies with 'mesh' (with "
                    "'parts' each file is one part)")
        if (has_mesh and "mesh" not in bad and "part_map" not in raw
                and Path(obj.mesh).suffix.lower()
                not in MESH_WITH_PART_ARRAY + MESH_WITH_PART_NAMES):
            ctx.err(f"{path}.part_map", None, "is required with a "
                    f"{Path(obj.mesh).suffix} mesh (only VTK/VTP/VTU files can carry a "
                    "per-cell 'part' array, OBJ/GLB files part names)",
                    'e.g. part_map = "ship.json", or part_map = "auto" (parts by rules)')
        if "draught" in raw and "waterline_z" in raw:
            ctx.err(f"{path}.draught", raw["draught"], "give draught or waterline_z, not both")
        if obj.part_map is not None and obj.part_map != "auto" and "part_map" not in bad:
            try:
                with open(obj.part_map) as fh:
                    data = json.load(fh)
                if isinstance(data, dict) and "parts" in data:
                    data = data["parts"]
                if not isinstance(data, dict):
                    raise ValueError("not a JSON object of part = face ranges")
                for part in data:
                    _part_key(str(part), f"{path}.part_map[{part!r}]", ctx)
            except (OSError, ValueError) as exc:
                ctx.err(f"{path}.part_map", raw.get("part_map"),
                        f"must be a JSON object of part = [[start, stop], ...] ({exc})")
        return obj

    def part_names(self) -> Optional[tuple]:
        """Part names known without reading the mesh (None if only the mesh knows them)."""
        if self.parts:
            names = tuple(self.parts)
        elif self.part_map == "auto":
            names = ("hull", "deck", "superstructure")
        elif self.part_map is not None:
            try:
                with open(self.part_map) as fh:
                    data = json.load(fh)
                names = tuple(data.get("parts", data))
            except (OSError, ValueError, AttributeError):
                return None
        else:
            return None
        return _expand_hull(names)


def _expand_hull(names) -> tuple:
    out = []
    for n in names:
        out.extend(("hull_wetted", "hull_dry") if n == "hull" else (n,))
    return tuple(dict.fromkeys(out))


def _builtin_part_names(builtin: str, dims: Mapping) -> tuple:
    """Parts of a built-in ship, from its parameters (no mesh is built)."""
    params = getattr(gship, f"{builtin}_parameters")(**dims)
    subs = sorted({b.part for b in params.blocks} - set(MAIN_PARTS))
    return MAIN_PARTS + tuple(subs)


def _compartment_default(ctx: _Context) -> Mapping:
    t = ISO7547_INDOOR_C[ctx.season] + ZERO_CELSIUS
    return MappingProxyType({"hull": t, "deck": t, "superstructure": t})


@dataclass(frozen=True)
class ShipSettings:
    """[ship]: the ship, where it lies, and its surface properties per part.

    Calling it builds the geometry: ``scenario.ship()`` → ShipGeometry (see
    :meth:`__call__`). Per-part tables accept main parts (``hull`` = both hull parts,
    ``hull_wetted``, ``hull_dry``, ``deck``, ``superstructure``) and sub-parts
    (``superstructure_funnel``); a sub-part without its own value takes its main part's.
    """

    builtin: Optional[str] = _opt("frigate", "choice", "Built-in ship (default when "
                                  "[ship.files] is absent; exclusive with it)",
                                  choices=BUILTIN_SHIP_NAMES)
    parameters: ShipParticulars = _opt(None, "section", "Main dimensions of the built-in "
                                       "ship", cls=ShipParticulars)
    superstructure_material: str = _opt("mild_steel", "choice", "Built-in ships: plate "
                                        "material of the default superstructure layup",
                                        choices=("aluminium_5083", "mild_steel"))
    files: Optional[ShipFiles] = _opt(None, "section", "A user ship instead of a built-in "
                                      "one", cls=ShipFiles, optional=True)
    edge_length: Optional[float] = _opt(None, "float", "Target surface edge length "
                                        "(built-in default 0.5 m per 132 m of length; user "
                                        "meshes are remeshed to it, finer or coarser, when "
                                        "given)", unit="m",
                                        lo=0.0, hi=50.0, lo_open=True, optional=True)
    heading: float = _opt(180.0, "float", "Heading, clockwise from north (default: moored "
                          "along the synthetic port's N-S pier, bow to the harbour entrance)",
                          unit="deg", lo=0.0, hi=360.0, hi_open=True)
    speed: float = _opt(0.0, "float", "Speed over ground (0 moored)", unit="m/s", lo=0.0,
                        hi=SHIP_SPEED_MAX)
    mooring_position: tuple = _opt((38.5, 100.0), "vec2", "Ship centre in the port scene, "
                                   "[east, north] of the scene centre (default: alongside "
                                   "the east face of the synthetic port's first N-S pier, "
                                   "30 m east of the centre in its class map, plus half the "
                                   "frigate's 15 m beam and 1 m of fenders)", unit="m",
                                   allowed_text="[x, y], inside the port scene")
    layups: Mapping = _opt({}, "layups", "Plate layup overrides per part, outer layer first "
                           "(defaults: shipthermal.geometry.layups)",
                           allowed_text="list of layers", cls=LayerSpec)
    compartment_temperature: Mapping = _opt(None, "part_table", "Air temperature inside "
                                            "each part (default ISO 7547 design: 27 degC "
                                            "summer, 22 degC winter)", unit="K", lo=200.0,
                                            hi=400.0, dynamic=_compartment_default,
                                            default_text="summer 300.15, winter 295.15 (all parts)")
    solar_absorptivity: Mapping = _opt(SOLAR_ABSORPTIVITY, "part_table",
                                       "Solar absorptivity per part (ASSUMPTION: grey paint, "
                                       "darker non-skid deck)", lo=0.0, hi=1.0, lo_open=True)
    longwave_emissivity: Mapping = _opt(LONGWAVE_EMISSIVITY, "part_table",
                                        "Broadband long-wave emissivity per part for the "
                                        "thermal stage (default: the 8-14 µm value)",
                                        lo=0.0, hi=1.0, lo_open=True)
    user_materials: Mapping = dataclasses.field(default_factory=dict, compare=False,
                                                repr=False, metadata={"internal": True})
    band_emissivity: Mapping = _opt(BAND_EMISSIVITY, "part_bands", "Emissivity per "
                                    "part and sensor band for the imaging stage (paper §5); "
                                    "a band inside 3-5 or 8-14 without its own value takes "
                                    "that band's", lo=0.0, hi=1.0, lo_open=True)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "builtin" in raw and "files" in raw:
            ctx.err(f"{path}.builtin", raw["builtin"], "give either builtin or [ship.files], "
                    "not both")
        if obj.files is not None and "builtin" not in raw:
            obj = dataclasses.replace(obj, builtin=None)
        if obj.files is not None:
            for key in ("parameters", "superstructure_material"):
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies to a built-in ship "
                            "(this ship comes from [ship.files])")
        known = None
        if obj.builtin is not None and "builtin" not in bad and "parameters" not in bad:
            known = _check_particulars(obj, path, ctx)
        elif obj.files is not None:
            known = obj.files.part_names() if "files" not in bad else None
        if known is not None:
            valid = {"hull"}
            for n in known:
                try:
                    valid |= {n, main_part(n)}
                except InputError:     # reported where the name was read
                    pass
            for key in ("layups", "compartment_temperature", "solar_absorptivity",
                        "longwave_emissivity", "band_emissivity"):
                f = ShipSettings.__dataclass_fields__[key]
                default = _thaw(_default(f, ctx, f"{path}.{key}")) if key != "layups" else {}
                for part in raw.get(key, {}) if isinstance(raw.get(key), dict) else ():
                    # a default entry written back by Scenario.to_dict is not the user's
                    if part in default and raw[key][part] == default[part]:
                        continue
                    if part not in valid and key not in bad:
                        ctx.err(f"{path}.{key}.{part}", part, "is not a part of this ship; "
                                f"parts: {', '.join(sorted(valid))}", _suggest(part, valid))
        return obj

    def _omit(self) -> tuple:
        return ("parameters", "superstructure_material") if self.files is not None else ()

    # ---- surface properties --------------------------------------------------------------
    def _outer_layer(self, part: str):
        """The outer layer of the layup a (sub-)part takes from ``layups``, or None."""
        key = part_key(self.layups, part)
        return None if key is None else self.layups[key][0]

    def solar_absorptivity_of(self, part: str) -> float:
        """Solar absorptivity of a (sub-)part [-]: its layup's outer layer's (a paint's)
        where given, else ``solar_absorptivity``."""
        layer = self._outer_layer(part)
        if layer is not None and layer.solar_absorptivity is not None:
            return float(layer.solar_absorptivity)
        return float(part_value(self.solar_absorptivity, part, "solar_absorptivity"))

    def longwave_emissivity_of(self, part: str) -> float:
        """Broadband long-wave emissivity of a (sub-)part [-]: its layup's outer layer's
        where given, else ``longwave_emissivity``."""
        layer = self._outer_layer(part)
        if layer is not None and layer.longwave_emissivity is not None:
            return float(layer.longwave_emissivity)
        return float(part_value(self.longwave_emissivity, part, "longwave_emissivity"))

    def compartment_temperature_of(self, part: str) -> float:
        """Air temperature inside a (sub-)part [K]."""
        return float(part_value(self.compartment_temperature, part,
                                "compartment_temperature"))

    def emissivity(self, part: str, band) -> float:
        """Emissivity of a (sub-)part in a sensor band [-] (see :func:`parse_band`).

        A band without its own value takes the value of the listed band that contains it
        (e.g. 3.7-4.8 µm takes 3-5 µm's).
        """
        name, (lo, hi) = parse_band(band)
        listed = []
        # most specific part first (sub-part, main part, hull); in each, the band itself,
        # then a listed band that contains it
        for key in part_keys(part):
            table = self.band_emissivity.get(key)
            if table is None:
                continue
            if name in table:
                return float(table[name])
            for bkey, val in table.items():
                klo, khi = parse_band(bkey)[1]
                if klo <= lo and hi <= khi:
                    return float(val)
            listed += [f"{key}: {', '.join(table)}"]
        raise InputError("band", name, f"has no emissivity for part {part!r} (bands with a "
                         f"value: {'; '.join(listed) or 'none'})",
                         f"Add ship.band_emissivity.{main_part(part)}.\"{name}\"")

    # ---- geometry ----------------------------------------------------------------------
    def _compartment_overrides(self) -> dict:
        table = dict(self.compartment_temperature)
        out = {}
        if "hull" in table:
            out.update({"hull_wetted": table["hull"], "hull_dry": table["hull"]})
        out.update({k: v for k, v in table.items() if k != "hull"})
        return out

    def _layup_overrides(self) -> Optional[dict]:
        if not self.layups:
            return None
        def material(name):
            spec = self.user_materials.get(name)
            return name if spec is None else spec.material(name)

        return {part: [(material(l.material), l.thickness, l.cells) for l in layers]
                for part, layers in self.layups.items()}

    def read_files(self):
        """Read, check and repair the user ship of [ship.files] (no remeshing): every
        problem of the mesh is raised in one :class:`InputError` naming the keys that fix
        it. Returns ``(ShipGeometry, report)``."""
        f = self.files
        source = dict(f.parts) if f.parts else f.mesh
        settings = ReadShipSettings(
            draught=f.draught, waterline_z=f.waterline_z, layups=self._layup_overrides(),
            compartment_temperature=self._compartment_overrides(), clean=f.clean,
            fix_normals=f.fix_normals, repair=None if f.repair == "none" else f.repair,
            check_scale=f.check_scale, max_repair_change=f.max_repair_change,
            repair_edge_length=f.repair_edge_length)
        ship, report = read_ship(source, units=f.units, part_map=f.part_map, settings=settings)
        if self.edge_length is not None:
            check_surface_size(float(face_areas(ship.vertices, ship.faces).sum()),
                               self.edge_length)
        share = report.get("sliver_share", 0.0)
        if share > SLIVER_WARN_SHARE and self.edge_length is None:
            report["warnings"].append(
                f"{100 * share:.0f} % of the triangles are slivers (smallest angle below "
                f"{SLIVER_ANGLE_DEG:g} deg): their view factors and heat fluxes are poorly "
                f"resolved. Set ship.edge_length (e.g. {report['equilateral_edge_m']:.2g} m, "
                "the same resolution) to remesh the ship with well-shaped triangles")
        report.setdefault("repairs", []).extend(f"warning: {w}" for w in report["warnings"])
        return ship, report

    def __call__(self, return_report: bool = False):
        """Build the ship geometry (slow: meshing / reading files).

        Returns
        -------
        ShipGeometry, or (ShipGeometry, dict) with ``return_report`` (the read/repair
        report of a user ship; ``{}`` for a built-in one).
        """
        report: dict = {}
        if self.files is None:
            ship = BUILTIN_SHIPS[self.builtin](
                edge_length=self.edge_length, **self.parameters.given(),
                layups=self._layup_overrides(),
                compartment_temperature=self._compartment_overrides(),
                superstructure_material=self.superstructure_material)
        else:
            ship, report = self.read_files()
            if self.edge_length is not None:
                ship, rem = remesh_ship(ship, self.edge_length, return_report=True)
                if rem:
                    report["remesh"] = rem
                    report.setdefault("repairs", []).append(_remesh_line(rem))
        return (ship, report) if return_report else ship


def _remesh_line(rem: dict) -> str:
    """One console line on an isotropic remesh of a user ship."""
    qb, qa = rem["quality_before"], rem["quality_after"]
    shrunk = ("" if rem["edge_length"] == rem["target_edge_length"] else
              f" (target {rem['target_edge_length']:g} m: reduced until >= 99 % of triangles "
              "have a smallest angle >= 20 deg)")
    return (f"remesh: {qb['n_faces']} -> {qa['n_faces']} triangles at {rem['edge_length']:.3g} m"
            f"{shrunk}; smallest angle >= 20 deg: {100 * (1 - qb['frac_min_angle_below_20']):.1f} "
            f"-> {100 * (1 - qa['frac_min_angle_below_20']):.1f} % of triangles; area "
            f"{100 * rem['area_change']:+.2f} %, volume {100 * rem['volume_change']:+.2f} %")


def _check_particulars(obj: ShipSettings, path: str, ctx: _Context) -> Optional[tuple]:
    """Validate a built-in ship's dimensions and edge length; return its part names."""
    dims = obj.parameters.given()
    try:
        params = getattr(gship, f"{obj.builtin}_parameters")(**dims)
        params.validate()
    except InputError as exc:
        key = exc.field.split(".", 1)[1] if "." in exc.field else exc.field
        where = f"{path}.parameters.{key}" if key in dims else f"{path}.parameters"
        ctx.err(where, exc.value, f"{exc.allowed} (for a {obj.builtin})", exc.fix)
        return None
    if obj.edge_length is not None:
        lo, hi = 1e-4 * params.length, 0.1 * params.length
        if not lo <= obj.edge_length <= hi:
            ctx.err(f"{path}.edge_length", obj.edge_length, f"must lie in [{lo:.3g}, {hi:.3g}] m "
                    f"for a {params.length:g} m ship (1e-4 to 0.1 of its length)")
        else:
            try:
                check_surface_size(builtin_area_bound(params.length, params.beam,
                                                      params.draught, params.freeboard),
                                   obj.edge_length, f"{path}.edge_length")
            except InputError as exc:
                ctx.err(exc.field, exc.value, exc.allowed, exc.fix)
    return _builtin_part_names(obj.builtin, dims)
