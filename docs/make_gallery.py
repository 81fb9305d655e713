"""Make the pictures of the gallery (``docs/gallery.md``) from one run of the tutorial's
scenario: ``python docs/make_gallery.py`` (a few minutes; writes ``docs/_static/gallery/``).

The pictures are products of the run folder that :meth:`shipthermal.SimulationResult.save`
(and ``shipthermal run --image``) writes, copied as they are, plus one image made in
Python (:meth:`~shipthermal.SimulationResult.image`). Each is kept under
:data:`MAX_BYTES` (the repository stays small): a larger PNG is written again at a
lower resolution.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "_static" / "gallery"

#: largest picture kept in the repository [bytes]
MAX_BYTES = 200_000

#: gallery picture → the product of a run folder it shows
PRODUCTS = {
    "panels_8-14.png": "imaging/panels_8-14.png",
    "scr_8-14.png": "imaging/scr_8-14.png",
    "scr_3-5.png": "imaging/scr_3-5.png",
    "part_means.png": "thermal/southampton/part_means.png",
    "surface_1200.png": "thermal/southampton/surface_1200.png",
    "class_map.png": "imaging/background/southampton/class_map.png",
    "background_hours.png": "imaging/background/southampton/background_hours.png",
}

SCENARIO = """
name = "southampton"
[location]
latitude = 50.90
longitude = -1.40
time_zone = "Europe/London"
[time]
date = 2023-07-15
[weather]
source = "{weather}"
[ship]
builtin = "frigate"
edge_length = 4.0
mooring_position = [90.0, 30.0]
[background]
size_px = 100
[outputs]
formats = ["csv", "json", "png"]
"""


def shrink(path: Path, max_bytes: int = MAX_BYTES) -> Path:
    """Write a PNG again at lower resolution until it is at most ``max_bytes``."""
    from PIL import Image

    while path.stat().st_size > max_bytes:
        with Image.open(path) as im:
            im = im.convert("RGB").resize((int(im.width * 0.8), int(im.height * 0.8)),
                                          Image.LANCZOS)
            im.save(path, optimize=True)
    return path


def image_picture(res, path: Path) -> Path:
    """The image of the tutorial at 13:00 in 8-14 µm, and its brightness temperature
    near the ship."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    img = res.image("13:00", band="8-14")
    bt = res.image("13:00", band="8-14", quantity="brightness_temperature")
    near = bt.where(bt.ship_coverage.rolling(x=9, y=9, center=True, min_periods=1).max() > 0,
                    drop=True)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    img.plot(ax=axes[0], cmap="inferno")
    axes[0].set_title("at-aperture radiance, 8-14 µm, 13:00 BST", fontsize=10)
    near.plot(ax=axes[1], cmap="inferno")
    axes[1].set_title("brightness temperature near the ship [K]", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return shrink(path)


def make_gallery(out: Path = OUT) -> dict:
    """Run the tutorial's scenario and write the gallery's pictures into ``out``."""
    sys.path.insert(0, str(ROOT / "src"))
    import shipthermal as st

    out.mkdir(parents=True, exist_ok=True)
    weather = ROOT / "tests" / "data" / "weather" / "southampton_2023-07-15.csv"
    with tempfile.TemporaryDirectory() as tmp:
        scenario = Path(tmp) / "southampton.toml"
        scenario.write_text(SCENARIO.format(weather=weather))
        res = st.Simulation(scenario).run()
        run = res.save(Path(tmp) / "run")
        written = {"image_1300_8-14.png": image_picture(res, out / "image_1300_8-14.png")}
        for name, product in PRODUCTS.items():
            written[name] = shrink(Path(shutil.copyfile(run / product, out / name)))
    return written


if __name__ == "__main__":
    for name, path in make_gallery().items():
        print(f"{name}: {path.stat().st_size / 1000:.0f} kB")
