"""How every figure looks and is saved: categorical palettes a colour-blind reader can
tell apart, line styles, unit labels as printed, and the output options (resolution of the
PNGs, vector copies for publication).

The categorical colours are taken from the Okabe–Ito palette (SOURCED: M. Okabe and K. Ito,
"Color Universal Design (CUD): how to make figures and presentations that are friendly to
colorblind people", 2008, jfly.uni-koeln.de/color), chosen per figure so that every pair
stays at least :data:`MIN_CVD_DELTA_E` apart in CIEDE2000 under simulated protanopia,
deuteranopia and tritanopia (tests/imaging/test_img_figures.py simulates them with the
matrices of Machado, Oliveira and Fernandes 2009). Lines that share a figure also differ in
dash pattern, so they stay apart in grey print.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .atomic import atomic_path

__all__ = ["OKABE_ITO", "CLASS_COLOURS", "BAND_STYLES", "LINE_STYLES", "PART_LINE_STYLES",
           "MIN_CVD_DELTA_E", "unit_label", "band_label", "FigureOptions", "save_figure",
           "VECTOR_FORMATS", "add_scale_bar", "polygon_index_raster"]

#: The Okabe–Ito palette (SOURCED: Okabe & Ito 2008)
OKABE_ITO = {"black": "#000000", "orange": "#E69F00", "sky_blue": "#56B4E9",
             "bluish_green": "#009E73", "yellow": "#F0E442", "blue": "#0072B2",
             "vermillion": "#D55E00", "reddish_purple": "#CC79A7"}

#: Smallest CIEDE2000 difference between two categorical colours of one figure under each
#: simulated dichromacy [-]. ASSUMPTION: a margin chosen here, ten just-noticeable
#: differences (ΔE00 ≈ 1 is one: G. Sharma, W. Wu, E. N. Dalal, Color Res. Appl. 30, 2005),
#: for small legend patches and thin lines seen at a glance; the palette's closest pair is
#: what limits telling categories apart (Gramazio, Laidlaw, Schloss, IEEE TVCG 23, 2017).
MIN_CVD_DELTA_E = 10.0

#: Land-cover classes by name: water blue, vegetation green, bare land yellow, buildings
#: vermillion (the old green/red pair fell to ΔE00 7 under deuteranopia)
CLASS_COLOURS = {"water": OKABE_ITO["blue"], "vegetation": OKABE_ITO["bluish_green"],
                 "land": OKABE_ITO["yellow"], "building": OKABE_ITO["vermillion"]}

#: The two infrared bands: (colour, dash pattern)
BAND_STYLES = {"3-5": (OKABE_ITO["blue"], "-"), "8-14": (OKABE_ITO["vermillion"], "--")}

#: Colours and dash patterns for the lines of one figure, in order of use
LINE_STYLES = ((OKABE_ITO["black"], "-"), (OKABE_ITO["blue"], "--"),
               (OKABE_ITO["orange"], "-."), (OKABE_ITO["reddish_purple"], ":"),
               (OKABE_ITO["sky_blue"], (0, (5, 1.5, 1, 1.5, 1, 1.5))),
               (OKABE_ITO["bluish_green"], (0, (8, 2))),
               (OKABE_ITO["vermillion"], (0, (2, 1))))

#: The part-mean temperature curves: part or medium → (colour, dash pattern, width)
PART_LINE_STYLES = {
    "hull": (OKABE_ITO["black"], "-", 2.0), "hull_dry": (OKABE_ITO["black"], "-", 2.0),
    "deck": (OKABE_ITO["orange"], "--", 2.0),
    "superstructure": (OKABE_ITO["blue"], "-.", 2.0),
    "hull_wetted": (OKABE_ITO["reddish_purple"], (0, (5, 1.5, 1, 1.5, 1, 1.5)), 1.6),
    "temp_air": (OKABE_ITO["sky_blue"], (0, (8, 2)), 1.4),
    "temp_sea": (OKABE_ITO["bluish_green"], ":", 1.4),
    "temp_sea_skin": (OKABE_ITO["vermillion"], (0, (2, 1)), 1.4),
}

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def unit_label(unit: str) -> str:
    """A UDUNITS unit as printed: ``"W m-2 sr-1"`` → ``"W m⁻² sr⁻¹"``, ``"um"`` →
    ``"µm"``."""
    words = []
    for w in str(unit).split():
        base = w.rstrip("-0123456789")
        power = w[len(base):]
        base = "µm" if base == "um" else base
        words.append(base + power.translate(_SUPERSCRIPT))
    return " ".join(words)


def band_label(band: str) -> str:
    """``"8-14"`` → ``"8–14 µm"``: a band as figures and files print it; a named band
    (``"landsat8_tirs_b10"``, a user sensor's ``"user"``) keeps its name."""
    lo, sep, hi = str(band).partition("-")
    numeric = sep and all(p.replace(".", "", 1).isdigit() for p in (lo, hi))
    return f"{lo}–{hi} µm" if numeric else str(band)


#: Vector formats a figure can also be written in (``outputs.formats``)
VECTOR_FORMATS = ("svg", "pdf")


@dataclass(frozen=True)
class FigureOptions:
    """How figures are written.

    Attributes
    ----------
    dpi : int
        Resolution of the PNGs [dots per inch] (``outputs.figure_dpi``; 300 for print).
    vector : tuple of str
        Also write each figure in these formats next to its PNG (``"svg"``, ``"pdf"``:
        ``outputs.formats``), same name, other suffix.
    """

    dpi: int = 110
    vector: tuple = ()

    @classmethod
    def from_outputs(cls, outputs) -> "FigureOptions":
        """From a scenario's ``[outputs]`` (``figure_dpi``, vector formats in ``formats``)."""
        return cls(dpi=int(getattr(outputs, "figure_dpi", cls.dpi)),
                   vector=tuple(f for f in getattr(outputs, "formats", ()) if f in VECTOR_FORMATS))


def save_figure(fig, path, options: FigureOptions | None = None, dpi: int | None = None,
                **savefig) -> Path:
    """Write ``fig`` as PNG at ``path`` (and its vector copies, :class:`FigureOptions`),
    each through a temporary name renamed into place, so no half-written file is left.
    ``dpi`` overrides the options' resolution (e.g. a small inline picture)."""
    options = options or FigureOptions()
    path = Path(path)
    for fmt, target in [("png", path)] + [(f, path.with_suffix(f".{f}")) for f in options.vector]:
        with atomic_path(target) as tmp:
            fig.savefig(tmp, format=fmt, dpi=dpi or options.dpi, **savefig)
    return path


def add_scale_bar(ax, width_km: float, colour: str = "white") -> None:
    """A scale bar in the lower right of map axes in km: a round length near a quarter of
    the map's width ``width_km`` [km], labelled in m below 1 km."""
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    target = width_km / 4.0
    length = max((v for v in (0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0)
                  if v <= target), default=0.05)
    label = f"{length * 1000:g} m" if length < 1.0 else f"{length:g} km"
    ax.add_artist(AnchoredSizeBar(ax.transData, length, label, "lower right", pad=0.3,
                                  color=colour, frameon=False, size_vertical=0.0,
                                  fontproperties={"size": 7}))


def polygon_index_raster(fig, ax, coll) -> np.ndarray:
    """The index (in ``coll``'s order) of the polygon drawn at each pixel of ``ax``, -1
    where none is: the figure drawn once with the polygons in colours that encode their
    index (24 bits, without antialiasing, so every pixel holds one polygon's exact
    colour), read back from the canvas inside the axes."""
    n = len(coll.get_paths())
    code = np.arange(1, n + 1)
    coll.set_array(None)
    coll.set_facecolor(np.stack([(code >> 16) & 255, (code >> 8) & 255, code & 255],
                                axis=1) / 255.0)
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(np.int64)
    x0, y0, x1, y1 = ax.get_window_extent().extents
    height = rgb.shape[0]
    rows = slice(int(round(height - y1)), int(round(height - y0)))
    cols = slice(int(round(x0)), int(round(x1)))
    rgb = rgb[rows, cols]
    index = (rgb[..., 0] << 16) + (rgb[..., 1] << 8) + rgb[..., 2] - 1
    # the figure's white background decodes past the last polygon
    return np.where(index < n, index, -1)
