"""``shipthermal background``: build and write the port background from real files alone.

With a Landsat scene and training ROIs it writes the overpass products (LST from ST_B10 or
the single-channel retrieval, class map, QA mask, water-index check, accuracy over held-out
ROI splits); with a DEM and an hourly met grid as well, the whole hourly background
(:func:`imaging.background.build_background_from_files`). Everything is written into a
hidden sibling folder and moved into place at the end, so a failure leaves nothing behind.

The output folder is signed like a run folder (``manifest.json`` with ``"tool":
"shipthermal"``, ``"kind": "background"`` and the ``entries`` written): ``--out`` is a new
or empty folder, or with ``--force`` an earlier output of this command holding nothing
else; never a file, a folder of other files or a folder that holds an input.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import time
from pathlib import Path

from ..atomic import atomic_write_text
from ..errors import InputError, require
from .rundir.inputs import check_inputs
from .rundir.manifest import _now, new_manifest
from .rundir.ownership import (MANIFEST, _foreign_error, _foreign_names, _remove,
                               read_signature)

__all__ = ["run_background"]


def _parse_bounds(bounds):
    if bounds is None:
        return None
    require(len(bounds) == 4, "--bounds", bounds, "must be four numbers: west south east north "
            "in the scene's projected CRS [m]")
    return tuple(float(b) for b in bounds)


def _check_out(out: Path, inputs, force: bool) -> None:
    """Refuse an ``--out`` that this command may not write: a file; a folder that is or
    holds an input; a non-empty folder without ``force``; with ``force``, anything but an
    earlier output of this command that holds only what it wrote."""
    if os.path.lexists(out) and not out.is_dir():
        raise InputError("--out", str(out), "must be a folder (a file of that name exists)",
                         "Choose another --out: shipthermal never turns a file into a folder, "
                         "not even with --force")
    check_inputs(out, inputs)
    if not out.is_dir() or not any(out.iterdir()):
        return
    if not force:
        raise InputError("--out", str(out), "exists and is not empty", "Give --force to "
                         "replace an earlier output of `shipthermal background`, or another "
                         "--out")
    sig = read_signature(out)
    if sig is None or sig.legacy:
        raise InputError("--out", str(out), "is not an output folder of `shipthermal "
                         "background` (no manifest.json of it): --force replaces only those",
                         "Choose a new or empty folder")
    if sig.kind != "background":
        raise InputError("--out", str(out), f"is a shipthermal {sig.kind} folder, not an "
                         "output of `shipthermal background`: --force replaces only those",
                         "Choose a new or empty folder")
    foreign = _foreign_names(out, sig.entries)
    if foreign:
        raise _foreign_error(out, foreign)


def _put_in_place(tmp: Path, target: Path) -> None:
    """Move the finished products from ``tmp`` to ``target``: a rename when ``target`` does
    not exist; into an existing (empty, or earlier output) folder entry by entry, the
    manifest listing old and new entries while they are exchanged, so that whatever
    happens the folder holds only listed entries; the earlier output's other entries go."""
    if not os.path.lexists(target):
        try:
            os.rename(tmp, target)
            return
        except OSError:
            if not target.is_dir():     # made meanwhile: an empty folder is moved into
                raise
    sig = read_signature(target)
    old = set(sig.entries) if sig is not None and sig.kind == "background" else set()
    foreign = _foreign_names(target, old)      # checked again: it might have changed
    if foreign:
        raise _foreign_error(target, foreign)
    new = {c.name for c in tmp.iterdir()}
    interim = json.loads((tmp / MANIFEST).read_text(encoding="utf-8"))
    interim.update(entries=sorted(old | new), status="replacing")
    atomic_write_text(target / MANIFEST, json.dumps(interim, indent=2, default=str) + "\n")
    for name in sorted(old - new):
        _remove(target / name)
    for name in sorted(new - {MANIFEST}):
        src, dst = tmp / name, target / name
        if os.path.lexists(dst) and (src.is_dir() or (dst.is_dir() and not dst.is_symlink())):
            _remove(dst)
        os.replace(src, dst)
    os.replace(tmp / MANIFEST, target / MANIFEST)
    tmp.rmdir()


def run_background(out, mtl, roi, *, dem=None, met=None, band_files=None, bounds=None,
                   use_qa: bool = True, n_splits: int = 10, seed: int = 0,
                   utc_offset_hours: float = 0.0, water_vapour: float | None = None,
                   krige_coarsen: int = 5, variogram_model: str = "spherical",
                   force: bool = False, log=print, progress: bool = False, command=None,
                   inputs=()) -> dict:
    """Build the port background from files and write it into ``out``.

    Parameters
    ----------
    out : path-like
        Output folder: new or empty; with ``force`` also an earlier output of this command
        that holds nothing else. Never a file, nor a folder that is or holds an input.
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
        Replace an earlier output of this command (only the entries its manifest lists).
    log : callable
        Receives notes (one line each).
    command : list of str, optional
        Command line recorded in the manifest (default ``sys.argv``).
    inputs : iterable of path-like
        Further files read (e.g. the scenario file): ``out`` may not hold them either.

    Returns
    -------
    dict
        ``files`` written, ``summary`` (key figures), ``seconds``.
    """
    out = Path(out)
    read = [mtl, roi, dem, met, *inputs]
    if mtl and band_files and os.path.dirname(str(band_files)):
        read.append(os.path.join(os.path.dirname(str(mtl)), os.path.dirname(str(band_files))))
    _check_out(out, read, force)
    require((dem is None) == (met is None), "--dem/--met", f"dem={dem}, met={met}",
            "go together: both give the hourly background, neither the overpass products only")
    bounds = _parse_bounds(bounds)
    # deferred: imaging.background loads scikit-learn, pykrige and scipy.stats (0.8 s of every
    # command's start-up, measured)
    from imaging.background import build_background_from_files
    from imaging.background.background import build_overpass
    from imaging.background.landsat import read_landsat_scene
    from imaging.background.outputs import write_overpass_outputs

    t0 = time.perf_counter()
    target = Path(os.path.abspath(out))
    manifest = new_manifest("background", command)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.part-", dir=target.parent))
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)        # as a plain mkdir would make it
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
        manifest.update(entries=sorted({c.name for c in tmp.iterdir()} | {MANIFEST}),
                        status="complete", finished=_now(),
                        seconds=round(time.perf_counter() - t0, 3),
                        inputs={k: (str(v) if v is not None else None) for k, v in
                                (("mtl", mtl), ("roi", roi), ("dem", dem), ("met", met))})
        atomic_write_text(tmp / MANIFEST, json.dumps(manifest, indent=2, default=str) + "\n")
        _put_in_place(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    for n in notes:
        log(f"note: {n}")
    files = {k: str(out / Path(v).name) for k, v in files.items()}
    return {"files": files, "summary": summary, "seconds": time.perf_counter() - t0}
