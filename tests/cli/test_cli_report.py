"""The HTML report: one self-contained file (no external URLs, inline scripts only), every
picture embedded as a PNG that decodes; opened in headless Chromium when it is installed
(the browser test saves screenshots of the first screen under the test's tmp dir)."""

import base64
import html.parser
import io
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.cli import main
from shipthermal.units import strip_units

CHROMIUM = next((p for p in ("/usr/bin/chromium", shutil.which("chromium") or "",
                             shutil.which("chromium-browser") or "") if p and Path(p).exists()),
                None)


class _Collect(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.tags, self.sections = [], [], [], []
        self.scripts = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.append(tag)
        if tag == "img":
            self.images.append(a)
        for key in ("href", "src", "action", "data", "poster"):
            if key in a:
                self.links.append(a[key])
        if tag == "script":
            self.scripts.append(a)
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
    assert "link" not in p.tags and "iframe" not in p.tags and "object" not in p.tags
    # scripts: inline only (no src), and none of them fetches anything
    assert p.scripts and all(not a for a in p.scripts)
    for code in re.findall(r"<script>(.*?)</script>", text, flags=re.S):
        assert not re.search(r"https?:|fetch\(|XMLHttpRequest|import\(|src\s*=", code)
    for ref in p.links:
        assert ref.startswith(("data:image/png;base64,", "data:text/csv;base64,", "#")), ref[:60]
    assert not re.search(r"url\(|@import|https?://", text.split("</style>")[0])
    assert set(p.sections) >= {"answer", "day", "run", "scenario", "thermal", "imaging", "data"}


def test_every_embedded_image_decodes(report):
    """Each <img> is a base64 PNG that Pillow opens and fully decodes, with its size."""
    from PIL import Image

    path, text, p = report
    # part means, 2 surface maps, energy, 2 panels, 2 SCR plots; slider: 25 hourly frames
    # per band (2) and of the surface temperature, 2 colour bars
    assert len(p.images) >= 8 + 3 * 25 + 2
    for a in p.images:
        data = base64.b64decode(a["src"].split(",", 1)[1], validate=True)
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        im = Image.open(io.BytesIO(data))
        im.load()                                   # decodes every byte of the stream
        assert im.width > 50 and im.height > 50
        assert a.get("alt")


def test_report_tables_match_the_run(report, imaged_run):
    path, text, p = report
    cross = strip_units(pd.read_csv(imaged_run / "imaging" / "crossovers.csv"))
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


def _chromium(*args, timeout=120):
    return subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                           "--hide-scrollbars", "--enable-logging=stderr", "--v=0", *args],
                          capture_output=True, text=True, timeout=timeout)


#: Put first in <head>: records script errors and console.error calls; after load, counts
#: the images that decoded, moves the slider to 06:00 and records what is shown.
_PROBE = """<script>
window.__errs=[];window.addEventListener('error',function(e){window.__errs.push(String(
e.message));});var __ce=console.error;console.error=function(){window.__errs.push(
[].join.call(arguments,' '));__ce.apply(console,arguments);};
window.addEventListener('load',function(){var b=document.body,im=[].slice.call(
document.images);b.setAttribute('data-decoded',im.filter(function(i){return i.complete&&
i.naturalWidth>0;}).length+'/'+im.length);b.setAttribute('data-before',
b.getAttribute('data-shown'));var vis=function(){return [].slice.call(document.querySelectorAll(
'img[data-frame]')).filter(function(i){return !i.hidden&&i.offsetWidth>0;}).map(function(i){
return i.getAttribute('data-frame');}).join(',');};b.setAttribute('data-vis-before',vis());
var s=document.getElementById('day-slider'),L=JSON.parse(s.getAttribute('data-labels'));
s.value=L.indexOf('06:00');s.dispatchEvent(new Event('input'));
b.setAttribute('data-vis-after',vis());b.setAttribute('data-cursor',
document.querySelector('line.cursor').getAttribute('x1'));
var j=document.querySelector('button[data-jump]');if(j){j.click();
b.setAttribute('data-jump-to',j.getAttribute('data-jump')+':'+b.getAttribute('data-shown')+':'+vis());}
var a=document.querySelector('table.answer-table');
b.setAttribute('data-widths',[document.documentElement.scrollWidth,window.innerWidth,
a?Math.ceil(a.getBoundingClientRect().right):-1].join(','));
b.setAttribute('data-errors',String(window.__errs.length)+':'+window.__errs.join('|'));});
</script>"""


@pytest.mark.skipif(CHROMIUM is None, reason="headless Chromium not installed (/usr/bin/chromium "
                    "absent); the embedded images are still decoded by the other tests")
def test_report_opens_in_headless_chromium(report, tmp_path):
    """Chromium loads the file from disk (no server) with a probe script put first: no
    script error or console error, every image decodes (naturalWidth > 0), the slider
    moved to 06:00 shows the 06:00 frame of every group (and only it) and moves the SCR
    cursor; screenshots of the first screen are kept in the test's tmp dir."""
    path, text, p = report
    copy = tmp_path / "probe.html"
    copy.write_text(text.replace("<head>", "<head>" + _PROBE, 1), encoding="utf-8")
    res = _chromium("--virtual-time-budget=10000", "--dump-dom", copy.as_uri())
    attrs = dict(re.findall(r'data-([a-z-]+)="([^"]*)"', res.stdout.split("<body", 1)[1]
                            .split(">", 1)[0]))
    assert "decoded" in attrs, res.stderr[-2000:]
    ok, total = map(int, attrs["decoded"].split("/"))
    assert total == len(p.images) and ok == total
    assert attrs["errors"] == "0:", attrs["errors"]
    assert "Uncaught" not in res.stderr, res.stderr[-2000:]
    n_groups = len({re.sub(r" \d\d:\d\d$", "", a["alt"]) for a in p.images
                    if "data-frame" in a})
    assert n_groups >= 3
    import html as _html
    import json

    labels = json.loads(_html.unescape(re.search(r'data-labels="([^"]*)"', text).group(1)))
    i12, i6 = labels.index("12:00"), labels.index("06:00")
    assert attrs["before"] == "12:00"
    assert attrs["vis-before"] == ",".join([str(i12)] * n_groups)
    assert attrs["vis-after"] == ",".join([str(i6)] * n_groups)
    m = re.search(r'class="cursor" data-x0="([\d.]+)" data-dx="([\d.]+)"', text)
    assert float(attrs["cursor"]) == pytest.approx(float(m.group(1)) + 6 * float(m.group(2)))
    # the first jump button goes to its key moment (not on the hour), every group follows
    k, rest = attrs["jump-to"].split(":", 1)
    shown, vis = rest.rsplit(":", 1)
    assert shown == labels[int(k)] and vis == ",".join([k] * n_groups)
    target = re.search(r'<button type="button" data-jump="\d+">[^<]*?(\d\d):(\d\d)', text)
    step_min = 10
    assert abs(int(shown[:2]) * 60 + int(shown[3:]) - int(target.group(1)) * 60
               - int(target.group(2))) <= step_min / 2
    for name, size in (("first_screen.png", "1280,1000"), ("first_screen_narrow.png", "800,1200")):
        shot = tmp_path / name
        _chromium(f"--window-size={size}", "--virtual-time-budget=5000",
                  f"--screenshot={shot}", path.as_uri())
        from PIL import Image

        with Image.open(shot) as im:
            im.load()
            assert im.size == tuple(int(v) for v in size.split(","))
            # not a blank page: the first screen has text and the answer box
            assert len(im.convert("L").getcolors(65536) or []) > 20


@pytest.mark.skipif(CHROMIUM is None, reason="headless Chromium not installed")
def test_report_fits_a_phone_screen(report, tmp_path):
    """At 390 x 844 CSS pixels (a phone) nothing is wider than the screen: the page does not
    scroll sideways and the answer table ends inside it (measured in Chromium); the first
    screen is kept as a screenshot. (Before the phone layout the answer table was 1005 px
    wide.)"""
    path, text, p = report
    copy = tmp_path / "probe.html"
    copy.write_text(text.replace("<head>", "<head>" + _PROBE, 1), encoding="utf-8")
    # headless Chromium keeps its window at least 500 px wide: the page goes into a phone-
    # sized frame, whose probe results the host page copies once the frame has loaded
    host = tmp_path / "phone.html"
    host.write_text('<!DOCTYPE html><html><body><iframe id="f" src="probe.html" '
                    'style="width:390px;height:844px;border:0"></iframe><script>'
                    "document.getElementById('f').addEventListener('load',function(){"
                    "document.body.setAttribute('data-widths',this.contentDocument.body"
                    ".getAttribute('data-widths'));});</script></body></html>", encoding="utf-8")
    res = _chromium("--allow-file-access-from-files", "--window-size=800,900",
                    "--virtual-time-budget=10000", "--dump-dom", host.as_uri())
    attrs = dict(re.findall(r'data-([a-z-]+)="([^"]*)"', res.stdout.split("<body", 1)[1]
                            .split(">", 1)[0]))
    page, screen, table = (int(v) for v in attrs["widths"].split(","))
    assert screen == 390, attrs["widths"]
    assert page <= screen and 0 < table <= screen, attrs["widths"]
    shot = tmp_path / "first_screen_phone.png"
    _chromium("--window-size=390,844", "--virtual-time-budget=5000", f"--screenshot={shot}",
              path.as_uri())
    assert shot.stat().st_size > 10_000


def test_first_screen_answers_from_the_metrics(report, imaged_run):
    """The headline band and time are those of the lowest SCR in the metrics CSVs
    (recomputed here with pandas): the lowest frame, or a zero of the contrast between two
    frames (a crossover: SCR 0 at the crossover's time); the low time is stated whenever
    the SCR goes below 1."""
    _, text, _ = report
    img = imaged_run / "imaging"
    cross = (strip_units(pd.read_csv(img / "crossovers.csv")) if (img / "crossovers.csv").is_file()
             else None)
    best, low = None, False
    for f in sorted(img.glob("metrics_*.csv")):
        season, band = f.stem[len("metrics_"):].split("_", 1)
        m = strip_units(pd.read_csv(f))
        t, c, scr = m["time_h"].to_numpy(), m["contrast"].to_numpy(), m["scr"].to_numpy()
        k = int(np.argmin(scr))
        cand = (scr[k], band, t[k])
        flips = np.flatnonzero(np.sign(c[:-1]) * np.sign(c[1:]) < 0)
        if len(flips):
            j = flips[0]
            t0 = t[j] + (t[j + 1] - t[j]) * abs(scr[j]) / (abs(scr[j]) + abs(scr[j + 1]))
            if cross is not None:
                sel = cross[(cross["season"] == season) & (cross["band"].astype(str) == band)
                            & (cross["time_h"] >= t[j]) & (cross["time_h"] <= t[j + 1])]
                t0 = float(sel["time_h"].iloc[0]) if len(sel) else t0
            cand = (0.0, band, t0)
        low = low or bool((scr < 1.0).any() or len(flips))
        if best is None or cand[0] < best[0]:
            best = cand
    h = int(round(best[2] * 60))
    answer = text.split('<section id="answer"', 1)[1].split("</section>", 1)[0]
    assert (f"hardest at <b>{h // 60:02d}:{h % 60:02d}</b> local (UTC+8) in the "
            f"<b>{best[1].replace('-', '–')} µm</b> "
            f"band, local SCR {best[0]:.2g}") in answer
    assert ("h in all" in answer) == low and ("never falls below" in answer) == (not low)


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
    assert (bg / "albedo.tif").is_file() and (bg / "class_map.png").is_file()
    assert (bg / "sea.csv").is_file() and (bg / "background_hours.png").is_file()
    with rasterio.open(bg / "background_K.tif") as src:       # every band says what it is
        assert all("synthetic port" in d for d in src.descriptions)


def test_mesh_report_is_tables_not_json(imaged_run, tmp_path):
    """A nested mesh repair report shows as tables (objects as key/value rows, lists of
    objects as one table), with no raw JSON left in the page."""
    import json

    from shipthermal.app.report import build_report

    run = tmp_path / "run"
    shutil.copytree(imaged_run, run)
    (run / "mesh").mkdir(exist_ok=True)
    rep = {"file": "ship.obj", "faces": 1520, "closed": True,
           "parts": [{"name": "hull", "faces": 800, "area_m2": 1234.5},
                     {"name": "deck", "faces": 720, "area_m2": 987.25}],
           "repairs": {"merged_vertices": 12, "flipped": {"count": 3, "faces": [4, 9, 11]}},
           "problems": []}
    (run / "mesh" / "mesh_report.json").write_text(json.dumps(rep))
    text = build_report(run)
    mesh = text.split('<section id="mesh">', 1)[1].split("</section>", 1)[0]
    assert "{" not in mesh and '"' not in mesh.replace('class="kv"', "")
    assert "<th>name</th><th>faces</th><th>area_m2</th>" in mesh
    assert "<td>hull</td><td>800</td><td>1234.5</td>" in mesh
    assert "<th>count</th><td>3</td>" in mesh and "4, 9, 11" in mesh
    assert "<th>problems</th><td>none</td>" in mesh
