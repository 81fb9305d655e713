"""``shipthermal background``: build and write the port background from real files alone.

With a Landsat scene and training ROIs it writes the overpass products (LST from ST_B10 or
the single-channel retrieval, class map, QA mask, water-index check, accuracy over held-out
ROI splits); with a DEM and an hourly met grid as well, the whole hourly background
(:func:`imaging.background.build_background_from_files`). Everything is written into a
hidden sibling folder and moved into place at the end, so a failure leaves nothing behind.
"""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path

from ..errors import InputError, require

__all__ = ["run_background"]


def _parse_bounds(bounds):
    if bounds is None:
        return None
    require(len(bounds) == 4, "--bounds", bounds, "must be four numbers: west south east north "
            "in the scene's projected CRS [m]")
    return tuple(float(b) for b in bounds)


def run_background(out, mtl, roi, *, dem=None, met=None, band_files=None, bounds=None,
                   use_qa: bool = True, n_splits: int = 10, seed: int = 0,
                   utc_offset_hours: float = 0.0, water_vapour: float | None = None,
                   krige_coarsen: int = 5, variogram_model: str = "spherical",
                   force: bool = False, log=print, progress: bool = False) -> dict:
    """Build the port background from files and write it into ``out``.

    Parameters
    ----------
    out : path-like
        Output folder; must not exist or be empty unless ``force``.
    mtl, roi : path-like
        Landsat MTL (Level-1 or Level-2, :func:`imaging.background.landsat.read_mtl`) and
        training ROIs (:func:`imaging.background.classify.read_roi`).
    dem, met : path-like, optional
        Both or neither: with them, the hourly background; without, the overpass products.
    band_files : str, optional
        Template of band file names (``"l8_{band}.tif"``) when they differ from the MTL.
    bounds : 4 floats, optional
        Crop box (west, south, east, north) in the scene CRS [m].
    use_qa, n_splits, seed, utc_offset_hours, water_vapour, krige_coarsen, variogram_model
        As :func:`imaging.background.build_background_from_files`.
    force : bool
        Replace an existing non-empty ``out``.
    log : callable
        Receives notes (one line each).

    Returns
    -------
    dict
        ``files`` written, ``summary`` (key figures), ``seconds``.
    """
    out = Path(out)
    if out.exists() and (not out.is_dir() or any(out.iterdir())) and not force:
        raise InputError("--out", str(out), "exists and is not empty", "Give --force to replace it, or another --out")
    require((dem is None) == (met is None), "--dem/--met", f"dem={dem}, met={met}",
            "go together: both give the hourly background, neither the overpass products only")
    bounds = _parse_bounds(bounds)
    from imaging.background import build_background_from_files
    from imaging.background.background import build_overpass
    from imaging.background.landsat import read_landsat_scene
    from imaging.background.outputs import write_overpass_outputs

    t0 = time.perf_counter()
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.parent / f".{out.name}.part-{os.getpid()}"
    shutil.rmtree(tmp, ignore_errors=True)
    try:
        if dem is None:
            scene = read_landsat_scene(mtl, bounds, band_files=band_files, use_qa=use_qa)
            ov = build_overpass(scene, roi, water_vapour=water_vapour, seed=seed, n_splits=n_splits)
            files = write_overpass_outputs(ov, tmp)
            notes = ov.notes
            summary = ov.summary_extra()
        else:
            bg = build_background_from_files(mtl, dem, met, roi, utc_offset_hours=utc_offset_hours,
                                             water_vapour=water_vapour, seed=seed, bounds=bounds,
                                             band_files=band_files, use_qa=use_qa, n_splits=n_splits,
                                             krige_coarsen=krige_coarsen, variogram_model=variogram_model,
                                             out_dir=tmp, progress=progress)
            files = bg.outputs
            notes = bg.overpass.notes if bg.overpass is not None else []
            summary = bg.summary()
        if out.exists():
            shutil.rmtree(out) if out.is_dir() else out.unlink()
        os.replace(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    for n in notes:
        log(f"note: {n}")
    files = {k: str(out / Path(v).name) for k, v in files.items()}
    return {"files": files, "summary": summary, "seconds": time.perf_counter() - t0}
