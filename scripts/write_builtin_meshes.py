"""Write the built-in ships to meshes/ as files a user can open.

For each ship (frigate, patrol_boat, cargo_ship), at a coarse edge length so the repository
stays small (the fine default meshes are generated in code: ``shipthermal.geometry.frigate()``):

* ``meshes/<ship>.ply``            whole closed surface, triangles sorted by part
* ``meshes/<ship>_parts.json``     part map (face ranges), units, particulars, layups
* ``meshes/<ship>_parts/<part>.stl`` one binary STL per part
* ``meshes/<ship>.png``            picture coloured by part

Read back with ``shipthermal.geometry.io.read_ship("meshes/frigate.ply", units="m",
part_map="meshes/frigate_parts.json")``.

Usage: ``python scripts/write_builtin_meshes.py [outdir]``
"""

import sys
from pathlib import Path

from shipthermal.geometry import cargo_ship, frigate, patrol_boat
from shipthermal.geometry.io import write_ship
from shipthermal.geometry.pictures import render_parts_png

COARSE_EDGE = {"frigate": 2.5, "patrol_boat": 1.0, "cargo_ship": 3.5}   # [m]


def main(outdir: str = "meshes") -> None:
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    for build in (frigate, patrol_boat, cargo_ship):
        name = build.__name__
        ship = build(COARSE_EDGE[name])
        write_ship(ship, out)
        backend = render_parts_png(ship, out / f"{name}.png", size=(1200, 600))
        print(f"{name}: {ship.n_faces} triangles at {COARSE_EDGE[name]} m, "
              f"area {ship.total_area:.0f} m2, volume {ship.signed_volume:.0f} m3 ({backend} picture)")


if __name__ == "__main__":
    main(*sys.argv[1:])
