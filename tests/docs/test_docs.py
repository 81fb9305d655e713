"""The documentation a user navigates: the Sphinx site builds without a warning (API
reference from the docstrings, the guides, the tutorial page, the gallery), the tutorial
notebook runs from the first cell to the report, and the gallery's pictures exist and
stay small.

Needs the ``docs`` extra (sphinx, myst-parser, nbformat, nbclient, ipykernel); without it
the tests are skipped and say which package is missing.
"""

import ast
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
TUTORIAL = DOCS / "tutorial.ipynb"


def _need(module: str):
    return pytest.importorskip(module, reason=f"{module} is not installed (the docs extra: "
                               "pip install sphinx myst-parser nbformat nbclient ipykernel)")


def test_the_docs_build_without_a_warning(tmp_path):
    _need("sphinx")
    _need("myst_parser")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"),
                                                        os.environ.get("PYTHONPATH", "")]))
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b",
                           "html", "-d", str(tmp_path / "doctrees"), str(DOCS),
                           str(tmp_path / "html")], capture_output=True, text=True, env=env,
                          timeout=600)
    seconds = time.perf_counter() - t0
    assert proc.returncode == 0 and "WARNING" not in proc.stderr, proc.stderr[-4000:]
    html = tmp_path / "html"
    # the pages a user looks for first
    for page in ("index.html", "tutorial.html", "gallery.html", "api/front_door.html",
                 "api/imaging.html", "CLI.html", "SCENARIO.html"):
        assert (html / page).is_file(), page
    front = (html / "api" / "front_door.html").read_text(encoding="utf-8")
    for name in ("Simulation", "SimulationResult", "image", "crossovers", "report"):
        assert f'id="shipthermal.{name}' in front or f"SimulationResult.{name}" in front, name
    # the tutorial page shows the notebook's code (highlighted: tags between the words)
    tutorial = re.sub(r"<[^>]+>", "", (html / "tutorial.html").read_text(encoding="utf-8"))
    assert "st.Simulation(scenario_file)" in tutorial
    print(f"sphinx build: {seconds:.0f} s")


def test_a_warning_fails_the_build(tmp_path):
    """The build above is a check: a broken docstring or a missing page is an error."""
    _need("sphinx")
    _need("myst_parser")
    src = tmp_path / "src"
    src.mkdir()
    (src / "conf.py").write_text("extensions = ['myst_parser']\n")
    (src / "index.md").write_text("# Index\n\n```{toctree}\nmissing_page\n```\n")
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", str(src),
                           str(tmp_path / "html")], capture_output=True, text=True, timeout=300)
    assert proc.returncode != 0 and "missing_page" in proc.stderr, proc.stderr


def _image_lines(nb: dict) -> list[str]:
    """The code from ``import shipthermal`` to the first ``.image(`` line, comments and
    blank lines left out."""
    code = [ln for c in nb["cells"] if c["cell_type"] == "code"
            for ln in "".join(c["source"]).splitlines()]
    start = next(i for i, ln in enumerate(code) if ln.startswith("import shipthermal"))
    end = next(i for i, ln in enumerate(code) if ".image(" in ln and i > start)
    return [ln for ln in code[start:end + 1] if ln.strip() and not ln.lstrip().startswith("#")]


def test_the_tutorial_reaches_an_image_in_at_most_five_lines():
    nb = json.loads(TUTORIAL.read_text(encoding="utf-8"))
    lines = _image_lines(nb)
    assert len(lines) <= 5, lines
    # one import, the package's own: no module of the application layer to guess
    imports = [ln for ln in lines if ln.startswith(("import ", "from "))]
    assert imports == ["import shipthermal as st"], imports
    # and every code cell is Python that parses
    for cell in nb["cells"]:
        if cell["cell_type"] == "code":
            ast.parse("".join(cell["source"]))


def test_the_tutorial_runs_from_the_scenario_to_the_report(tmp_path, monkeypatch):
    nbformat = _need("nbformat")
    nbclient = _need("nbclient")
    _need("ipykernel")
    nb = nbformat.read(TUTORIAL, as_version=4)
    params = [c for c in nb.cells if "parameters" in c.metadata.get("tags", [])]
    assert len(params) == 1, "the tutorial's paths are in one cell tagged 'parameters'"
    # the paths the tutorial reads and writes, here: the repository's data, a tmp folder
    src = params[0].source
    src = re.sub(r'DATA = Path\("[^"]*"\)',
                 f'DATA = Path({str(ROOT / "tests" / "data" / "weather")!r})', src)
    src = re.sub(r'OUT = Path\("[^"]*"\)', f'OUT = Path({str(tmp_path / "out")!r})', src)
    assert src != params[0].source
    params[0].source = src
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(ROOT / "src"),
                                                      os.environ.get("PYTHONPATH", "")]))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    client = nbclient.NotebookClient(nb, timeout=1800, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    t0 = time.perf_counter()
    client.execute()
    print(f"tutorial: {time.perf_counter() - t0:.0f} s")
    out = tmp_path / "out"
    report = out / "southampton-report.html"
    assert report.is_file() and report.stat().st_size > 100_000
    assert (out / "image_1300_8-14.nc").is_file() and (out / "ship_1300.vtp").is_file()
    texts = ["".join(o.get("text", "") + json.dumps(o.get("data", {}))
                     for o in c.get("outputs", [])) for c in nb.cells if c.cell_type == "code"]
    joined = "\n".join(texts)
    assert "xarray.DataArray" in joined and "crossovers" in joined
    assert "dark->bright" in joined and "+01:00" in joined      # tz-aware crossovers (BST)


GALLERY = DOCS / "gallery.md"


def test_the_gallery_shows_small_pictures_of_every_product():
    text = GALLERY.read_text(encoding="utf-8")
    pictures = re.findall(r"\]\((_static/gallery/[^)]+\.png)\)", text)
    assert len(pictures) >= 6, pictures
    for rel in pictures:
        path = DOCS / rel
        assert path.is_file(), rel
        assert path.stat().st_size <= 200_000, (rel, path.stat().st_size)
    sys.path.insert(0, str(DOCS))
    try:
        from make_gallery import PRODUCTS
    finally:
        sys.path.remove(str(DOCS))
    # every picture the script copies is in the gallery, and the gallery names its product
    for name, product in PRODUCTS.items():
        assert f"_static/gallery/{name}" in pictures, name
        assert Path(product).name in text, product
