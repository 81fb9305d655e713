"""Weather ensembles: crossover times and SCR curves with an uncertainty.

The built-in weather is one design day per season (``shipthermal.environment.climatology``);
a real day differs from it. An ensemble draws ``N`` members of three weather offsets from
stated distributions (:data:`DISTRIBUTIONS`, the one place where they and their reasons
live), with a Latin hypercube of fixed seed (``scipy.stats.qmc``), and runs every member ×
season as one case of a sweep (:mod:`shipthermal.app.sweep`: dask LocalCluster, an existing
scheduler, or serial; thermal and imaging stages). Each crossover moment (band, season,
direction, its order in the day) is then given as the median and the 5–95 % range of the
members' times, and the SCR curves as a median with a 5–95 % band.

The same members (the same draws) are used in every season, so the seasons are compared on
the same weather perturbations. Files in ``DIR/ensemble/``:

* ``ensemble.toml``   — distributions, seed, members, seasons (what was asked);
* ``members.csv``     — one row per member: its drawn offsets;
* ``member_crossovers.csv`` — every member's crossover times (long form);
* ``crossovers.csv``  — per season, band, direction and order: members with that crossover,
  median and 5 / 95 % percentiles [h and HH:MM];
* ``scr.csv``         — per season, band and frame time: SCR 5 %, median, 95 %;
* ``ensemble.png``    — the crossover distribution per band and season and the SCR bands.

The sweep's own files (``cases/``, ``table.csv``, ``table.png``) sit beside them.
"""

from __future__ import annotations

import json
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..atomic import atomic_path, atomic_write_text
from ..errors import InputError
from ..figures import OKABE_ITO, band_label
from ..results import save_png
from .scenario import ScenarioError, loads_scenario
from .sweep_file import load_sweep

__all__ = ["DISTRIBUTIONS", "PERCENTILES", "Distribution", "draw_members",
           "ensemble_sweep_text", "format_distribution", "load_ensemble_sweep",
           "member_crossovers", "parse_distribution", "plot_ensemble", "summarise",
           "write_ensemble"]

#: Percentiles of the ranges [%] (the range is 5–95 %; the median is the 50th).
PERCENTILES = (5.0, 50.0, 95.0)

KINDS = {"uniform": ("lower", "upper"), "normal": ("mean", "standard deviation")}


@dataclass(frozen=True)
class Distribution:
    """One varied weather quantity: the scenario key it offsets and its distribution."""

    name: str
    key: str
    kind: str
    a: float
    b: float
    unit: str
    source: str

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Quantile function at ``u`` in (0, 1) (scipy.stats)."""
        # lazy: scipy.stats takes over a second to import (measured)
        from scipy import stats

        if self.kind == "uniform":
            return stats.uniform(loc=self.a, scale=self.b - self.a).ppf(u)
        return stats.norm(loc=self.a, scale=self.b).ppf(u)

    def describe(self) -> str:
        p1, p2 = KINDS[self.kind]
        return f"{self.name} ({self.key}): {self.kind}, {p1} {self.a:g}, {p2} {self.b:g} {self.unit}"


#: The default distributions (ASSUMPTION labels as in the climatology: our choice where
#: no statistic of Dalian's day-to-day spread was at hand; override with ``--dist``).
DISTRIBUTIONS = {
    "cloud": Distribution(
        "cloud", "weather.cloud_cover_offset", "uniform", -0.3, 0.3, "",
        "ASSUMPTION: the design day's cloud fraction (1 - relative sunshine, DERIVED in "
        "the climatology) is a monthly mean; single days range from clear to overcast, "
        "so +-0.3 spans most days without making every member clear or overcast"),
    "wind": Distribution(
        "wind", "weather.wind_speed_offset", "normal", 0.0, 1.5, "m/s",
        "ASSUMPTION: the design day's 4-5 m/s is itself an ASSUMPTION inside the range of "
        "the climatology's source; 1.5 m/s standard deviation of the daily mean wind"),
    "air": Distribution(
        "air", "weather.temp_air_offset", "normal", 0.0, 2.0, "K",
        "ASSUMPTION: 2 K standard deviation of the daily mean air temperature about the "
        "monthly mean (typical of mid-latitude coastal stations; the whole diurnal curve "
        "moves)"),
}

_DIST_RE = re.compile(r"^([A-Za-z_]+)=(uniform|normal):([^:]+):([^:]+)$")


def parse_distribution(text: str) -> Distribution:
    """``NAME=uniform:LOWER:UPPER`` or ``NAME=normal:MEAN:SD`` (``NAME`` in
    :data:`DISTRIBUTIONS`) → a :class:`Distribution` replacing that default.

    Raises
    ------
    InputError
        Unknown name, malformed text, non-numbers, an empty range or a non-positive SD.
    """
    name = text.split("=", 1)[0].strip()
    if name not in DISTRIBUTIONS:
        raise InputError("--dist", name, f"must name one of {', '.join(DISTRIBUTIONS)}",
                         "e.g. --dist wind=normal:0:1.5")
    m = _DIST_RE.match(text.replace(" ", ""))
    if not m:
        raise InputError("--dist", text, "must be NAME=uniform:LOWER:UPPER or "
                         "NAME=normal:MEAN:SD", "e.g. --dist cloud=uniform:-0.3:0.3")
    try:
        a, b = float(m.group(3)), float(m.group(4))
    except ValueError:
        raise InputError("--dist", text, "must give two numbers after the kind") from None
    kind = m.group(2)
    if not (np.isfinite(a) and np.isfinite(b)):
        raise InputError("--dist", text, "must give finite numbers")
    if kind == "uniform" and not a < b:
        raise InputError("--dist", text, "must have LOWER < UPPER")
    if kind == "normal" and not b > 0:
        raise InputError("--dist", text, "must have a standard deviation > 0")
    d = DISTRIBUTIONS[name]
    return Distribution(name, d.key, kind, a, b, d.unit, "given on the command line")


MAX_MEMBERS = 1000
"""Most members of an ensemble (a 5-95 % range is stable to a few percent with 100; a
thousand members is days of runs)."""


def draw_members(dists, members: int, seed: int = 0) -> pd.DataFrame:
    """``members`` draws of every distribution: a Latin hypercube (scipy.stats.qmc, fixed
    ``seed``) mapped through each quantile function; values rounded to 4 decimals (they
    are written into scenario files). One row per member, one column per scenario key."""
    # lazy: scipy.stats takes over a second to import (measured)
    from scipy.stats import qmc

    if not isinstance(members, int) or members < 2:
        raise InputError("--members", members, "must be an integer >= 2 (a range needs "
                         "several members)", "e.g. --members 8")
    if members > MAX_MEMBERS:
        raise InputError("--members", members, f"must be at most {MAX_MEMBERS} (each member "
                         "is a thermal and an imaging run per season)", "e.g. --members 8")
    if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) \
            or not 0 <= seed <= 2 ** 32 - 1:
        raise InputError("--seed", seed, "must be an integer in [0, 4294967295]",
                         "e.g. --seed 0")
    dists = list(dists)
    u = qmc.LatinHypercube(d=len(dists), seed=seed).random(members)
    df = pd.DataFrame({d.key: np.round(d.ppf(u[:, j]), 4) for j, d in enumerate(dists)})
    df.insert(0, "member", np.arange(members))
    return df


def _toml_value(v) -> str:
    return json.dumps(v)    # strings, numbers and lists of them are valid TOML this way


def ensemble_sweep_text(base: str, draws: pd.DataFrame, seasons=None, fixed=None) -> str:
    """The sweep file of an ensemble: the seasons (optional) × one grouped axis of the
    members (each member sets its offsets together)."""
    lines = ['name = "ensemble"', f"base = {_toml_value(base)}",
             'stages = ["thermal", "imaging"]']
    if fixed:
        lines.append("[set]")
        lines += [f"{_toml_value(k)} = {_toml_value(v)}" for k, v in fixed.items()]
    lines.append("[axes]")
    if seasons:
        lines.append(f'"time.season" = {_toml_value(list(seasons))}')
    for _, row in draws.iterrows():
        lines.append("[[axes.member]]")
        lines += [f"{_toml_value(k)} = {float(row[k])!r}" for k in draws.columns
                  if k != "member"]
    return "\n".join(lines) + "\n"


def load_ensemble_sweep(text: str):
    """Validate the ensemble's sweep (every case's scenario) without writing anything
    beside the inputs: the text goes through a temporary file."""
    with tempfile.TemporaryDirectory(prefix="shipthermal-ensemble-") as tmp:
        path = Path(tmp) / "ensemble.toml"
        path.write_text(text, encoding="utf-8")
        try:
            return load_sweep(path)
        except ScenarioError as exc:        # the members, not the temporary file
            raise ScenarioError(exc.errors, "ensemble members") from None
        except InputError as exc:
            value = "the ensemble" if str(exc.value) == str(path) else exc.value
            raise InputError(exc.field, value, exc.allowed, exc.fix) from None


def _hhmm(h: float) -> str:
    if not np.isfinite(h):
        return ""
    m = round(h * 60.0)
    return f"{(m // 60) % 24:02d}:{m % 60:02d}"


def member_crossovers(spec, cases_dir, members: int) -> tuple:
    """Long tables from the case files: crossovers (season, member, band, direction,
    order, time_h) and SCR curves (season, member, band, time_h, scr)."""
    rows, curves = [], []
    for case in spec.cases:
        f = Path(cases_dir) / f"{case.id}.json"
        if not f.is_file():
            continue
        r = json.loads(f.read_text(encoding="utf-8"))
        if r.get("status") != "ok":
            continue
        season = loads_scenario(case.toml).time.season
        member = case.index % members
        for band, items in (r.get("crossovers") or {}).items():
            seen: dict = {}
            for t, direction in items:
                seen[direction] = seen.get(direction, 0) + 1
                rows.append({"season": season, "member": member, "band": band,
                             "direction": direction, "order": seen[direction],
                             "time_h": float(t)})
        for band, c in (r.get("curves") or {}).items():
            for t, s in zip(c["time_h"], c["scr"]):
                curves.append({"season": season, "member": member, "band": band,
                               "time_h": float(t), "scr": float(s)})
    cross = pd.DataFrame(rows, columns=["season", "member", "band", "direction", "order",
                                        "time_h"])
    return cross, pd.DataFrame(curves, columns=["season", "member", "band", "time_h", "scr"])


def summarise(cross: pd.DataFrame, curves: pd.DataFrame, members_ok: dict) -> tuple:
    """Crossover distribution and SCR band.

    ``members_ok`` maps a season to the number of members that finished. A crossover
    moment is one (season, band, direction, order); ``members`` counts the members that
    have it (a member may miss a weak crossover), and the percentiles are over those.
    """
    lo, mid, hi = PERCENTILES
    rows = []
    for (season, band, direction, order), g in cross.groupby(
            ["season", "band", "direction", "order"], sort=True):
        t = g["time_h"].to_numpy(float)
        p = np.percentile(t, [lo, mid, hi])
        rows.append({"season": season, "band": band, "direction": direction, "order": order,
                     "members": len(t), "of": members_ok.get(season, len(t)),
                     "median_h": p[1], "p05_h": p[0], "p95_h": p[2],
                     "median": _hhmm(p[1]), "p05": _hhmm(p[0]), "p95": _hhmm(p[2])})
    dist = pd.DataFrame(rows, columns=["season", "band", "direction", "order", "members", "of",
                                       "median_h", "p05_h", "p95_h", "median", "p05", "p95"])
    if len(dist):
        dist = dist.sort_values(["season", "band", "median_h"]).reset_index(drop=True)
    band = (curves.groupby(["season", "band", "time_h"])["scr"]
            .quantile([lo / 100, mid / 100, hi / 100]).unstack()
            if len(curves) else pd.DataFrame())
    if len(band):
        band.columns = ["scr_p05", "scr_median", "scr_p95"]
        band = band.reset_index()
    return dist, band


def plot_ensemble(cross: pd.DataFrame, dist: pd.DataFrame, band: pd.DataFrame, path,
                  title: str = "") -> Path:
    """PNG: per band (rows) the member crossover times per season with median and 5–95 %
    range (left) and the SCR median with its 5–95 % band per season (right)."""
    # lazy: matplotlib takes most of a second to import (measured)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    bands = sorted(set(cross["band"]) | set(band["band"] if len(band) else []))
    seasons = sorted(set(cross["season"]) | set(band["season"] if len(band) else []))
    colours = {s: c for s, c in zip(seasons, [OKABE_ITO["orange"], OKABE_ITO["blue"],
                                              OKABE_ITO["bluish_green"],
                                              OKABE_ITO["reddish_purple"]])}
    fig, axes = plt.subplots(max(len(bands), 1), 2,
                             figsize=(12, 3.4 * max(len(bands), 1) + 0.6), squeeze=False)
    for i, b in enumerate(bands):
        a, s_ax = axes[i]
        labels = []
        for _, r in dist[dist["band"] == b].iterrows() if len(dist) else []:
            y = len(labels)
            g = cross[(cross["season"] == r["season"]) & (cross["band"] == b)
                      & (cross["direction"] == r["direction"]) & (cross["order"] == r["order"])]
            col = colours[r["season"]]
            a.plot(g["time_h"], np.full(len(g), y), "o", color=col, alpha=0.45, ms=5)
            a.hlines(y, r["p05_h"], r["p95_h"], color=col, lw=3)
            a.plot(r["median_h"], y, "|", color="k", ms=16, mew=2)
            a.text(r["p95_h"], y + 0.18, f" {r['median']} ({r['p05']}–{r['p95']})",
                   fontsize=8, va="bottom")
            labels.append(f"{r['season']} {r['direction']} #{r['order']}\n"
                          f"{r['members']}/{r['of']} members")
        a.set_yticks(range(len(labels)))
        a.set_yticklabels(labels, fontsize=8)
        a.set_ylim(-0.7, max(len(labels), 1) - 0.3)
        a.set_xlim(0, 24)
        a.set_xticks(range(0, 25, 3))
        a.set_xlabel("local time [h]")
        a.set_title(f"{band_label(b)}: crossover times (members, 5–95 % range, median)",
                    fontsize=9)
        a.grid(alpha=0.3)
        if len(band):
            for s in seasons:
                g = band[(band["band"] == b) & (band["season"] == s)]
                if not len(g):
                    continue
                s_ax.fill_between(g["time_h"], g["scr_p05"], g["scr_p95"],
                                  color=colours[s], alpha=0.25, lw=0)
                s_ax.plot(g["time_h"], g["scr_median"], color=colours[s],
                          label=f"{s} median, 5–95 %")
        s_ax.set_xlim(0, 24)
        s_ax.set_xticks(range(0, 25, 3))
        s_ax.set_xlabel("local time [h]")
        s_ax.axhline(1.0, color=OKABE_ITO["black"], lw=0.8, ls=(0, (1, 2)))
        s_ax.set_ylabel("SCR [-] (dotted: SCR = 1)")
        s_ax.set_title(f"{band_label(b)}: SCR", fontsize=9)
        s_ax.grid(alpha=0.3)
        s_ax.legend(fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return save_png(fig, path, dpi=90)


def write_ensemble(spec, out_dir, draws: pd.DataFrame, dists, seed: int,
                   seasons, quick: bool) -> dict:
    """After the sweep: the ensemble files in ``out_dir/ensemble`` (see the module)."""
    out = Path(out_dir)
    ens = out / "ensemble"
    ens.mkdir(parents=True, exist_ok=True)
    members = len(draws)
    cross, curves = member_crossovers(spec, out / "cases", members)
    ok: dict = {}
    for case in spec.cases:
        f = out / "cases" / f"{case.id}.json"
        if f.is_file() and json.loads(f.read_text(encoding="utf-8")).get("status") == "ok":
            s = loads_scenario(case.toml).time.season
            ok[s] = ok.get(s, 0) + 1
    dist, band = summarise(cross, curves, ok)
    files = {}

    def csv(df, name, fmt="%.6f"):
        with atomic_path(ens / name) as tmp:
            df.to_csv(tmp, index=False, float_format=fmt)
        files[name] = ens / name

    csv(draws, "members.csv")
    csv(cross, "member_crossovers.csv")
    csv(dist, "crossovers.csv")
    csv(band, "scr.csv")
    lines = [f"members = {members}", f"seed = {seed}",
             'sampling = "latin hypercube (scipy.stats.qmc.LatinHypercube)"', f"quick = {str(bool(quick)).lower()}",
             f"seasons = {_toml_value(sorted(ok) or list(seasons or []))}",
             f"percentiles = {list(PERCENTILES)}"]
    for d in dists:
        p1, p2 = KINDS[d.kind]
        lines += [f"[distributions.{d.name}]", f"key = {_toml_value(d.key)}",
                  f"kind = {_toml_value(d.kind)}",
                  f"{_toml_value(p1.replace(' ', '_'))} = {d.a!r}",
                  f"{_toml_value(p2.replace(' ', '_'))} = {d.b!r}",
                  f"unit = {_toml_value(d.unit)}", f"source = {_toml_value(d.source)}"]
    atomic_write_text(ens / "ensemble.toml", "\n".join(lines) + "\n")
    files["ensemble.toml"] = ens / "ensemble.toml"
    files["ensemble.png"] = plot_ensemble(
        cross, dist, band, ens / "ensemble.png",
        f"weather ensemble: {members} members, Latin hypercube seed {seed}\n"
        + "\n".join(d.describe() for d in dists))
    return {"files": files, "crossovers": dist, "scr": band, "members": cross}


def format_distribution(dist: pd.DataFrame) -> str:
    """The crossover distribution as a printable table."""
    if not len(dist):
        return "  no crossover in any member"
    show = dist[["season", "band", "direction", "order", "members", "of", "median", "p05",
                 "p95"]].rename(columns={"p05": "5%", "p95": "95%"})
    return show.to_string(index=False)
