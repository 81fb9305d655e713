"""Figures for publication: categorical colours a colour-blind reader can tell apart
(simulated), distinct line styles, units as printed, vector and 300 dpi output.

Colour-blindness is simulated with the matrices of Machado, Oliveira and Fernandes (2009,
IEEE TVCG 15(6), severity 1.0, applied to linear sRGB); colour differences are CIEDE2000
(Sharma, Wu and Dalal 2005, whose test pairs check the implementation here). Every pair of
colours that share a figure must stay :data:`~shipthermal.figures.MIN_CVD_DELTA_E` apart
under protanopia, deuteranopia and tritanopia (and with normal vision).
"""

import itertools

import numpy as np
import pytest

from shipthermal import figures as F

#: Machado et al. (2009), severity 1.0, linear sRGB
CVD = {"protanopia": ((0.152286, 1.052583, -0.204868), (0.114503, 0.786281, 0.099216),
                      (-0.003882, -0.048116, 1.051998)),
       "deuteranopia": ((0.367322, 0.860646, -0.227968), (0.280085, 0.672501, 0.047413),
                        (-0.011820, 0.042940, 0.968881)),
       "tritanopia": ((1.255528, -0.076749, -0.178779), (-0.078411, 0.930809, 0.147602),
                      (0.004733, 0.691367, 0.303900)),
       "normal": ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))}


def _linear(hex_colour):
    c = np.array([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)]) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _lab(rgb_linear):
    """CIELAB (D65) of linear sRGB."""
    xyz = np.array([[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750],
                    [0.0193339, 0.1191920, 0.9503041]]) @ rgb_linear
    t = xyz / np.array([0.95047, 1.0, 1.08883])
    f = np.where(t > (6 / 29) ** 3, np.cbrt(t), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def ciede2000(lab1, lab2):
    """CIEDE2000 colour difference (Sharma, Wu, Dalal 2005, eqs. 1-22)."""
    L1, a1, b1 = lab1
    L2, a2, b2 = lab2
    cb = 0.5 * (np.hypot(a1, b1) + np.hypot(a2, b2))
    g = 0.5 * (1 - np.sqrt(cb ** 7 / (cb ** 7 + 25.0 ** 7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1p, c2p = np.hypot(a1p, b1), np.hypot(a2p, b2)
    h1p = np.degrees(np.arctan2(b1, a1p)) % 360 if c1p else 0.0
    h2p = np.degrees(np.arctan2(b2, a2p)) % 360 if c2p else 0.0
    dl, dc = L2 - L1, c2p - c1p
    dh = 0.0 if c1p * c2p == 0 else (h2p - h1p + 180) % 360 - 180
    dhh = 2 * np.sqrt(c1p * c2p) * np.sin(np.radians(dh / 2))
    lb, cbp = 0.5 * (L1 + L2), 0.5 * (c1p + c2p)
    if c1p * c2p == 0:
        hb = h1p + h2p
    elif abs(h1p - h2p) <= 180:
        hb = 0.5 * (h1p + h2p)
    else:
        hb = 0.5 * (h1p + h2p + (360 if h1p + h2p < 360 else -360))
    t = (1 - 0.17 * np.cos(np.radians(hb - 30)) + 0.24 * np.cos(np.radians(2 * hb))
         + 0.32 * np.cos(np.radians(3 * hb + 6)) - 0.20 * np.cos(np.radians(4 * hb - 63)))
    dtheta = 30 * np.exp(-(((hb - 275) / 25) ** 2))
    rc = 2 * np.sqrt(cbp ** 7 / (cbp ** 7 + 25.0 ** 7))
    sl = 1 + 0.015 * (lb - 50) ** 2 / np.sqrt(20 + (lb - 50) ** 2)
    sc, sh = 1 + 0.045 * cbp, 1 + 0.015 * cbp * t
    rt = -np.sin(np.radians(2 * dtheta)) * rc
    return float(np.sqrt((dl / sl) ** 2 + (dc / sc) ** 2 + (dhh / sh) ** 2
                         + rt * (dc / sc) * (dhh / sh)))


def seen_as(hex_colour, vision):
    return _lab(np.clip(np.array(CVD[vision]) @ _linear(hex_colour), 0.0, 1.0))


def closest_pair(colours):
    """(ΔE00, vision, a, b) of the least distinct pair over all visions."""
    return min((ciede2000(seen_as(a, v), seen_as(b, v)), v, a, b)
               for v in CVD for a, b in itertools.combinations(colours, 2))


@pytest.mark.parametrize("lab1, lab2, expected", [          # Sharma et al. 2005, Table 1
    ((50.0, 2.6772, -79.7751), (50.0, 0.0, -82.7485), 2.0425),
    ((50.0, 3.1571, -77.2803), (50.0, 0.0, -82.7485), 2.8615),
    ((50.0, 2.8361, -74.0200), (50.0, 0.0, -82.7485), 3.4412),
    ((50.0, 0.0, 0.0), (50.0, -1.0, 2.0), 2.3669),
    ((50.0, 2.5, 0.0), (73.0, 25.0, -18.0), 27.1492),
])
def test_ciede2000_reproduces_sharmas_test_pairs(lab1, lab2, expected):
    assert ciede2000(lab1, lab2) == pytest.approx(expected, abs=1e-4)


def test_the_simulation_keeps_greys_and_merges_red_and_green_for_a_deuteranope():
    """Sanity of the simulation: greys stay grey; pure red and green, far apart for normal
    vision, come close for a deuteranope."""
    for g in ("#000000", "#808080", "#ffffff"):
        assert ciede2000(seen_as(g, "deuteranopia"), seen_as(g, "normal")) < 0.5
    red, green = "#ff0000", "#00ff00"
    assert ciede2000(seen_as(red, "normal"), seen_as(green, "normal")) > 80
    assert ciede2000(seen_as(red, "deuteranopia"), seen_as(green, "deuteranopia")) < 25


def test_the_check_catches_the_old_class_colours():
    """The class colours before this palette: vegetation and buildings ΔE00 7 apart under
    deuteranopia, the fault the check exists for."""
    old = ["#1f5fa8", "#2e8b3a", "#c8a165", "#d9423b"]
    de, vision, a, b = closest_pair(old)
    assert de < F.MIN_CVD_DELTA_E and vision == "deuteranopia" and {a, b} == {"#2e8b3a", "#d9423b"}


def _palettes():
    from imaging.background.classify import CLASS_COLOURS
    from shipthermal.geometry.pictures import _SUB_COLOURS, PART_COLOURS

    return {
        "land-cover classes": list(CLASS_COLOURS.values()),
        "bands": [c for c, _ in F.BAND_STYLES.values()],
        "part-mean curves": [c for c, _, _ in F.PART_LINE_STYLES.values()
                             if c != F.PART_LINE_STYLES["hull"][0]] + [F.PART_LINE_STYLES["hull"][0]],
        "lines": [c for c, _ in F.LINE_STYLES],
        "ship parts picture": list(PART_COLOURS.values()) + list(_SUB_COLOURS),
    }


@pytest.mark.parametrize("name", ["land-cover classes", "bands", "part-mean curves", "lines",
                                  "ship parts picture"])
def test_categorical_colours_stay_apart_under_colour_blindness(name):
    colours = list(dict.fromkeys(_palettes()[name]))
    assert len(colours) >= 2
    de, vision, a, b = closest_pair(colours)
    assert de >= F.MIN_CVD_DELTA_E, f"{name}: {a} and {b} are ΔE00 {de:.1f} apart for {vision}"


def test_curves_differ_in_dash_pattern_too():
    """Every curve of one figure has its own dash pattern, so lines stay apart in grey."""
    for styles in ([ls for _, ls in F.LINE_STYLES],
                   [ls for k, (_, ls, _) in F.PART_LINE_STYLES.items() if k != "hull_dry"],
                   [ls for _, ls in F.BAND_STYLES.values()]):
        assert len({str(s) for s in styles}) == len(styles)


def test_units_are_printed_with_superscripts_and_micro():
    assert F.unit_label("W m-2 sr-1") == "W m⁻² sr⁻¹"
    assert F.unit_label("W m-2 K-1") == "W m⁻² K⁻¹"
    assert F.unit_label("um") == "µm" and F.unit_label("K") == "K"
    assert F.band_label("8-14") == "8–14 µm"


def test_vector_and_300_dpi_output(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    fig, ax = plt.subplots(figsize=(2.0, 1.0))
    ax.plot([0, 1], [0, 1])
    path = F.save_figure(fig, tmp_path / "f.png", F.FigureOptions(dpi=300, vector=("svg", "pdf")))
    plt.close(fig)
    with Image.open(path) as im:
        assert im.size == (600, 300)
    assert (tmp_path / "f.svg").read_text().lstrip().startswith("<?xml")
    assert (tmp_path / "f.pdf").read_bytes()[:5] == b"%PDF-"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.pdf", "f.png", "f.svg"]


def test_figure_options_come_from_the_scenario():
    from shipthermal.app.scenario import default_scenario

    sc = default_scenario("summer").updated({"outputs.figure_dpi": 300,
                                              "outputs.formats": ["png", "svg", "csv"]})
    assert F.FigureOptions.from_outputs(sc.outputs) == F.FigureOptions(dpi=300, vector=("svg",))


def test_scr_figure_prints_units_and_marks_scr_one(tmp_path, monkeypatch):
    """The SCR figure: every text in µm and superscripts (no ASCII "um", "m-2"), a log SCR
    axis with SCR = 1 drawn."""
    import types

    import matplotlib
    import pandas as pd

    matplotlib.use("Agg")
    from matplotlib.text import Text

    from imaging import products

    t = np.arange(0.0, 24.01, 0.5)
    contrast = np.sin(2 * np.pi * (t - 6.0) / 24.0)
    m = pd.DataFrame({"time_h": t, "scr": np.abs(contrast) / 0.1, "contrast": contrast})
    sr = types.SimpleNamespace(metrics=m, times_s=t * 3600.0, crossovers=[])
    seen = {}
    monkeypatch.setattr(products, "save_figure", lambda fig, path, opts=None, **kw:
                        seen.setdefault("fig", fig) and path)
    products.plot_scr_curves(tmp_path / "scr.png", {("summer", "8-14"): sr}, "8-14")
    texts = " | ".join(x.get_text() for x in seen["fig"].findobj(Text))
    assert "µm" in texts and "W m⁻² sr⁻¹" in texts
    assert " um" not in texts and "m-2" not in texts
    ax = seen["fig"].axes[0]
    assert ax.get_yscale() == "log"
    assert any(np.allclose(line.get_ydata(), 1.0) for line in ax.get_lines())
