"""What a mesh file is, read from its first bytes before its body is read.

A mesh file that is damaged, truncated, of another format than its name says, or far too
large must be refused quickly with a message that names the file and says what is wrong,
never by a parser's exception after minutes and gigabytes:

* :func:`sniff_mesh_file` — from the header only: the format, the declared triangle count
  (binary STL, PLY), whether the body has the length the header promises (binary STL),
  and the size limits :data:`MAX_MESH_FILE_BYTES` and :data:`MAX_MESH_TRIANGLES`;
* :func:`ascii_stl_problem` — the first line of an ASCII STL whose numbers do not parse
  (its line number, never its text).

Messages never quote the file's contents: a path may point at a file the user did not
mean to show (a link to a protected file).
"""

from __future__ import annotations

import os
import re
import struct
from pathlib import Path

from ..errors import InputError

__all__ = ["MAX_MESH_FILE_BYTES", "MAX_MESH_TRIANGLES", "sniff_mesh_file",
           "ascii_stl_problem"]

MAX_MESH_FILE_BYTES = 1 << 30
"""Largest mesh file read [bytes] (1 GiB: a binary STL of 21 million triangles, ten times
:data:`MAX_MESH_TRIANGLES`' worth of text formats; a ship export is tens of MB)."""

MAX_MESH_TRIANGLES = 5_000_000
"""Most triangles a mesh file may declare (2.5 times the solver's limit
:data:`shipthermal.geometry.remesh.MAX_SURFACE_FACES`, so that a fine export can still be
remeshed coarser with ``ship.edge_length``)."""

_PLY_ELEMENT = re.compile(rb"^element\s+(\w+)\s+(\d+)\s*$")


def _mib(n: int) -> str:
    return f"{n / 2 ** 20:.0f} MiB" if n >= 2 ** 20 else f"{n} bytes"


def sniff_mesh_file(path, field: str = "ship.files.mesh") -> dict:
    """Check a mesh file from its header: format, declared size, limits.

    Parameters
    ----------
    path : path-like
    field : str
        Scenario key named in messages.

    Returns
    -------
    dict
        ``format`` ('stl_binary', 'stl_ascii', 'ply', or the suffix without the dot),
        ``triangles`` declared (binary STL, PLY; None otherwise), ``bytes``.

    Raises
    ------
    InputError
        A file larger than :data:`MAX_MESH_FILE_BYTES`, declaring more than
        :data:`MAX_MESH_TRIANGLES` triangles or none, a binary STL whose length does not
        match its triangle count, a file that is not of the format its name says.
    """
    p = Path(path)
    name = p.name
    size = os.path.getsize(p)
    ext = p.suffix.lower()
    if size > MAX_MESH_FILE_BYTES:
        raise InputError(field, name, f"is {_mib(size)}, more than the {_mib(MAX_MESH_FILE_BYTES)} "
                         "a ship mesh file may have", "Export the ship coarser (a ship needs "
                         f"at most {MAX_MESH_TRIANGLES:,} triangles), or check that this is the "
                         "right file")
    if size == 0:
        raise InputError(field, name, "is empty (0 bytes)", "Export the ship again")
    with open(p, "rb") as fh:
        head = fh.read(65536)
    info = {"format": ext.lstrip("."), "triangles": None, "bytes": size}
    if ext == ".stl":
        info.update(_sniff_stl(head, size, name, field))
    elif ext == ".ply":
        info.update(_sniff_ply(head, name, field))
    elif ext in (".obj", ".off", ".vtk") and b"\0" in head[:4096]:
        raise InputError(field, name, f"is not a text {ext[1:].upper()} file (it holds binary "
                         "data)", f"Export the ship as {ext[1:].upper()}, or give the file the "
                         "suffix of its format")
    elif ext == ".glb" and head[:4] != b"glTF":
        raise InputError(field, name, "is not a binary glTF file (a .glb starts with 'glTF')",
                         "Export the ship as GLB again, or give the file the suffix of its format")
    n = info["triangles"]
    if n is not None and n > MAX_MESH_TRIANGLES:
        raise InputError(field, name, f"declares {n:,} triangles, more than the "
                         f"{MAX_MESH_TRIANGLES:,} a ship mesh may have",
                         "Export the ship coarser (ship.edge_length then sets the solver's mesh)")
    if n == 0:
        raise InputError(field, name, "holds no triangles (its header declares 0)",
                         "Export the ship surface as triangles")
    return info


def _sniff_stl(head: bytes, size: int, name: str, field: str) -> dict:
    if len(head) >= 84:
        n = struct.unpack("<I", head[80:84])[0]
        if size == 84 + 50 * n:
            return {"format": "stl_binary", "triangles": n}
    text = head.lstrip()
    if text[:5].lower() == b"solid" and b"\0" not in head:
        return {"format": "stl_ascii", "triangles": None}
    if len(head) >= 84:
        n = struct.unpack("<I", head[80:84])[0]
        expected = 84 + 50 * n
        raise InputError(field, name, "is not a readable STL file: a binary STL holds an "
                         "80-byte header, a triangle count and 50 bytes per triangle, and "
                         f"this file's count ({n:,}) needs {expected:,} bytes where it has "
                         f"{size:,}; an ASCII STL starts with 'solid'",
                         "The file is truncated, damaged or of another format: export the "
                         "ship as STL again")
    raise InputError(field, name, f"is not an STL file ({size} bytes: too short for a binary "
                     "STL, and it does not start with 'solid')", "Export the ship as STL again")


def _sniff_ply(head: bytes, name: str, field: str) -> dict:
    if not head.startswith(b"ply"):
        raise InputError(field, name, "is not a PLY file (a PLY file starts with 'ply')",
                         "Export the ship as PLY again, or give the file the suffix of its "
                         "format")
    end = head.find(b"end_header")
    if end < 0:
        raise InputError(field, name, "has no complete PLY header ('end_header' missing in "
                         "its first 64 KiB)", "Export the ship as PLY again")
    faces = None
    for line in head[:end].splitlines():
        m = _PLY_ELEMENT.match(line.strip())
        if m and m.group(1) == b"face":
            faces = int(m.group(2))
    return {"format": "ply", "triangles": faces}


def ascii_stl_problem(path) -> str | None:
    """The first problem of an ASCII STL's numbers, as ``"line N: ..."`` (None if every
    ``vertex`` / ``facet normal`` line holds three numbers)."""
    with open(path, "rb") as fh:
        for k, raw in enumerate(fh, start=1):
            words = raw.split()
            if not words:
                continue
            key = words[0].lower()
            if key == b"vertex":
                nums = words[1:]
                what = "a vertex"
            elif key == b"facet" and len(words) > 1 and words[1].lower() == b"normal":
                nums = words[2:]
                what = "a facet normal"
            else:
                continue
            if len(nums) != 3:
                return f"line {k}: {what} needs 3 numbers, found {len(nums)} fields"
            for x in nums:
                try:
                    float(x)
                except ValueError:
                    return f"line {k}: {what} coordinate is not a number"
    return None
