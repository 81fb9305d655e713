"""Pictures and VTK files of a ship's parts.

* :func:`render_parts_png` — off-screen PNG coloured by part (pyvista/VTK through EGL; if
  VTK cannot render, matplotlib's ``plot_trisurf``-style ``Poly3DCollection`` instead);
* :func:`write_parts_vtu` — one ``.vtu`` per part plus ``all_parts.vtu`` with a ``part``
  cell array, for ParaView.

Files are written to a temporary name and moved into place (nothing half-written).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..figures import OKABE_ITO
from .parts import main_part

__all__ = ["PART_COLOURS", "render_parts_png", "render_values_png", "write_parts_vtu",
           "ship_polydata"]

PART_COLOURS = {
    "hull_wetted": "#8b2d2d",       # antifouling red
    "hull_dry": "#7a8590",          # haze grey
    "deck": "#3c4247",              # dark non-skid
    "superstructure": "#c9ced3",    # light grey
}
#: Sub-parts (funnel, gun, mast, ...): Okabe–Ito orange, blue, yellow, which stay apart from
#: each other and from the part colours under simulated colour-blindness
#: (:data:`shipthermal.figures.MIN_CVD_DELTA_E`; tests/imaging/test_img_figures.py)
_SUB_COLOURS = [OKABE_ITO["orange"], OKABE_ITO["blue"], OKABE_ITO["yellow"]]


def _colour_table(part_names):
    out, k = {}, 0
    for name in part_names:
        if name in PART_COLOURS:
            out[name] = PART_COLOURS[name]
        else:
            out[name] = _SUB_COLOURS[k % len(_SUB_COLOURS)] if main_part(name) else "#999999"
            k += 1
    return out


def ship_polydata(ship):
    """The ship surface as :class:`pyvista.PolyData` with ``part`` and ``area`` cell arrays."""
    import pyvista as pv        # deferred: start-up cost (~1 s to import)

    cells = np.hstack([np.full((ship.n_faces, 1), 3), ship.faces]).ravel()
    poly = pv.PolyData(np.asarray(ship.vertices), cells)
    poly.cell_data["part"] = np.asarray(ship.face_part, dtype=np.int32)
    poly.cell_data["area"] = ship.face_areas
    poly.field_data["part_names"] = np.array(ship.part_names)
    return poly


def write_parts_vtu(ship, directory) -> list[Path]:
    """Write ``<part>.vtu`` for each part and ``all_parts.vtu``; returns the paths."""
    import pyvista as pv        # deferred: start-up cost (~1 s to import)

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    poly = ship_polydata(ship)
    written = []
    grids = [("all_parts", pv.UnstructuredGrid(poly))]
    for k, name in enumerate(ship.part_names):
        sub = poly.extract_cells(np.flatnonzero(ship.face_part == k))
        grids.append((name, sub))
    for name, grid in grids:
        grid.field_data["part_names"] = np.array(ship.part_names)
        path = directory / f"{name}.vtu"
        with atomic_path(path) as tmp:
            grid.save(tmp)
        written.append(path)
    return written


def render_parts_png(ship, path, size=(1600, 900), backend: str = "auto",
                     view: str = "iso", colours: dict | None = None) -> str:
    """Render the ship coloured by part to a PNG.

    Parameters
    ----------
    ship : ShipGeometry
    path : str or Path
        Output PNG.
    size : (int, int)
        Image size [pixel].
    backend : {'auto', 'pyvista', 'matplotlib'}
        'auto' tries pyvista off-screen (EGL) and falls back to matplotlib.
    view : {'iso', 'side'}
    colours : dict, optional
        Colour per part name (default :data:`PART_COLOURS`, sub-parts in a palette).

    Returns
    -------
    str
        The backend that rendered the picture.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if backend in ("auto", "pyvista"):
        try:
            _render_pyvista(ship, path, size, view, colours)
            return "pyvista"
        except Exception:
            if backend == "pyvista":
                raise
    _render_matplotlib(ship, path, size, view, colours)
    return "matplotlib"


def _pyvista_plotter(size):
    """An off-screen pyvista plotter (EGL, white background)."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv        # deferred: start-up cost (~1 s to import)

    pv.OFF_SCREEN = True
    pl = pv.Plotter(off_screen=True, window_size=list(size))
    pl.set_background("white")
    return pl


def _pyvista_shoot(pl, ship, view: str, zoom: float, path: Path) -> None:
    """Place the camera ('iso' or 'side' from starboard, bow to the right), write the PNG."""
    L = ship.length
    if view == "side":
        pl.camera_position = [(0, -2.2 * L, 0.05 * L), (0, 0, 0.05 * L), (0, 0, 1)]
    else:
        pl.camera_position = [(0.9 * L, -1.1 * L, 0.55 * L), (0, 0, 0.03 * L), (0, 0, 1)]
    pl.reset_camera()
    pl.camera.zoom(zoom)
    with atomic_path(path) as tmp:
        pl.screenshot(str(tmp))
        pl.close()


def _mpl_frame(ax, ship, view: str) -> None:
    """Equal axis ranges around the ship, the view angle, no axes."""
    lo, hi = ship.vertices.min(axis=0), ship.vertices.max(axis=0)
    mid, rad = 0.5 * (lo + hi), 0.5 * (hi - lo).max()
    ax.set_xlim(mid[0] - rad, mid[0] + rad)
    ax.set_ylim(mid[1] - rad, mid[1] + rad)
    ax.set_zlim(mid[2] - rad, mid[2] + rad)
    ax.view_init(elev=5 if view == "side" else 25, azim=-90 if view == "side" else -50)
    ax.set_axis_off()


def _render_pyvista(ship, path: Path, size, view, colours=None):
    colours = {**_colour_table(ship.part_names), **(colours or {})}
    poly = ship_polydata(ship)
    pl = _pyvista_plotter(size)
    for k, name in enumerate(ship.part_names):
        ids = np.flatnonzero(ship.face_part == k)
        if len(ids) == 0:
            continue
        pl.add_mesh(poly.extract_cells(ids), color=colours[name], label=name,
                    show_edges=False, smooth_shading=False)
    pl.add_legend(bcolor="white", size=(0.18, 0.2), loc="upper left")
    _pyvista_shoot(pl, ship, view, 1.5, path)


def _render_matplotlib(ship, path: Path, size, view, colours=None):
    import matplotlib           # deferred: start-up cost (pyplot takes ~1 s to import)

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    colours = {**_colour_table(ship.part_names), **(colours or {})}
    dpi = 100
    fig = plt.figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi)
    ax = fig.add_subplot(projection="3d")
    tri = ship.vertices[ship.faces]
    normals = ship.face_normals
    light = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
    shade = 0.55 + 0.45 * np.clip(normals @ light, 0, 1)
    from matplotlib.colors import to_rgb

    base = np.array([to_rgb(colours[n]) for n in ship.part_names])[ship.face_part]
    coll = Poly3DCollection(tri, facecolors=np.clip(base * shade[:, None], 0, 1), linewidths=0)
    ax.add_collection3d(coll)
    _mpl_frame(ax, ship, view)
    handles = [plt.Rectangle((0, 0), 1, 1, color=colours[n]) for n in ship.part_names]
    ax.legend(handles, ship.part_names, loc="upper left", fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, bbox_inches="tight")
        plt.close(fig)


def render_values_png(ship, values, path, title: str = "", clim=None, size=(1400, 800),
                      label: str = "T [K]", cmap: str = "inferno", backend: str = "auto",
                      view: str = "iso") -> str:
    """Render the ship coloured by one value per triangle (e.g. surface temperature) to a PNG.

    ``clim`` defaults to the 1st–99th percentile of ``values``. Backends as
    :func:`render_parts_png`; returns the one that rendered.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    values = np.asarray(values, dtype=float)
    clim = clim or (float(np.percentile(values, 1)), float(np.percentile(values, 99)))
    if backend in ("auto", "pyvista"):
        try:
            poly = ship_polydata(ship)
            poly.cell_data["values"] = values
            pl = _pyvista_plotter(size)
            pl.add_mesh(poly, scalars="values", cmap=cmap, clim=clim,
                        scalar_bar_args=dict(title=label, color="black", vertical=True))
            pl.add_text(title, font_size=10, color="black")
            _pyvista_shoot(pl, ship, view, 1.4, path)
            return "pyvista"
        except Exception:
            if backend == "pyvista":
                raise
    import matplotlib           # deferred: start-up cost (pyplot takes ~1 s to import)

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import cm, colors
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig = plt.figure(figsize=(size[0] / 100, size[1] / 100), dpi=100)
    ax = fig.add_subplot(projection="3d")
    norm = colors.Normalize(*clim)
    colourmap = matplotlib.colormaps[cmap]
    ax.add_collection3d(Poly3DCollection(ship.vertices[ship.faces],
                                         facecolors=colourmap(norm(values)), linewidths=0))
    _mpl_frame(ax, ship, view)
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=colourmap), ax=ax, label=label, shrink=0.6)
    ax.set_title(title, fontsize=9)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, bbox_inches="tight")
        plt.close(fig)
    return "matplotlib"
