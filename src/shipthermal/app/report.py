"""One self-contained HTML page per run directory.

Everything is inside the file: pictures are embedded as base64 PNG (``data:`` URIs), the
style sheet and the one small script (the time slider) are inline, there are no external
URLs, so the page opens from a disk, a mail attachment or an archive without a server.

Sections (each only when the run has it): the answer first (when the ship is hardest to
see, in which band, how sure: :mod:`shipthermal.app.report_day`), the day under a time slider
(images, SCR cursor, surface temperature), run (status, manifest, versions, timings),
scenario summary per case (and the full TOML, folded), mesh, thermal (part-mean curves,
surface maps, spin-up, energy balance with a per-step plot, deck means next to the paper's
reference values), imaging (panels per band and time, SCR curves, crossover table, band
comparison), validation tables, and for a sweep folder its table and plot.
"""

from __future__ import annotations

import base64
import html
import io
import json
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

from ..atomic import atomic_write_text
from ..diurnal import plot_part_means
from ..errors import InputError
from ..figures import band_label
from ..units import latitude_text, longitude_text, strip_units, zone_text
from .html_table import html_table
from .paper import REFERENCE_DECK
from .rundir.ownership import MANIFEST, MARKER
from .scenario import load_scenario

__all__ = ["write_report", "build_report", "is_report_file", "GENERATOR"]

#: The tag by which a report of this tool is recognised (``report --output`` writes over
#: nothing else)
GENERATOR = '<meta name="generator" content="shipthermal report">'

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Helvetica,Arial,sans-serif;margin:0;
color:#1d2327;background:#fafbfc}
main{max-width:1200px;margin:0 auto;padding:1.5em}
h1{font-size:1.6em;margin-bottom:.2em}h2{border-bottom:2px solid #d0d7de;padding-bottom:.2em;
margin-top:2em}h3{margin-bottom:.3em}
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}
th,td{border:1px solid #d0d7de;padding:3px 8px;text-align:right}
th{background:#eef1f4}td:first-child,th:first-child{text-align:left}
figure{margin:.8em 0;display:inline-block;vertical-align:top;max-width:100%}
table{display:block;max-width:100%;overflow-x:auto}
figure img{max-width:100%;border:1px solid #d0d7de;background:white}
figcaption{font-size:.85em;color:#57606a}
.status-complete{color:#1a7f37;font-weight:bold}.status-other{color:#bc4c00;font-weight:bold}
pre{background:#f0f2f4;padding:.8em;overflow-x:auto;font-size:.8em}
.note{color:#57606a;font-size:.9em}
nav{display:flex;flex-wrap:wrap;gap:.3em 1em}
table.kv td{text-align:left;overflow-wrap:anywhere}
.answer{background:#fff8e6;border:1px solid #e3b341;padding:.2em 1em 1em;margin:1em 0}
.answer h2{margin-top:.6em;border:none}.headline{font-size:1.15em}
.slider{position:sticky;top:0;background:#fafbfc;padding:.5em 0;z-index:2;
border-bottom:1px solid #d0d7de}
.slider input{width:55%;vertical-align:middle}.slider output{font-weight:bold;font-size:1.2em}
.slider button{margin:.1em .2em;font-size:.9em}.jumps{margin-top:.3em;font-size:.9em}
.row{display:flex;flex-wrap:wrap;align-items:flex-start}
figure.frames{max-width:420px}figure.frames img{display:block}
figure.frames img[hidden]{display:none}
svg.scr{display:inline-block;vertical-align:top;background:white;border:1px solid #d0d7de;
margin:.8em .8em 0 0;max-width:100%;height:auto}
.zone{margin:.2em 0}.background{margin:.2em 0}h3.sure{margin:.6em 0 0;font-size:1em}
.downloads li{margin:.2em 0}
@media (max-width:700px){main{padding:.6em}h1{font-size:1.25em}
table.answer-table{display:block}table.answer-table thead{display:none}
table.answer-table tbody,table.answer-table tr,table.answer-table td{display:block}
table.answer-table tr{border:1px solid #d0d7de;margin:.4em 0;background:white}
table.answer-table td{border:none;text-align:left;padding:2px 6px}
table.answer-table td::before{content:attr(data-label) ": ";font-weight:bold}
.slider input{width:100%}figure.frames{max-width:100%}}
"""


def _img(png: bytes, alt: str, caption: str = "", width: int | None = None) -> str:
    data = base64.b64encode(png).decode("ascii")
    w = f' style="width:{width}px"' if width else ""
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    return (f'<figure{w}><img alt="{html.escape(alt)}" src="data:image/png;base64,{data}">'
            f"{cap}</figure>")


def _img_file(path: Path, caption: str = "", width: int | None = None) -> str:
    return _img(path.read_bytes(), path.name, caption or path.name, width)


def _kv(pairs) -> str:
    rows = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                   for k, v in pairs)
    return f'<table class="kv">{rows}</table>'


def _fig_png(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, bbox_inches="tight")
    # lazy: matplotlib takes most of a second to import (measured)
    import matplotlib.pyplot as plt

    plt.close(fig)
    return buf.getvalue()


def _energy_png(energy: pd.DataFrame, title: str) -> bytes:
    """Cumulative stored energy vs heat in through the boundary, and the per-step
    imbalance relative to the gross boundary heat."""
    # lazy: matplotlib takes most of a second to import (measured)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = energy["time"].to_numpy() / 3600.0
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 3.6))
    a.plot(t, np.cumsum(energy["stored"]) / 1e9, label="stored (cumulative)")
    a.plot(t, np.cumsum(energy["boundary"] + energy["source"]) / 1e9, "--",
           label="boundary + sources (cumulative)")
    a.set_xlabel("simulated time [h]")
    a.set_ylabel("energy [GJ]")
    a.legend(fontsize=8)
    a.grid(alpha=.3)
    gross = energy["gross"].to_numpy()
    rel = np.abs(energy["imbalance"].to_numpy()) / np.where(gross > 0, gross, np.inf)
    b.semilogy(t, np.maximum(rel, 1e-18), ".", ms=2)
    b.set_xlabel("simulated time [h]")
    b.set_ylabel("|imbalance| / gross boundary heat [-]")
    b.grid(alpha=.3)
    fig.suptitle(title, fontsize=10)
    return _fig_png(fig)


def _part_means_png(pm: pd.DataFrame, title: str) -> bytes:
    with tempfile.TemporaryDirectory() as tmp:
        p = plot_part_means(pm, Path(tmp) / "pm.png", title=title)
        return p.read_bytes()


def _cases(run: Path, manifest: dict) -> dict:
    """case → scenario file, from the manifest (or the files present)."""
    cases = {}
    for case, info in (manifest.get("cases") or {}).items():
        f = run / info.get("scenario", "")
        if f.is_file():
            cases[case] = f
    if not cases:
        if (run / "scenario.toml").is_file():
            cases["run"] = run / "scenario.toml"
        for f in sorted(run.glob("scenario_*.toml")):
            cases[f.stem[len("scenario_"):]] = f
    return cases


def _scenario_section(case: str, path: Path) -> str:
    try:
        sc = load_scenario(path)
    except InputError as exc:
        return f"<h3>{html.escape(case)}</h3><pre>{html.escape(str(exc))}</pre>"
    loc, t, w, s, sv, img = sc.location, sc.time, sc.weather, sc.ship, sc.solver, sc.imaging
    ship = s.builtin if s.files is None else "user files"
    pairs = [
        ("name", sc.name), ("season / date", f"{t.season}, {t.date}"),
        ("location", f"{latitude_text(loc.latitude, 3)}, {longitude_text(loc.longitude, 3)}; "
                     f"local time {zone_text(t.date, loc.time_zone)}"),
        ("weather", f"{w.source} (wind {w.wind_speed_offset:+g} m/s, air "
                    f"{w.temp_air_offset:+g} K, cloud {w.cloud_cover_offset:+g})"),
        ("ship", f"{ship}, edge {s.edge_length if s.edge_length else 'default'} m, heading "
                 f"{s.heading:g} deg, speed {s.speed:g} m/s, mooring "
                 f"{list(s.mooring_position)} m"),
        ("solver", f"{sv.scheme}, dt {sv.time_step:g} s (night up to {sv.night_step:g} s), "
                   f"spin-up tol {sv.spinup_tolerance:g} K, "
                   f"max {sv.spinup_max_days} days, {sv.rays_per_face} rays/face, seed {sv.seed}"),
        ("background", f"{sc.background.source} (seed {sc.background.seed})"),
        ("imaging", f"bands {', '.join(img.bands)}; images at {', '.join(img.times)}; SCR every "
                    f"{img.scr_interval / 60:g} min; view zenith {img.sensor.view_zenith_deg:g} "
                    f"deg; atmosphere {img.atmosphere.backend}"),
    ]
    text = path.read_text(encoding="utf-8")
    return (f"<h3>{html.escape(case)}</h3>{_kv(pairs)}<details><summary>full scenario "
            f"({html.escape(path.name)})</summary><pre>{html.escape(text)}</pre></details>")


def _thermal_section(case: str, d: Path, season: str | None) -> str:
    parts = [f"<h3>{html.escape(case)}</h3>"]
    summary = {}
    if (d / "thermal_summary.json").is_file():
        summary = json.loads((d / "thermal_summary.json").read_text())
        e = summary.get("energy", {})
        changes = [c for c in summary.get("day_changes_K", []) if c is not None]
        pairs = [("ship", summary.get("ship")), ("surface faces / cells",
                                                  f"{summary.get('surface_faces')} / "
                                                  f"{summary.get('cells')}"),
                 ("spin-up", f"{summary.get('days')} days, converged: {summary.get('converged')}"
                             + (f" (last day-to-day change {changes[-1]:.4f} K, tolerance "
                                f"{summary.get('spinup_tolerance_K')} K)" if changes else "")),
                 ("energy: stored / boundary+sources [J]",
                  f"{e.get('stored_J', float('nan')):.6e} / "
                  f"{e.get('boundary_J', float('nan')) + e.get('source_J', 0.0):.6e}"),
                 ("energy: relative imbalance (run, worst step)",
                  f"{e.get('relative_imbalance', float('nan')):.2e}, "
                  f"{e.get('max_step_relative_imbalance', float('nan')):.2e}"),
                 ("wall time [s]", ", ".join(f"{k} {v:.1f}" for k, v in
                                             summary.get("timings_s", {}).items()
                                             if isinstance(v, (int, float))))]
        parts.append(_kv(pairs))
    pm = None
    if (d / "part_means.csv").is_file():
        pm = strip_units(pd.read_csv(d / "part_means.csv", index_col=0))
    if (d / "part_means.png").is_file():
        parts.append(_img_file(d / "part_means.png", "area-mean outer-surface temperature"))
    elif pm is not None:
        parts.append(_img(_part_means_png(pm, f"{case}: part means"), "part means",
                          "area-mean outer-surface temperature"))
    maps = sorted(d.glob("surface_*.png"))
    for m in maps:
        hhmm = m.stem.split("_")[-1]
        parts.append(_img_file(m, f"outer surface temperature at {hhmm[:2]}:{hhmm[2:]} local",
                               width=560))
    if (d / "energy.csv").is_file():
        energy = strip_units(pd.read_csv(d / "energy.csv"))
        if len(energy):
            parts.append("<h4>Energy balance</h4>")
            parts.append(_img(_energy_png(energy, f"{case}: energy bookkeeping over the whole "
                                          "run (spin-up included)"), "energy balance"))
    if pm is not None and "deck" in pm.columns and season in ("summer", "winter"):
        rows = []
        for (s, hour), ref in sorted(REFERENCE_DECK.items()):
            if s != season:
                continue
            ours = float(np.interp(hour, pm.index.to_numpy(float), pm["deck"].to_numpy(float)))
            rows.append({"time": f"{int(hour):02d}:00", "deck mean [K]": ours,
                         "paper reference [K]": ref, "difference [K]": ours - ref,
                         "difference [%]": 100 * (ours - ref) / ref})
        if rows:
            parts.append("<h4>Deck mean vs the paper's reference (§3.1)</h4>")
            parts.append(html_table(pd.DataFrame(rows)))
            parts.append('<p class="note">The paper\'s reference conditions are unknown; this '
                         "run's scenario was not tuned to them (see <code>shipthermal "
                         "validate</code> for the sensitivity table).</p>")
    return "".join(parts)


def _imaging_section(d: Path) -> str:
    parts = []
    for sub in [d] + sorted(p for p in d.iterdir() if p.is_dir()):
        title = "" if sub == d else f"<h3>{html.escape(sub.name)}</h3>"
        block = []
        for png in sorted(sub.glob("panels_*.png")):
            block.append(_img_file(png, "images at the typical times, "
                                        f"{band_label(png.stem[7:])}"))
        for png in sorted(sub.glob("scr_*.png")):
            block.append(_img_file(png, f"local SCR and contrast over the day, "
                                        f"{band_label(png.stem[4:])}"))
        if (sub / "crossovers.csv").is_file():
            cross = pd.read_csv(sub / "crossovers.csv")
            block.append("<h4>Thermal crossover moments</h4>")
            block.append(html_table(cross) if len(cross) else "<p>No crossover found.</p>")
        if (sub / "band_comparison.csv").is_file():
            comp = strip_units(pd.read_csv(sub / "band_comparison.csv"))
            keep = [c for c in ("season", "band", "n_crossovers", "crossover_times",
                                "scr_in_crossover_mean", "scr_out_crossover_mean", "scr_min",
                                "scr_max") if c in comp.columns]
            block.append("<h4>Band comparison (SCR in / out of crossover periods)</h4>")
            block.append(html_table(comp[keep]))
        if block:
            parts.append(title + "".join(block))
    return "".join(parts)


def _validation_section(d: Path) -> str:
    parts = []
    names = {"validation_deck": "Deck temperature vs the paper",
             "validation_table": "Validation table",
             "validation_sensitivity": "Sensitivity",
             "validation_crossovers": "Crossover moments vs the paper"}
    seen = set()
    for stem, title in names.items():
        f = d / f"{stem}.csv"
        if f.is_file():
            df = pd.read_csv(f)
            if stem == "validation_table" and "validation_deck" in seen:
                continue
            seen.add(stem)
            parts.append(f"<h3>{title}</h3>" + (html_table(df) if len(df) else "<p>(empty)</p>"))
    for f in sorted(d.glob("*.csv")):
        if f.stem not in names:
            parts.append(f"<h3>{html.escape(f.stem)}</h3>" + html_table(pd.read_csv(f)))
    if (d / "validation.txt").is_file():
        parts.append("<details><summary>validation.txt</summary><pre>"
                     + html.escape((d / "validation.txt").read_text()) + "</pre></details>")
    return "".join(parts)


def _nested_table(value) -> str:
    """A JSON value as HTML tables: objects as key/value tables (nested objects as
    nested tables), lists of objects as one table with a column per key."""
    if isinstance(value, dict):
        if not value:
            return "—"
        rows = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{_nested_table(v)}</td></tr>"
                       for k, v in value.items())
        return f'<table class="kv">{rows}</table>'
    if isinstance(value, list):
        if value and all(isinstance(v, dict) for v in value):
            df = pd.DataFrame(value)
            head = "".join(f"<th>{html.escape(str(c))}</th>" for c in df.columns)
            body = "".join("<tr>" + "".join(f"<td>{_nested_table(row.get(c))}</td>"
                                            for c in df.columns) + "</tr>" for row in value)
            return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
        if not value:
            return "none"
        return ", ".join(_nested_table(v) for v in value)
    if value is None:
        return "—"
    if isinstance(value, float):
        return html.escape(f"{value:.6g}")
    return html.escape(str(value))


def _mesh_section(d: Path) -> str:
    parts = []
    for png in sorted(d.glob("*.png")):
        parts.append(_img_file(png, "ship coloured by part"))
    if (d / "mesh_report.json").is_file():
        rep = json.loads((d / "mesh_report.json").read_text())
        parts.append(_nested_table(rep))
    return "".join(parts)


def _calendar_section(d: Path) -> str:
    """The overpass calendar: the monthly fractions first, the pictures, the crossover times
    by month and every overpass."""
    parts = []
    summary = {}
    if (d / "summary.json").is_file():
        summary = json.loads((d / "summary.json").read_text(encoding="utf-8"))
    thr = summary.get("threshold", 1.0)
    parts.append(f"<p>{summary.get('overpasses', 0)} overpasses "
                 f"({html.escape(', '.join(summary.get('satellites', [])) or 'listed')}"
                 f"{'; two-line elements' if summary.get('tle') else ''}); an overpass is "
                 f"under the clutter when its local SCR is below {thr:g}. Background: "
                 f"{html.escape(str(summary.get('background', '')))}.</p>")
    if (d / "monthly.csv").is_file():
        m = strip_units(pd.read_csv(d / "monthly.csv"))
        if len(m):
            parts.append("<h3>By month</h3>" + html_table(m[[c for c in (
                "month", "band", "overpasses", "under_clutter", "fraction_under",
                "fraction_under_day", "fraction_under_night", "scr_median",
                "apparent_contrast_median_K") if c in m]], "{:.3g}"))
    for png in sorted(d.glob("calendar_*.png")):
        parts.append(_img_file(png, "local SCR of every day (colour), the overpasses "
                               "(white: under the clutter) and the monthly fraction"))
    if (d / "crossover_months.csv").is_file():
        c = strip_units(pd.read_csv(d / "crossover_months.csv"))
        if len(c):
            parts.append("<h3>Crossover times by month (local clock, median and 5–95 %)</h3>"
                         + html_table(c, "{:.2f}"))
    if (d / "crossover_dates.csv").is_file():
        c = strip_units(pd.read_csv(d / "crossover_dates.csv", dtype={"date": str}))
        years = ", ".join(str(y) for y in summary.get("years", []))
        if len(c):
            parts.append("<h3>Crossover times by calendar date over the years "
                         f"{html.escape(years)} (local clock, median and 5–95 %)</h3>"
                         + html_table(c, "{:.2f}"))
    if (d / "overpasses.csv").is_file():
        o = strip_units(pd.read_csv(d / "overpasses.csv"))
        if len(o):
            parts.append("<details><summary>every overpass</summary>"
                         + html_table(o, "{:.3g}") + "</details>")
    return "".join(parts)


#: Largest CSV embedded as a download [bytes], and all of them together
_EMBED_CSV_MAX, _EMBED_TOTAL_MAX = 512 * 1024, 3 * 1024 * 1024

#: What each kind of product file is, for the list of files (docs/DATA.md has the details)
_FILE_KINDS = {".nc": "NetCDF (CF) image stack", ".tif": "GeoTIFF", ".vtkhdf": "VTKHDF (ParaView)",
               ".npz": "NumPy archive", ".json": "JSON", ".png": "picture", ".svg": "picture",
               ".pdf": "picture", ".csv": "table", ".vtu": "VTU", ".pvd": "ParaView series",
               ".vtp": "VTP"}


def _size(n: int) -> str:
    return f"{n / 1e6:.1f} MB" if n >= 1e5 else f"{n / 1e3:.0f} kB"


def _downloads_section(run: Path) -> str:
    """The run's tables as downloads embedded in the page (``data:text/csv`` links, up to
    :data:`_EMBED_CSV_MAX` each), and every other product with its path in the run folder
    and size (the units and meaning of every column and variable: docs/DATA.md)."""
    skip = {"report.html", "manifest.json", "COMPLETE"}
    files = sorted(p for p in run.rglob("*") if p.is_file() and p.name not in skip
                   and not p.name.startswith(".") and "checkpoints" not in p.parts)
    links, listed, total = [], [], 0
    for f in files:
        rel = f.relative_to(run).as_posix()
        size = f.stat().st_size
        if f.suffix == ".csv" and size <= _EMBED_CSV_MAX and total + size <= _EMBED_TOTAL_MAX:
            total += size
            data = base64.b64encode(f.read_bytes()).decode("ascii")
            name = rel.replace("/", "_")
            links.append(f'<li><a download="{html.escape(name)}" href="data:text/csv;base64,'
                         f'{data}">{html.escape(rel)}</a> ({_size(size)})</li>')
        elif f.suffix != ".png":
            listed.append(f"<li><code>{html.escape(rel)}</code> — "
                          f"{_FILE_KINDS.get(f.suffix, f.suffix.lstrip('.'))}, {_size(size)}</li>")
    if not links and not listed:
        return ""
    out = []
    if links:
        out.append("<p>Tables (CSV, units in the headers), inside this page:</p>"
                   f'<ul class="downloads">{"".join(links)}</ul>')
    if listed:
        out.append("<p>In the run folder next to this report (too large to embed):</p>"
                   f'<ul class="downloads">{"".join(listed)}</ul>')
    out.append('<p class="note">What every column, variable and band holds, with units and '
               "the time convention: docs/DATA.md of shipthermal.</p>")
    return "".join(out)


def build_report(run_dir, finishing: bool = False) -> str:
    """The HTML text of a run directory's report (``finishing``: written as the last step
    of a run that is about to write its ``COMPLETE`` marker)."""
    run = Path(run_dir)
    if not run.is_dir():
        raise InputError("run directory", str(run), "must be an existing folder")
    try:
        manifest = json.loads((run / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        raise InputError("run directory", str(run), "must hold a readable manifest.json "
                         "(a shipthermal run directory)") from None
    complete = finishing or (run / MARKER).is_file()
    cases = _cases(run, manifest)
    seasons = {c: (manifest.get("cases", {}).get(c, {}) or {}).get("season") for c in cases}
    nav, body = [], []

    def section(anchor, title, content):
        if content:
            nav.append(f'<a href="#{anchor}">{title}</a>')
            body.append(f'<section id="{anchor}"><h2>{title}</h2>{content}</section>')

    status = "complete" if complete else manifest.get("status", "unknown")
    cls = "status-complete" if complete else "status-other"
    versions = manifest.get("versions", {})
    git = manifest.get("git") or {}
    timings = manifest.get("timings_s", {})
    run_pairs = [("status", status), ("kind", manifest.get("kind")),
                 ("started / finished", f"{manifest.get('started')} / {manifest.get('finished')}"),
                 ("command", " ".join(manifest.get("command", []))),
                 ("git commit", f"{git.get('commit', 'n/a')}"
                                + (" (local changes)" if git.get("local_changes") else "")),
                 ("seeds", json.dumps(manifest.get("seeds", {}))),
                 ("settings", json.dumps(manifest.get("settings", {}))),
                 ("versions", ", ".join(f"{k} {v}" for k, v in versions.items() if v))]
    run_html = _kv(run_pairs)
    if timings:
        run_html += "<h3>Wall time per stage [s]</h3>" + html_table(pd.DataFrame(
            [{"stage": k, "seconds": v} for k, v in timings.items()]), "{:.1f}")
    # deferred: the day's pictures, 17 ms of every command's start-up (measured)
    from . import report_day

    answer = report_day.first_screen(run)
    section("day", "The day, hour by hour", report_day.day_section(run))
    section("run", "Run", run_html)
    section("scenario", "Scenario", "".join(_scenario_section(c, f) for c, f in cases.items()))
    if (run / "mesh").is_dir():
        section("mesh", "Mesh", _mesh_section(run / "mesh"))
    if (run / "thermal").is_dir():
        th = []
        for d in sorted(p for p in (run / "thermal").iterdir() if p.is_dir()):
            th.append(_thermal_section(d.name, d, seasons.get(d.name)))
        section("thermal", "Thermal", "".join(th))
    if (run / "imaging").is_dir():
        section("imaging", "Imaging", _imaging_section(run / "imaging"))
    if (run / "validation").is_dir():
        section("validation", "Validation", _validation_section(run / "validation"))
    if (run / "calendar").is_dir():
        section("calendar", "Detectability calendar", _calendar_section(run / "calendar"))
    if (run / "ensemble" / "crossovers.csv").is_file():   # a weather ensemble
        ens = run / "ensemble"
        parts = [_img_file(ens / "ensemble.png", "crossover times of the members with their "
                           "median and 5-95 % range; SCR median with its 5-95 % band")
                 if (ens / "ensemble.png").is_file() else ""]
        dist = strip_units(pd.read_csv(ens / "crossovers.csv",
                                       dtype={"median": str, "p05": str, "p95": str}))
        parts.append(html_table(dist[[c for c in dist.columns if not c.endswith("_h")]], "{:.3f}"))
        if (ens / "ensemble.toml").is_file():
            parts.append("<details><summary>distributions and seed</summary><pre>"
                         + html.escape((ens / "ensemble.toml").read_text()) + "</pre></details>")
        section("ensemble", "Weather ensemble: crossover times", "".join(parts))
    if (run / "table.csv").is_file():
        sweep = []
        if (run / "sweep.toml").is_file():
            sweep.append("<details><summary>sweep file</summary><pre>"
                         + html.escape((run / "sweep.toml").read_text()) + "</pre></details>")
        if (run / "table.png").is_file():
            sweep.append(_img_file(run / "table.png", "one point per case"))
        table = strip_units(pd.read_csv(run / "table.csv"))
        table = table[[c for c in table.columns if c not in ("worker",)]]
        sweep.append(html_table(table, "{:.3f}"))
        section("sweep", "Sweep", "".join(sweep))
    section("data", "Data", _downloads_section(run))
    title = f"shipthermal run {run.resolve().name}"
    head = (f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">{GENERATOR}'
            f'<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body><main>"
            f"<h1>{html.escape(title)}</h1><p>Status: <span class=\"{cls}\">"
            f"{html.escape(str(status))}</span>"
            + ("" if complete else " — this run did not finish: its results are partial")
            + f"</p>{answer}<nav>{''.join(nav)}</nav>")
    has_slider = 'id="day-slider"' in "".join(body)
    script = f"<script>{report_day.SCRIPT}</script>" if has_slider else ""
    return head + "".join(body) + f"</main>{script}</body></html>\n"


def is_report_file(path) -> bool:
    """Whether ``path`` is a report this tool wrote (its generator tag, or the title that
    earlier versions began with): the only kind of file ``report --output`` writes over."""
    try:
        with open(path, "rb") as fh:
            start = fh.read(4096)
    except OSError:
        return False
    return (start.startswith(b"<!DOCTYPE html>")
            and (GENERATOR.encode() in start or b"<title>shipthermal run " in start))


def write_report(run_dir, path=None, finishing: bool = False) -> Path:
    """Write the report of ``run_dir`` (default ``<run_dir>/report.html``) atomically."""
    text = build_report(run_dir, finishing)
    return atomic_write_text(Path(path) if path is not None else Path(run_dir) / "report.html",
                             text)
