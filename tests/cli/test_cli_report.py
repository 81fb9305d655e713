"""The HTML report: one self-contained file (no external URLs, no scripts), every picture
embedded as a PNG that decodes; opened in headless Chromium when it is installed."""

import base64
import html.parser
import io
import re
import shutil
import subprocess
from pathlib import Path

import pandas as pd
import pytest

from shipthermal.cli import main

CHROMIUM = next((p for p in ("/usr/bin/chromium", shutil.which("chromium") or "",
                             shutil.which("chromium-browser") or "") if p and Path(p).exists()),
                None)


class _Collect(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.tags, self.sections = [], [], [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.append(tag)
        if tag == "img":
            self.images.append(a)
        for key in ("href", "src", "action", "data", "poster"):
            if key in a:
                self.links.append(a[key])
        if tag == "section":
            self.sections.append(a.get("id"))


@pytest.fixture(scope="module")
def report(imaged_run):
    path = imaged_run / "report.html"
    text = path.read_text(encoding="utf-8")
    p = _Collect()
    p.feed(text)
    return path, text, p


def test_report_is_self_contained(report):
    path, text, p = report
    assert "script" not in p.tags and "link" not in p.tags and "iframe" not in p.tags
    for ref in p.links:
        assert ref.startswith(("data:image/png;base64,", "#")), ref[:60]
    assert not re.search(r"url\(|@import|https?://", text.split("</style>")[0])
    assert set(p.sections) >= {"run", "scenario", "thermal", "imaging"}


def test_every_embedded_image_decodes(report):
    """Each <img> is a base64 PNG that Pillow opens and fully decodes, with its size."""
    from PIL import Image

    path, text, p = report
    # part means, 2 surface maps, energy, 2 panels, 2 SCR plots
    assert len(p.images) >= 8
    for a in p.images:
        data = base64.b64decode(a["src"].split(",", 1)[1], validate=True)
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        im = Image.open(io.BytesIO(data))
        im.load()                                   # decodes every byte of the stream
        assert im.width > 50 and im.height > 50
        assert a.get("alt")


def test_report_tables_match_the_run(report, imaged_run):
    path, text, p = report
    cross = pd.read_csv(imaged_run / "imaging" / "crossovers.csv")
    assert len(cross) >= 1
    for t in cross["time_local"]:
        assert f"<td>{t}</td>" in text
    # the paper's reference deck temperatures (summer 07:00 and 12:00) are tabulated
    assert "304.67" in text and "292.08" in text
    assert "Status: <span class=\"status-complete\">complete" in text


def test_report_command_rewrites_and_marks_unfinished_runs(imaged_run, tmp_path, capsys):
    out = tmp_path / "copy.html"
    assert main(["-q", "report", str(imaged_run), "--output", str(out)]) == 0
    assert out.read_text().startswith("<!DOCTYPE html>")
    # an unfinished run's report says so
    partial = tmp_path / "partial"
    shutil.copytree(imaged_run, partial)
    (partial / "COMPLETE").unlink()
    assert main(["-q", "report", str(partial)]) == 0
    assert "did not finish" in (partial / "report.html").read_text()


@pytest.mark.skipif(CHROMIUM is None, reason="headless Chromium not installed (/usr/bin/chromium "
                    "absent); the embedded images are still decoded by the other tests")
def test_report_opens_in_headless_chromium(report, tmp_path):
    """Chromium loads the file from disk (no server), runs a probe script appended to a
    copy, and the dumped DOM says every image decoded (naturalWidth > 0)."""
    path, text, p = report
    probe = ("<script>window.addEventListener('load',()=>{const im=[...document.images];"
             "document.body.setAttribute('data-probe',im.filter(i=>i.complete&&"
             "i.naturalWidth>0).length+'/'+im.length);});</script>")
    copy = tmp_path / "probe.html"
    copy.write_text(text.replace("</body>", probe + "</body>"), encoding="utf-8")
    res = subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                          "--virtual-time-budget=10000", "--dump-dom", copy.as_uri()],
                         capture_output=True, text=True, timeout=120)
    m = re.search(r'data-probe="(\d+)/(\d+)"', res.stdout)
    assert m, res.stderr[-2000:]
    ok, total = int(m.group(1)), int(m.group(2))
    assert total == len(p.images) and ok == total


def test_report_shows_start_and_finish(report, imaged_run):
    import json

    _, text, _ = report
    m = json.loads((imaged_run / "manifest.json").read_text())
    assert m["started"] and m["finished"] and m["started"] <= m["finished"]
    assert f"{m['started']} / {m['finished']}" in text
    assert "/ None" not in text


def test_run_writes_the_port_background(imaged_run):
    """What the README lists: the port background as float32 GeoTIFFs in kelvin and a class
    map, per case, beside the images."""
    import numpy as np
    import rasterio

    bg = imaged_run / "imaging" / "background" / "tiny"
    with rasterio.open(bg / "background_K.tif") as src:
        assert src.count == 24 and src.dtypes[0] == "float32" and src.crs is not None
        data = src.read()
    finite = data[np.isfinite(data)]
    assert finite.size and 250.0 < finite.min() and finite.max() < 340.0      # kelvin
    with rasterio.open(bg / "class_map.tif") as src:
        classes = np.unique(src.read(1))
    from imaging.background.classify import CLASS_CODES

    assert set(classes) - {0} and set(classes) <= {0, *CLASS_CODES}
    assert (bg / "lst_K.tif").is_file() and (bg / "class_map.png").is_file()
