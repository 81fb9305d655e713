"""The ship surface with named parts: :class:`ShipGeometry`.

A closed triangulated surface with outward normals, a part per triangle, and per part a
plate layup, a compartment air temperature and the medium outside. Built-in ships come
from :mod:`.ship`, user meshes from :mod:`.io`.

Coordinates: x forward (bow at +x), y to port, z up; z = 0 is the waterline, the origin is
amidships on the centreline. Lengths in metres.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from types import MappingProxyType
from typing import TYPE_CHECKING, Mapping

import numpy as np

from ..errors import InputError, require
from ..materials import Layup
from .layups import compartment_temperatures, default_layups
from .parts import (HULL_PARTS, MAIN_PARTS, boundary_edges, face_areas, main_part, part_areas,
                    part_key, signed_volume)

if TYPE_CHECKING:
    from .ship.parameters import ShipParameters

__all__ = ["ShipGeometry"]


@dataclass(frozen=True, eq=False)
class ShipGeometry:
    """A closed ship surface split into named parts, with plate layups per part.

    Attributes
    ----------
    vertices : (N, 3) float array [m]
    faces : (M, 3) int array
        Triangles wound so that normals point out of the ship.
    face_part : (M,) int array
        Index into ``part_names`` of each triangle.
    part_names : tuple of str
        Main parts and sub-parts (see :mod:`.parts`).
    layups : mapping part → Layup
    compartment_temperature : mapping part → air temperature inside [K]
    outer_medium : mapping part → ``'sea'`` or ``'air'``
    length, beam, draught, freeboard : float [m]
        Overall length, maximum beam, draught (keel below waterline), freeboard amidships.
    name : str
    provenance : str
        Where the dimensions come from.
    edge_length : float
        Nominal surface edge length [m] the surface was made at.
    parameters : ShipParameters or None
        The generator parameters of a built-in ship (None for user meshes).
    """

    vertices: np.ndarray
    faces: np.ndarray
    face_part: np.ndarray
    part_names: tuple[str, ...]
    layups: Mapping[str, Layup]
    compartment_temperature: Mapping[str, float]
    outer_medium: Mapping[str, str]
    length: float
    beam: float
    draught: float
    freeboard: float
    name: str = "ship"
    provenance: str = ""
    edge_length: float = float("nan")
    parameters: "ShipParameters | None" = None

    def __post_init__(self):
        v = np.ascontiguousarray(self.vertices, dtype=float)
        f = np.ascontiguousarray(self.faces, dtype=np.int64)
        p = np.ascontiguousarray(self.face_part, dtype=np.int32)
        require(v.ndim == 2 and v.shape[1] == 3, "vertices", v.shape, "must be (N, 3)")
        require(f.ndim == 2 and f.shape[1] == 3 and len(f) > 0, "faces", f.shape, "must be (M, 3), M > 0")
        require(f.min() >= 0 and f.max() < len(v), "faces", (int(f.min()), int(f.max())),
                f"vertex indices must lie in [0, {len(v) - 1}]")
        require(p.shape == (len(f),), "face_part", p.shape, f"must hold one part per face ({len(f)})")
        names = tuple(str(n) for n in self.part_names)
        require(len(set(names)) == len(names), "part_names", names, "must be unique")
        require(p.min() >= 0 and p.max() < len(names), "face_part", (int(p.min()), int(p.max())),
                f"must index part_names (0..{len(names) - 1})")
        for n in names:
            main_part(n)
        for attr in ("layups", "compartment_temperature", "outer_medium"):
            table = getattr(self, attr)
            missing = [n for n in names if n not in table]
            require(not missing, attr, sorted(table), f"must give a value for every part; missing {missing}")
        for arr in (v, f, p):
            arr.setflags(write=False)
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "faces", f)
        object.__setattr__(self, "face_part", p)
        object.__setattr__(self, "part_names", names)
        for attr in ("layups", "compartment_temperature", "outer_medium"):
            object.__setattr__(self, attr, MappingProxyType(dict(getattr(self, attr))))

    def __reduce__(self):
        """Pickled as its fields (the read-only tables as plain dicts): a record's segments
        run in processes of their own."""
        values = [getattr(self, f.name) for f in fields(self)]
        return (type(self), tuple(dict(v) if isinstance(v, MappingProxyType) else v
                                  for v in values))

    # ---- sizes and geometry ------------------------------------------------------------
    @property
    def n_faces(self) -> int:
        return int(len(self.faces))

    @property
    def face_areas(self) -> np.ndarray:
        """Area of each triangle [m2]."""
        return face_areas(self.vertices, self.faces)

    @property
    def face_normals(self) -> np.ndarray:
        """Outward unit normal of each triangle."""
        p0, p1, p2 = (self.vertices[self.faces[:, k]] for k in range(3))
        n = np.cross(p1 - p0, p2 - p0)
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    @property
    def face_centroids(self) -> np.ndarray:
        """Triangle centroids [m]."""
        return self.vertices[self.faces].mean(axis=1)

    @property
    def total_area(self) -> float:
        """Surface area [m2]."""
        return float(self.face_areas.sum())

    @property
    def signed_volume(self) -> float:
        """Enclosed volume [m3]; positive when normals point outward."""
        return signed_volume(self.vertices, self.faces)

    @property
    def is_watertight(self) -> bool:
        """Every edge shared by exactly two triangles."""
        open_e, nonman = boundary_edges(self.faces)
        return len(open_e) == 0 and len(nonman) == 0

    @property
    def face_outer_medium(self) -> np.ndarray:
        """What each triangle's outer side faces: ``'sea'`` or ``'air'`` (M,) str."""
        table = np.array([self.outer_medium[n] for n in self.part_names])
        return table[self.face_part]

    @property
    def face_compartment_temperature(self) -> np.ndarray:
        """Air temperature behind each triangle (inside the ship) [K] (M,)."""
        table = np.array([self.compartment_temperature[n] for n in self.part_names])
        return table[self.face_part]

    def part_index(self, name: str) -> int:
        if name not in self.part_names:
            raise InputError("part", name, f"unknown part; parts are {', '.join(self.part_names)}")
        return self.part_names.index(name)

    def part_mask(self, name: str) -> np.ndarray:
        """Faces of a part; a main-part name also selects its sub-parts."""
        if name in MAIN_PARTS or name == "hull":
            members = [i for i, n in enumerate(self.part_names)
                       if main_part(n) == name or (name == "hull" and main_part(n) in HULL_PARTS)]
            require(members, "part", name, f"no faces; parts are {', '.join(self.part_names)}")
            return np.isin(self.face_part, members)
        return self.face_part == self.part_index(name)

    def part_areas(self) -> dict[str, float]:
        """Area of each part [m2]."""
        return part_areas(self.vertices, self.faces, self.face_part, self.part_names)

    def main_part_areas(self) -> dict[str, float]:
        """Area of each main part, sub-parts included [m2]."""
        out = {m: 0.0 for m in MAIN_PARTS}
        for name, a in self.part_areas().items():
            out[main_part(name)] += a
        return out

    def part_masses(self) -> dict[str, float]:
        """Plate mass of each part, area × Σρ·t of its layup [kg]."""
        return {n: a * self.layups[n].areal_mass for n, a in self.part_areas().items()}

    def part_heat_capacities(self) -> dict[str, float]:
        """Heat capacity of each part's plating, area × Σρ·c·t [J K-1]."""
        return {n: a * self.layups[n].areal_heat_capacity for n, a in self.part_areas().items()}

    def to_trimesh(self):
        """The surface as a :class:`trimesh.Trimesh` (no processing) with ``face_part``."""
        import trimesh      # deferred: start-up cost (trimesh takes ~1.5 s to import)

        mesh = trimesh.Trimesh(self.vertices, self.faces, process=False, validate=False)
        mesh.face_attributes["part"] = np.asarray(self.face_part)
        return mesh

    # ---- overrides -----------------------------------------------------------------------
    def with_layups(self, overrides: Mapping, superstructure_material: str = "mild_steel") -> "ShipGeometry":
        """Copy with some layups replaced (``{part: Layup | [(material, t, cells), ...]}``)."""
        base = default_layups(self.part_names, superstructure_material=superstructure_material)
        base.update({k: v for k, v in self.layups.items()})
        new = default_layups(self.part_names, overrides, superstructure_material)
        merged = {n: (new[n] if _overridden(n, overrides) else base[n]) for n in self.part_names}
        return replace(self, layups=merged)

    def with_compartment_temperature(self, overrides: Mapping) -> "ShipGeometry":
        """Copy with some compartment air temperatures [K] replaced."""
        table = dict(self.compartment_temperature)
        new = compartment_temperatures(self.part_names, overrides)
        table.update({n: new[n] for n in self.part_names if _overridden(n, overrides)})
        return replace(self, compartment_temperature=table)

    def summary(self) -> str:
        """Particulars, parts, areas and plate masses as text."""
        lines = [f"{self.name}: L = {self.length:.1f} m, B = {self.beam:.1f} m, T = {self.draught:.2f} m, "
                 f"freeboard {self.freeboard:.2f} m; {self.n_faces} triangles, "
                 f"area {self.total_area:.0f} m2, volume {self.signed_volume:.0f} m3"]
        masses = self.part_masses()
        for n, a in self.part_areas().items():
            lay = self.layups[n]
            lines.append(f"  {n:24s} {a:9.1f} m2  layup {lay.thickness * 1e3:6.1f} mm "
                         f"{masses[n] / 1e3:8.1f} t  inside {self.compartment_temperature[n] - 273.15:.1f} °C"
                         f"  outside {self.outer_medium[n]}")
        if self.provenance:
            lines.append(f"  provenance: {self.provenance}")
        return "\n".join(lines)


def _overridden(name: str, overrides: Mapping) -> bool:
    return part_key(overrides, name) is not None

