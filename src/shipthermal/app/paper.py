"""The paper's reference values and the comparison of our crossover moments with its own.

The paper (§3.1) reproduces the area-mean deck temperature of its ref. [26] at four moments
(:data:`REFERENCE_DECK`) and reports thermal-crossover moments (§5,
:data:`PAPER_CROSSOVERS`). Used by the validation, the calibration of the paper's case and
the report.
"""

from __future__ import annotations

import numpy as np

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


def crossover_rows(results: dict, say=None) -> list:
    """Crossover moments next to the paper's, one row per season and band.

    ``results = {season: SimulationResult}`` (:class:`shipthermal.app.chain.
    SimulationResult`): each season's scenario imaged by the chain of ``shipthermal run
    --image`` — its own background, mooring, heading, view, sensor, emissivities and
    weather — every ``imaging.scr_interval`` from its thermal run. Nothing here builds a
    scene of its own, so the moments are those a run of the same scenario reports.
    """
    rows = []
    for season, result in results.items():
        if say:
            say(f"{season}: imaging every {result.scenario.imaging.scr_interval / 60:g} min "
                "for the crossover moments")
        for band, sr in result.series.items():
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
