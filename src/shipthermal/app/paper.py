"""The paper's reference values and the comparison of our crossover moments with its own.

The paper (§3.1) reproduces the area-mean deck temperature of its ref. [26] at four moments
(:data:`REFERENCE_DECK`) and reports thermal-crossover moments (§5,
:data:`PAPER_CROSSOVERS`). Used by the validation, the calibration of the paper's case and
the report.
"""

from __future__ import annotations

import numpy as np

from .run_environment import sky_weather
from .thermal import ship_thermal_history

__all__ = ["REFERENCE_DECK", "PAPER_CROSSOVERS", "clock_text", "crossover_rows"]

#: (season, local hour) → area-mean deck temperature of the paper / its ref. [26] [K]
REFERENCE_DECK = {("summer", 12.0): 304.67, ("winter", 12.0): 280.51,
                  ("summer", 7.0): 292.08, ("winter", 8.0): 274.88}

#: (season, band) → the paper's crossover moments [local hour] (§5.1, §5.2)
PAPER_CROSSOVERS = {("summer", "3-5"): (6.5, 19.5), ("winter", "3-5"): (8.5, 18.5),
                    ("winter", "8-14"): (8.5, 18.0), ("summer", "8-14"): ()}


def clock_text(h) -> str:
    """A local hour as ``HH:MM`` (``—`` for none)."""
    if h is None or not np.isfinite(h):
        return "—"
    m = int(round(h * 60))
    return f"{m // 60:02d}:{m % 60:02d}"


def crossover_rows(scen, runs, progress, say):
    """Crossover moments next to the paper's: contrast zero crossings every 10 min in
    every band of each season's scenario (``scen[season]``), rendered from its thermal run
    (``runs[season]``); one row per season and band."""
    from imaging.experiment import ImagingScenario, render_series

    rows = []
    times = np.arange(0.0, 86400.0, 600.0)
    for season, res in runs.items():
        sc = scen[season]
        say(f"{season}: imaging every 10 min for the crossover moments")
        # the image's sky follows this scenario's weather, as the thermal run's does
        img = ImagingScenario.default(season, sky_weather=sky_weather(sc.environment()))
        series = render_series(ship_thermal_history(res), img, bands=tuple(sc.bands), times_s=times,
                               progress=progress)
        for band, sr in series.items():
            ours = [c.time / 3600.0 for c in sr.crossovers]
            paper = PAPER_CROSSOVERS.get((season, band), ())
            diffs = []
            for p in paper:
                if ours:
                    k = int(np.argmin([abs(o - p) for o in ours]))
                    diffs.append(f"{60 * (ours[k] - p):+.0f} min")
                else:
                    diffs.append("none found")
            rows.append({"season": season, "band": band,
                         "ours": ", ".join(clock_text(h) for h in ours) or "none",
                         "paper": ", ".join(clock_text(h) for h in paper) or "not given",
                         "difference": ", ".join(diffs) or "—"})
    return rows
