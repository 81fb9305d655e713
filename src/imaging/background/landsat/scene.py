"""A Landsat Level-1 or Level-2 scene on one grid: the MTL and the bands it names, with
their quality flags, reflectances, radiances and temperatures."""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from shipthermal.errors import InputError, require

from .bands import QA_MASK_FLAGS, _open_grid, _rio_open, qa_flags, read_band
from .grid import THERMAL_BAND, SceneGrid
from .mtl import MtlMetadata, read_mtl
from .radiometry import dn_to_radiance, dn_to_reflectance, radiance_to_brightness_temperature


LST_ACCURACY_ST_B10_K = 1.5
"""Stated accuracy of the Collection-2 Level-2 surface temperature [K]: validation of the
product's single-channel algorithm against in-situ and buoy temperatures reports RMSE of
roughly 1–2 K for clear-sky pixels (Malakar et al. 2018, IEEE TGRS 56(10)), larger near
clouds (the product's ``ST_CDIST`` / ``ST_QA`` layers)."""


@dataclass(frozen=True)
class LandsatScene:
    """A Landsat L1 or L2 scene on one grid.

    Attributes
    ----------
    mtl : MtlMetadata
    grid : SceneGrid
    dn : dict[int, ndarray]
        Stored values per band (uint16): ``Q_cal`` [DN] on Level-1, scaled SR / ST on Level-2.
    fill : ndarray of bool
        Pixels that are fill (DN == 0 in any band, or the QA fill bit).
    qa : dict[str, ndarray] or None
        Decoded quality flags (:func:`qa_flags`), None without a quality band.
    georeferenced_from_mtl : bool
        The band TIFFs carried no CRS; the grid is the MTL's.
    notes : tuple[str, ...]
        What the reader decided (MTL georeferencing, band files found by suffix, ...).
    """

    mtl: MtlMetadata
    grid: SceneGrid
    dn: dict
    fill: np.ndarray
    qa: dict | None = None
    georeferenced_from_mtl: bool = False
    notes: tuple = ()

    @property
    def level(self) -> str:
        return self.mtl.level

    @property
    def masked(self) -> np.ndarray:
        """Pixels to replace: fill, cloud, cirrus, cloud shadow (:data:`QA_MASK_FLAGS`)."""
        m = self.fill.copy()
        if self.qa is not None:
            for f in QA_MASK_FLAGS:
                m |= self.qa[f]
        return m

    def reflectance(self, band: int) -> np.ndarray:
        """Reflectance of an OLI band [-] (NaN on fill): sun-angle-corrected TOA on Level-1,
        surface reflectance on Level-2."""
        if self.mtl.level == "L2":
            rho = dn_to_radiance(self.dn[band], self.mtl.reflectance_mult[band], self.mtl.reflectance_add[band])
        else:
            rho = dn_to_reflectance(self.dn[band], self.mtl.reflectance_mult[band],
                                    self.mtl.reflectance_add[band], self.mtl.sun_elevation_deg)
        return np.where(self.fill, np.nan, rho).astype(np.float32)

    def radiance(self, band: int = THERMAL_BAND) -> np.ndarray:
        """TOA spectral radiance [W m-2 sr-1 um-1] (NaN on fill; Level-1 only)."""
        require(self.mtl.level == "L1", "landsat.level", self.mtl.level,
                "TOA radiance needs a Level-1 band 10 (a Level-2 scene gives ST_B10 instead)")
        rad = dn_to_radiance(self.dn[band], self.mtl.radiance_mult[band], self.mtl.radiance_add[band])
        return np.where(self.fill, np.nan, rad)

    def brightness_temperature(self) -> np.ndarray:
        """TIRS band-10 brightness temperature [K] (NaN on fill; Level-1 only)."""
        return radiance_to_brightness_temperature(self.radiance(THERMAL_BAND), self.mtl.k1, self.mtl.k2)

    def surface_temperature(self) -> np.ndarray:
        """Level-2 ``ST_B10`` surface temperature [K] (NaN on fill), ``mult * DN + add``."""
        require(self.mtl.level == "L2", "landsat.level", self.mtl.level,
                "ST_B10 exists in Level-2 products only")
        st = dn_to_radiance(self.dn[THERMAL_BAND], self.mtl.st_mult, self.mtl.st_add)
        return np.where(self.fill | (self.dn[THERMAL_BAND] == 0), np.nan, st)


def read_landsat_scene(mtl_path: str | os.PathLike, bounds=None, band_files=None,
                       use_qa: bool = True) -> LandsatScene:
    """Read the MTL and the bands it names (2–7 and 10, and the quality band); check they
    share one grid.

    Parameters
    ----------
    mtl_path : path-like
        ``*_MTL.txt`` or ``*_MTL.json`` (Level-1 or Level-2, :func:`read_mtl`).
    bounds : (west, south, east, north), optional
        Crop box in the scene's projected CRS [m] (e.g. the port out of a 185 km scene);
        widened to whole 30 m pixels, only that window is read from each band.
    band_files : str or dict, optional
        Band file names differing from the MTL's (:func:`read_mtl`).
    use_qa : bool
        Read the quality band when there is one.

    Raises
    ------
    InputError
        Missing MTL keys or band files; bands whose shape, CRS or transform differ; a crop
        box outside the scene; TIFFs without CRS whose size differs from the MTL's grid.
    """
    mtl = read_mtl(mtl_path, band_files)
    notes = list(mtl.notes)
    files = dict(mtl.band_files)
    if use_qa and mtl.qa_file is not None:
        files["qa"] = mtl.qa_file
    dn: dict = {}
    grid0: SceneGrid | None = None
    ref_band = None
    from_mtl = False
    for band, path in files.items():
        # Compare the full grids (a crop could hide a shape mismatch), then read.
        key = "QA" if band == "qa" else f"FILE_NAME_BAND_{band}"
        with _rio_open(path, key) as src:
            grid, by_mtl = _open_grid(src, path, key, mtl.georef)
        from_mtl |= by_mtl
        if grid0 is None:
            grid0, ref_band = grid, band
        else:
            if grid.shape != grid0.shape:
                raise InputError(f"{key}.shape", grid.shape,
                                 f"must equal band {ref_band}'s shape {grid0.shape}",
                                 "All bands of one scene share the 30 m grid; "
                                 "check that the files belong to the same scene")
            if grid.crs != grid0.crs:
                raise InputError(f"{key}.crs", str(grid.crs),
                                 f"must equal band {ref_band}'s CRS {grid0.crs}",
                                 "Reproject the band onto the scene grid first")
            if not grid.same_as(grid0):
                raise InputError(f"{key}.transform", tuple(grid.transform)[:6],
                                 f"must equal band {ref_band}'s transform {tuple(grid0.transform)[:6]}",
                                 "Resample the band onto the scene grid first")
    if from_mtl:
        notes.append(f"band TIFFs carry no CRS: georeferencing from the MTL ({mtl.georef.crs}, upper-left "
                     f"pixel centre {mtl.georef.ul_x:.1f} E, {mtl.georef.ul_y:.1f} N, {mtl.georef.cell:g} m)")
    scene_grid = None
    for band, path in files.items():
        key = "QA" if band == "qa" else f"FILE_NAME_BAND_{band}"
        data, scene_grid, _ = read_band(path, key, bounds, mtl.georef)
        dn[band] = data
    qa_raw = dn.pop("qa", None)
    fill = np.zeros(scene_grid.shape, dtype=bool)
    for data in dn.values():
        fill |= data == 0
    qa = None
    if qa_raw is not None:
        qa = qa_flags(qa_raw, mtl.collection)
        fill |= qa["fill"]
        counts = ", ".join(f"{f} {int(qa[f].sum())}" for f in QA_MASK_FLAGS if f != "fill")
        notes.append(f"quality band {os.path.basename(files['qa'])} ({'QA_PIXEL' if mtl.collection == '2' else 'BQA'}"
                     f", {'pre-collection' if mtl.collection == 'pre' else 'collection ' + mtl.collection} bits): "
                     f"{counts} pixels")
    return LandsatScene(mtl=mtl, grid=scene_grid, dn=dn, fill=fill, qa=qa,
                        georeferenced_from_mtl=from_mtl, notes=tuple(notes))
