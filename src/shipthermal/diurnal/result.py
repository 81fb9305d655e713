"""The outcome of a diurnal run: :class:`DiurnalResult` (the recorded day, or a weather
record's outputs on disk, with the spin-up's bookkeeping) and its products — part-mean
table and curves, surface maps, VTKHDF files, the JSON summary.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..figures import LINE_STYLES, PART_LINE_STYLES, save_figure
from ..geometry import main_part
from ..geometry.surface_maps import render_surface_map
from ..results import EnergyLog, Results, atomic_path, graph_vtkhdf, write_surface_vtkhdf
from ..units import HOUR, with_units
from .settings import DiurnalSettings


#: Columns of the part-mean table, in plotting order
MAIN_SERIES = ("hull", "deck", "superstructure", "hull_wetted")


def part_groups(part_names) -> dict:
    """Pool sub-parts for reporting: ``hull_dry`` → ``hull`` (the visible hull),
    ``hull_wetted`` stays, ``superstructure_mast`` → ``superstructure``."""
    out = {}
    for name in part_names:
        main = main_part(name)
        out[name] = "hull" if main in ("hull_dry", "hull") else main
    return out


def part_mean_table(res: Results, groups: dict, environment) -> pd.DataFrame:
    """Area-mean outer-surface temperature per reporting part (``groups``:
    :func:`part_groups`), :data:`MAIN_SERIES` first, then air, bulk sea and sea-skin
    temperature at the output times of ``res`` [K]."""
    pm = res.part_mean("outer", groups=groups)
    pm = pm[[c for c in MAIN_SERIES if c in pm.columns]
            + [c for c in pm.columns if c not in MAIN_SERIES]]
    env = environment.at(res.times)
    pm["temp_air"] = env.temp_air
    pm["temp_sea"] = env.temp_sea
    pm["temp_sea_skin"] = env.temp_sea_skin
    return pm


@dataclass(eq=False)
class DiurnalResult:
    """A converged (or capped) diurnal run: the last simulated day.

    Attributes
    ----------
    ship : ShipGeometry
    graph : CellGraph
    forcing : ShipForcing
    results : Results
        The recorded day with ``times`` in seconds after local midnight [s].
    part_means : pandas.DataFrame
        Area-mean outer-surface temperature per reporting part, plus ``temp_air``,
        ``temp_sea`` (bulk) and ``temp_sea_skin``, indexed by local hour [K].
    days : int
        Days simulated (spin-up included).
    day_changes : list of float
        Largest cell-temperature change over each day, end vs start [K] (the periodicity
        defect; it bounds the change to the following day).
    converged : bool
    energy : EnergyLog
        Every step of the whole run.
    timings : dict
        Wall times [s]: mesh, forcing (ray tracing + tables), solve, total.
    record : RecordFile, optional
        A weather record's outputs on disk
        (:func:`~shipthermal.diurnal.record.run_record`), read lazily; ``results`` then
        holds the final state only and ``forcing`` the last window's tables.
    """

    ship: object
    graph: object
    forcing: object
    results: Results
    part_means: pd.DataFrame
    days: int
    day_changes: list
    converged: bool
    energy: EnergyLog
    timings: dict
    settings: DiurnalSettings
    environment: object = None
    meta: dict = field(default_factory=dict)
    record: object = None

    @property
    def n_surface_faces(self) -> int:
        return int(self.ship.n_faces)

    def __repr__(self) -> str:
        # the dataclass's own repr prints every array: a few lines instead
        kind = (f"{self.meta['record_days']} recorded days" if self.is_record
                else "one periodic day")
        return (f"DiurnalResult({self.ship.name}: {self.ship.n_faces} faces, "
                f"{self.graph.n_cells} cells; {kind} after {self.days} days, "
                f"{'converged' if self.converged else 'not converged'}; "
                f"{len(self.results.times)} outputs; parts {', '.join(self.part_means.columns)})")

    def part_mean_at(self, part: str, hour: float) -> float:
        """Area-mean outer temperature of a reporting part at a local hour [K] (linear)."""
        s = self.part_means[part]
        return float(np.interp(hour, s.index.to_numpy(), s.to_numpy()))

    def outer_face_temperature(self) -> np.ndarray:
        """(nt, M) outer-surface temperature of each ship triangle [K] (a weather record's:
        the streamed file's dataset, read as indexed)."""
        if self.record is not None:
            return self.record.face_temperature
        m = self.ship.n_faces
        return self.results.face_temperature[:, :m]

    @property
    def is_record(self) -> bool:
        """Whether this is a weather-record run
        (:func:`~shipthermal.diurnal.record.run_record`) over several days."""
        return "record_days" in self.meta

    def summary(self) -> dict:
        """JSON-ready summary (spin-up, energy, timings, part extremes)."""
        pm = self.part_means
        parts = {c: {"min_K": float(pm[c].min()), "max_K": float(pm[c].max()),
                     "hour_of_max": float(pm[c].idxmax())} for c in pm.columns}
        return {"ship": self.ship.name, "surface_faces": self.n_surface_faces,
                "edge_length_m": (float(self.ship.edge_length)
                                  if np.isfinite(self.ship.edge_length) else None),
                "cells": int(self.graph.n_cells), "days": self.days,
                "converged": self.converged,
                "day_changes_K": [None if not np.isfinite(x) else float(x) for x in self.day_changes],
                "spinup_tolerance_K": self.settings.spinup_tolerance,
                "energy": self.energy.summary(), "timings_s": self.timings, "parts": parts,
                "settings": {k: getattr(self.settings, k) for k in self.settings.__dataclass_fields__},
                **self.meta}

    # ------------------------------------------------------------------ outputs -----------
    def write(self, out_dir, map_hours=(7.0, 12.0), formats=("csv", "png", "vtkhdf", "json"),
              progress: bool = False, figures=None) -> dict:
        """Write the run's products into ``out_dir`` (each file atomically).

        * ``part_means.csv`` — hourly table of part means, air and sea [K] (headers
          ``name [unit]``, as every CSV product: docs/DATA.md);
        * ``part_means.png`` — 24 h curves of hull, deck, superstructure with air and sea;
        * ``surface_HHMM.png`` — the ship coloured by outer-surface temperature;
        * ``thermal.vtkhdf`` — the recorded day, cells (ParaView ≥ 5.12; the surface as a
          VTU series: ``results.to_vtu``);
        * ``surface.vtkhdf`` — the ship's outer surface over the recorded day: the
          temperature of every triangle the images are rendered from, with its part;
        * ``thermal_summary.json`` — spin-up, energy balance, timings.

        ``figures`` (:class:`shipthermal.figures.FigureOptions`): resolution and vector copies
        of the pictures. Returns a mapping product → path.
        """
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        written = {}
        if "csv" in formats:
            with atomic_path(out / "part_means.csv") as tmp:
                with_units(self.part_means, {c: "K" for c in self.part_means.columns}).to_csv(
                    tmp, float_format="%.4f")
            written["part_means_csv"] = out / "part_means.csv"
            fs = pd.DataFrame(self.forcing.summary()) if self.forcing is not None else None
            if fs is not None:
                with atomic_path(out / "forcing_summary.csv") as tmp:
                    with_units(fs).to_csv(tmp, float_format="%.5g")
                written["forcing_csv"] = out / "forcing_summary.csv"
        if "png" in formats:
            where = self.where()
            written["part_means_png"] = plot_part_means(self.part_means, out / "part_means.png",
                                                        title=f"{self.ship.name}: area-mean "
                                                        f"outer-surface temperature{where}",
                                                        figures=figures)
            env = self.environment
            heading = float(getattr(env, "ship_heading", 0.0))
            view = self.meta.get("sensor_view_deg") or (0.0, 0.0)
            clim = None
            if map_hours:
                allt = np.concatenate([self.face_temperature_at(h) for h in map_hours])
                clim = (float(np.percentile(allt, 1)), float(np.percentile(allt, 99)))
            for hour in map_hours:
                name = out / f"surface_{int(hour):02d}{int(round(60 * (hour % 1))):02d}.png"
                sun_az, sun_el = 180.0, -90.0
                if env is not None:
                    st = env.at([hour * HOUR])
                    sun_az, sun_el = float(st.azimuth[0]), 90.0 - float(st.zenith[0])
                render_surface_map(self.ship.vertices, self.ship.faces,
                                   self.face_temperature_at(hour), name, heading_deg=heading,
                                   sun_azimuth_deg=sun_az, sun_elevation_deg=sun_el,
                                   view_zenith_deg=view[0], view_azimuth_deg=view[1],
                                   clim=clim, title=f"{self.ship.name}, outer surface at "
                                   f"{_clock(hour)} local{where}", figures=figures)
                written[f"surface_{hour:g}h"] = name
        if "vtkhdf" in formats:
            start = getattr(self.environment, "start", None)
            units = f"s since {start.isoformat(sep=' ')}" if start is not None else None
            ship = self.ship
            m = ship.n_faces
            if self.record is not None:
                # the sampled days of a record (record_stream.SAMPLE_DAYS_MAX)
                rec = self.record
                times = rec.sample_times
                written["vtkhdf"] = graph_vtkhdf(out / "thermal.vtkhdf", self.graph, times,
                                                 lambda k: rec.sample_row(k)[0], time_units=units)
                outer = (lambda k: rec.sample_row(k)[1][:m])
            else:
                times = self.results.times
                written["vtkhdf"] = self.results.to_vtkhdf(out / "thermal.vtkhdf",
                                                           time_units=units)
                outer = self.outer_face_temperature()
            written["vtkhdf_surface"] = write_surface_vtkhdf(
                out / "surface.vtkhdf", ship.vertices, ship.faces, ship.face_part, ship.part_names,
                times, outer, time_units=units)
        if "json" in formats:
            with atomic_path(out / "thermal_summary.json") as tmp:
                tmp.write_text(json.dumps(self.summary(), indent=2, default=_json_default))
            written["summary_json"] = out / "thermal_summary.json"
        return written

    def where(self) -> str:
        """``" — season, date, lat N lon E"`` for picture titles (what is known)."""
        bits = [str(self.meta[k]) for k in ("season", "date") if self.meta.get(k)]
        env = self.environment
        if env is not None and hasattr(env, "latitude"):
            bits.append(f"{env.latitude:.2f} N {env.longitude:.2f} E")
        return (" — " + ", ".join(bits)) if bits else ""

    def face_temperature_at(self, hour: float) -> np.ndarray:
        """Outer-surface temperature per triangle at a local hour (linear in time) [K]."""
        if self.record is not None:
            return self.record.face_temperature_at(hour * HOUR)
        t = self.results.times / HOUR
        tf = self.outer_face_temperature()
        k = int(np.clip(np.searchsorted(t, hour) - 1, 0, len(t) - 2))
        w = float(np.clip((hour - t[k]) / (t[k + 1] - t[k]), 0.0, 1.0))
        return (1 - w) * tf[k] + w * tf[k + 1]


def _clock(hour: float) -> str:
    return f"{int(hour):02d}:{int(round(60 * (hour % 1))):02d}"


def _json_default(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def plot_part_means(part_means: pd.DataFrame, path, title: str = "", figures=None) -> Path:
    """PNG of the 24 h part-mean curves with air and sea temperature: every curve its own
    colour-blind-safe colour and dash pattern (:data:`shipthermal.figures.PART_LINE_STYLES`;
    other parts take the remaining :data:`~shipthermal.figures.LINE_STYLES`)."""
    # lazy: matplotlib takes a second to import, and the Agg backend is chosen only when
    # a picture is drawn
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5), dpi=110)
    labels = {"temp_air": "air", "temp_sea": "sea (bulk)", "temp_sea_skin": "sea skin",
              "hull": "hull (dry)",
              "hull_wetted": "hull (wetted)"}
    spare = iter(LINE_STYLES[1:] * 3)
    for col in part_means.columns:
        colour, ls, lw = PART_LINE_STYLES.get(col) or (*next(spare), 1.6)
        ax.plot(part_means.index, part_means[col], color=colour, ls=ls, lw=lw,
                label=labels.get(col, col))
    end = max(24, int(np.ceil(float(part_means.index.max()) / 24.0)) * 24)
    ax.set_xlabel("local time [h]" if end == 24 else "hours since local midnight of the "
                  "first recorded day [h]")
    ax.set_ylabel("temperature [K]")
    ax.set_xlim(0, end)
    ax.set_xticks(range(0, end + 1, 3 if end == 24 else (6 if end <= 96 else 24)))
    ax.grid(alpha=0.3)
    ax.legend(ncol=3, fontsize=8)
    ax.set_title(title, fontsize=10)
    path = Path(path)
    save_figure(fig, path, figures, bbox_inches="tight")
    plt.close(fig)
    return path


def concat_energy(parts) -> EnergyLog:
    """The energy logs of consecutive stretches of a run as one log."""
    if not parts:
        return EnergyLog.from_lists({k: [] for k in EnergyLog.FIELDS})
    return EnergyLog(*[np.concatenate([getattr(p, k) for p in parts]) for k in EnergyLog.FIELDS])
