"""Surface-temperature maps of a moored ship: framed on the ship, north and sun marked.

One PNG, two views of the same colour scale:

* left, an oblique view from the ship's starboard quarter (bow to the right), framed on
  the ship (equal scale, a few percent margin);
* right, the ship as the sensor sees it (orthographic, along the sensor's view direction;
  at nadir a plan view with north up and east right), with a north arrow and the direction
  of the sun (compass azimuth, elevation in the legend; dashed when it is below the horizon).

Drawn with matplotlib's 2-D polygons in painter's order (far faces first), so it needs no
OpenGL and renders the same everywhere.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..figures import save_figure

__all__ = ["render_surface_map", "ship_to_enu", "project", "surface_frame_figure"]

#: Oblique view of the left panel in the ship frame (x bow, y port, z up): azimuth and
#: elevation of the viewer [deg] (matplotlib convention: starboard-aft quarter).
OBLIQUE_VIEW_DEG = (-50.0, 25.0)


def ship_to_enu(heading_deg: float) -> np.ndarray:
    """3 x 3 matrix taking ship-frame vectors (x bow, y port, z up) to east-north-up for a
    bow heading ``heading_deg`` (compass, clockwise from north) [-]."""
    h = np.radians(heading_deg)
    bow = np.array([np.sin(h), np.cos(h), 0.0])
    port = np.array([-np.cos(h), np.sin(h), 0.0])
    return np.column_stack([bow, port, [0.0, 0.0, 1.0]])


def _basis(azim_deg: float, elev_deg: float):
    """(right, up, toward-viewer) unit vectors of an orthographic view from azimuth
    ``azim_deg`` (counter-clockwise from +x) and elevation ``elev_deg``."""
    a, e = np.radians(azim_deg), np.radians(elev_deg)
    view = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    return right, np.cross(view, right), view


def project(points, azim_deg: float, elev_deg: float):
    """Screen ``u`` (right), ``v`` (up) and depth toward the viewer of ``points`` (n, 3)."""
    right, up, view = _basis(azim_deg, elev_deg)
    p = np.asarray(points, dtype=float)
    return p @ right, p @ up, p @ view


def _sensor_view(view_zenith_deg: float, view_azimuth_deg: float):
    """(azimuth, elevation) in ENU of the view from the sensor: compass azimuth of the
    sensor seen from the ship; at nadir north up, east right."""
    elev = 90.0 - float(view_zenith_deg)
    if view_zenith_deg < 1e-6:
        return -90.0, 90.0
    return 90.0 - float(view_azimuth_deg), elev


def _draw(ax, verts, faces, values, azim, elev, norm, cmap):
    from matplotlib.collections import PolyCollection   # deferred: start-up cost

    u, v, depth = project(verts, azim, elev)
    order = np.argsort(depth[faces].mean(axis=1))          # far faces first
    coll = PolyCollection(np.stack([u[faces], v[faces]], axis=-1)[order], cmap=cmap,
                          norm=norm, edgecolors="face", linewidths=0.1)
    coll.set_array(np.asarray(values)[order])
    ax.add_collection(coll)
    du, dv = np.ptp(u), np.ptp(v)
    m = 0.04 * max(du, dv)
    ax.set_xlim(u.min() - m, u.max() + m)
    ax.set_ylim(v.min() - m, v.max() + m)
    ax.set_aspect("equal")
    return coll


def _arrow(ax, vec_screen, label, colour, dashed=False):
    """An arrow from the centre of a (-1.5, 1.5) inset along a screen direction; its
    length shows how much of the direction lies in the picture plane."""
    d = np.asarray(vec_screen, dtype=float)
    if np.hypot(*d) < 0.05:
        ax.annotate(label + " ⊙", (0, 0), fontsize=7, color=colour, ha="center")
        return
    ax.annotate("", xy=(d[0], d[1]), xytext=(0, 0),
                arrowprops=dict(arrowstyle="-|>", color=colour, lw=1.4,
                                ls="--" if dashed else "-"))
    ax.annotate(label, (1.3 * d[0], 1.3 * d[1]), fontsize=7, color=colour, ha="center",
                va="center")


def render_surface_map(vertices, faces, values, path, *, heading_deg: float,
                       sun_azimuth_deg: float, sun_elevation_deg: float,
                       view_zenith_deg: float = 0.0, view_azimuth_deg: float = 0.0,
                       title: str = "", clim=None, label: str = "outer-surface temperature [K]",
                       cmap: str = "inferno", dpi: int = 100, figures=None) -> Path:
    """Write the two-view surface map of a ship coloured by one value per triangle.

    Parameters
    ----------
    vertices, faces : array_like
        Ship-frame mesh (x bow, y port, z up) [m] and triangles.
    values : array_like
        One value per triangle (e.g. outer-surface temperature [K]).
    path : path-like
        PNG to write (atomically).
    heading_deg : float
        Compass heading of the bow [deg].
    sun_azimuth_deg, sun_elevation_deg : float
        Sun position (compass azimuth, elevation above the horizon) [deg].
    view_zenith_deg, view_azimuth_deg : float
        Sensor direction seen from the ship (zenith angle, compass azimuth) [deg].
    title : str
        First title line (site, date, season, time).
    clim : (float, float) or None
        Colour limits; default the 1st-99th percentile of ``values``.
    dpi : int
        Resolution [dots per inch] when no ``figures`` are given.
    figures : shipthermal.figures.FigureOptions or None
        Resolution and vector copies (:func:`shipthermal.figures.save_figure`).
    """
    import matplotlib           # deferred: start-up cost (pyplot takes ~1 s to import)

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize
    from matplotlib.ticker import MaxNLocator

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=int)
    vals = np.asarray(values, dtype=float)
    clim = clim or (float(np.percentile(vals, 1)), float(np.percentile(vals, 99)))
    norm = Normalize(*clim)
    R = ship_to_enu(heading_deg)
    enu = v @ R.T
    az, el = _sensor_view(view_zenith_deg, view_azimuth_deg)
    ratios = []
    for pts, (a, e) in ((v, OBLIQUE_VIEW_DEG), (enu, (az, el))):
        pu, pv, _ = project(pts, a, e)
        ratios.append(float(np.clip(np.ptp(pu) / max(np.ptp(pv), 1e-9), 0.45, 4.0)))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12.0, 4.8), dpi=dpi,
                                 gridspec_kw={"width_ratios": ratios},
                                 constrained_layout=True)
    coll = _draw(a1, v, f, vals, *OBLIQUE_VIEW_DEG, norm, cmap)
    a1.set_title("oblique view from the starboard quarter (bow right)", fontsize=8)
    _draw(a2, enu, f, vals, az, el, norm, cmap)
    a2.set_title(f"from the sensor\n(zenith {view_zenith_deg:g}°, azimuth "
                 f"{view_azimuth_deg:g}°)", fontsize=8)
    for ax in (a1, a2):
        ax.tick_params(labelsize=7)
        ax.set_xlabel("m", fontsize=7)
    # north and sun on both views (ENU directions turned into each view's screen axes)
    sun_h = np.array([np.sin(np.radians(sun_azimuth_deg)), np.cos(np.radians(sun_azimuth_deg)),
                      0.0])
    north = np.array([0.0, 1.0, 0.0])
    below = sun_elevation_deg < 0
    sun_label = (f"sun {sun_azimuth_deg:.0f}° az, {sun_elevation_deg:.0f}° elev"
                 + (" (below horizon)" if below else ""))
    for ax, (azv, elv), to_frame in ((a1, OBLIQUE_VIEW_DEG, R.T), (a2, (az, el), np.eye(3))):
        right, up, _ = _basis(azv, elv)
        x0, x1 = ax.get_xlim()
        y0, y1 = ax.get_ylim()
        aspect = (x1 - x0) / (y1 - y0)          # width / height of the equal-scale box
        w, h = (0.6, 0.6 * aspect) if aspect < 1 else (0.3 / aspect, 0.3)   # a square inset
        inset = ax.inset_axes([0.0, 1.0 - h, w, h])
        inset.set_xlim(-1.5, 1.5)
        inset.set_ylim(-1.5, 1.5)
        inset.set_aspect("equal")
        inset.axis("off")
        for vec, lab, col, dash in ((north, "N", "#0969da", False),
                                    (sun_h, "sun", "#bc4c00", below)):
            w = to_frame @ vec
            _arrow(inset, (w @ right, w @ up), lab, col, dash)
    cb = fig.colorbar(coll, ax=[a1, a2], shrink=0.85, pad=0.01)
    cb.set_label(label, fontsize=8)
    cb.locator = MaxNLocator(nbins=7, steps=[1, 2, 2.5, 5, 10])
    cb.formatter = matplotlib.ticker.FormatStrFormatter("%g")
    cb.update_ticks()
    cb.ax.tick_params(labelsize=7)
    fig.suptitle(f"{title}\n{sun_label}; colour scale {clim[0]:.1f}–{clim[1]:.1f} K",
                 fontsize=9)
    save_figure(fig, path, figures, dpi=None if figures else dpi)
    plt.close(fig)
    return path


def surface_frame_figure(vertices, faces, vmin: float, vmax: float):
    """The figure of a slider frame: the ship's triangles seen obliquely, far ones first,
    as a polygon collection on the colour scale ``vmin`` … ``vmax`` [K] with its colour
    bar and an empty title. Returns ``(fig, ax, collection, title, order)``: ``order``
    the triangles' drawing order (the collection's rows)."""
    # lazy: matplotlib takes most of a second to import (measured)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    u, w, depth = project(vertices, *OBLIQUE_VIEW_DEG)
    order = np.argsort(depth[faces].mean(axis=1))       # far faces first (painter's order)
    polys = np.stack([u[faces], w[faces]], axis=-1)[order]
    fig, ax = plt.subplots(figsize=(5.2, 2.6), dpi=80)
    coll = PolyCollection(polys, cmap="inferno", edgecolors="none", antialiaseds=False)
    coll.set_clim(vmin, vmax)
    ax.add_collection(coll)
    ax.set_xlim(u.min() - 1, u.max() + 1)
    ax.set_ylim(w.min() - 1, w.max() + 1)
    ax.set_aspect("equal")
    ax.axis("off")
    cb = fig.colorbar(coll, ax=ax, shrink=0.8, pad=0.01)
    cb.set_label("outer-surface temperature [K]", fontsize=7)
    cb.ax.tick_params(labelsize=6)
    return fig, ax, coll, ax.set_title("", fontsize=8), order
