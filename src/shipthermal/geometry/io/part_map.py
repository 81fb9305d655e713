"""Part maps: per-triangle part labels from an array, face ranges or a JSON file."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from ...errors import InputError, require

__all__ = ["read_part_map"]


def read_part_map(part_map, n_faces: int, part_names: Sequence[str] | None = None):
    """Per-triangle part labels from a part map.

    Parameters
    ----------
    part_map : array, dict or path
        * (M,) ints indexing ``part_names``, or (M,) part-name strings;
        * ``{part: [[start, stop], ...]}`` face ranges (stop exclusive), or a JSON file
          holding that mapping (optionally under a ``"parts"`` key).
    n_faces : int
        Number of triangles of the mesh.

    Returns
    -------
    labels (M,) int, names tuple
    """
    if isinstance(part_map, (str, os.PathLike)):
        path = Path(part_map)
        require(path.exists(), "part_map", str(path), "file not found")
        with open(path) as fh:
            part_map = json.load(fh)
        if isinstance(part_map, dict) and "parts" in part_map:
            part_map = part_map["parts"]
    if isinstance(part_map, Mapping):
        names = tuple(part_map)
        labels = np.full(n_faces, -1, np.int64)
        for k, name in enumerate(names):
            ranges = part_map[name]
            ranges = [ranges] if len(ranges) == 2 and np.isscalar(ranges[0]) else ranges
            for r in ranges:
                require(len(r) == 2 and 0 <= int(r[0]) <= int(r[1]) <= n_faces,
                        f"part_map[{name!r}]", r, f"must be [start, stop] with 0 <= start <= stop <= {n_faces}")
                seg = labels[int(r[0]):int(r[1])]
                clash = seg >= 0
                if clash.any():
                    i = int(r[0]) + int(np.argmax(clash))
                    raise InputError(f"part_map[{name!r}]", r, f"overlaps part {names[seg[clash][0]]!r} "
                                     f"at face {i}: every face must belong to exactly one part")
                labels[int(r[0]):int(r[1])] = k
        missing = np.flatnonzero(labels < 0)
        if len(missing):
            raise InputError("part_map", f"{len(missing)} faces without a part",
                             f"must cover every face exactly once (first uncovered: face {missing[0]})",
                             f"Add ranges so that faces 0..{n_faces - 1} are all assigned")
        return labels, names
    arr = np.asarray(part_map)
    require(arr.shape == (n_faces,), "part_map", arr.shape, f"must hold one entry per face ({n_faces})")
    if arr.dtype.kind in "US":
        names, labels = np.unique(arr, return_inverse=True)
        return labels.astype(np.int64), tuple(str(n) for n in names)
    require(part_names is not None, "part_names", None, "are required with an integer part map")
    labels = arr.astype(np.int64)
    require(labels.min() >= 0 and labels.max() < len(part_names), "part_map",
            (int(labels.min()), int(labels.max())), f"must index part_names (0..{len(part_names) - 1})")
    return labels, tuple(part_names)
