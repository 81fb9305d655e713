"""The model a calibration evaluates: one :class:`_Case` per scenario (ship, shell graph and
ray tracing built once, warm-started diurnal runs), run at the coarse
:data:`CALIBRATION_SETTINGS`."""

from __future__ import annotations

import time as _time
from pathlib import Path

import numpy as np
import pandas as pd

from ...diurnal import part_groups
from ...errors import InputError, require
from ..scenario import default_scenario, load_scenario
from ..thermal import run_scenario_thermal


#: Scenario changes of every calibration run: coarse mesh, fewer rays, 900 s steps (the
#: deck means move by < 0.05 K against 300 s steps on the same mesh), looser spin-up
#: tolerance (finite-difference steps change the fitted temperatures by ≳ 0.5 K).
CALIBRATION_SETTINGS = {"ship.edge_length": 4.0, "solver.rays_per_face": 64,
                        "solver.samples_per_face": 8, "solver.time_step": 900.0,
                        "solver.spinup_tolerance": 0.02}


# --------------------------------------------------------------------------- model ------
class _Case:
    """One scenario: ship, graph and ray tracing built once; warm-started evaluations."""

    def __init__(self, name, scenario, rows: pd.DataFrame, progress=False):
        self.name = name
        self.scenario = scenario
        self.rows = rows
        self.ship = scenario.ship()
        self.parts = set(part_groups(self.ship.part_names).values())
        self.traced = None
        self.graph = None
        self.state = None
        self.memo: dict = {}
        self.runs = 0
        self.seconds = 0.0
        self.days: list = []
        self.progress = progress
        centres = self.ship.vertices[self.ship.faces].mean(axis=1)
        self.face_of_row = {}
        for idx, r in rows.iterrows():
            tgt = r["target"]
            if tgt.startswith("point:"):
                p = np.array([float(v) for v in tgt[6:].replace(";", " ").replace(",", " ").split()])
                d = np.linalg.norm(centres - p, axis=1)
                k = int(np.argmin(d))
                require(d[k] < 3.0 * float(scenario.ship.edge_length or 4.0), f"measurements line "
                        f"{r['line']}: target", tgt, "must lie on the ship's surface",
                        f"nearest surface face is {d[k]:.1f} m away")
                self.face_of_row[idx] = k
            else:
                require(tgt in self.parts, f"measurements line {r['line']}: target", tgt,
                        f"must be a part of this ship ({', '.join(sorted(self.parts))}) "
                        "or 'point:x y z'")

    def run(self, changes: dict):
        """The full diurnal result with these changes (warm-started, ray tracing reused)."""
        sc = self.scenario.updated(changes) if changes else self.scenario
        return run_scenario_thermal(sc, ship=self.ship, progress=False, traced=self.traced,
                                    graph=self.graph, initial_state=self.state)

    def predict(self, changes: dict) -> np.ndarray:
        key = tuple(sorted((k, round(float(v), 10)) for k, v in changes.items()))
        if key in self.memo:
            return self.memo[key]

        t0 = _time.perf_counter()
        sc = self.scenario.updated(changes) if changes else self.scenario
        res = run_scenario_thermal(sc, ship=self.ship, progress=False, traced=self.traced,
                                   graph=self.graph, initial_state=self.state)
        self.seconds += _time.perf_counter() - t0
        self.runs += 1
        self.days.append(int(res.days))
        if self.traced is None:
            self.traced = getattr(res.forcing, "traced", None)
            self.graph = res.graph
        self.state = res.results.cell_temperature[0]
        hmax = float(res.part_means.index.max())
        out = np.empty(len(self.rows))
        for j, (idx, r) in enumerate(self.rows.iterrows()):
            require(r["hour"] <= hmax + 1e-9, f"measurements line {r['line']}: time",
                    r["hour"], f"must lie within the simulated day(s) (0 … {hmax:g} h)")
            if idx in self.face_of_row:
                out[j] = res.face_temperature_at(r["hour"])[self.face_of_row[idx]]
            else:
                out[j] = res.part_mean_at(r["target"], r["hour"])
        self.memo[key] = out
        return out


#: settings where the larger value is the coarser (the others: the smaller)
_COARSER_IS_LARGER = ("ship.edge_length", "solver.time_step", "solver.spinup_tolerance")


def _coarsest(scenario, tweaks: dict) -> dict:
    """The calibration setting, but never finer than the scenario's own (a scenario that is
    already coarser keeps its values)."""
    out = {}
    for key, value in tweaks.items():
        own = _default_value(scenario, key)
        if own is None:
            out[key] = value
        elif key in _COARSER_IS_LARGER:
            out[key] = max(own, value)
        else:
            out[key] = min(own, value)
        if isinstance(value, int):
            out[key] = int(out[key])
    step = out.get("solver.time_step")
    interval = _default_value(scenario, "time.output_interval")
    if step is not None and interval is not None and abs(interval / step - round(interval / step)) > 1e-9:
        out.pop("solver.time_step")            # must divide the recording interval
    return out


def _default_value(scenario, key: str) -> float | None:
    """The scenario's current value of a dotted key (None when it has no plain number)."""
    if key.startswith("ship.solar_absorptivity."):
        return float(scenario.solar_absorptivity(key.rsplit(".", 1)[1]))
    if key.startswith("ship.longwave_emissivity."):
        return float(scenario.longwave_emissivity(key.rsplit(".", 1)[1]))
    node = scenario.to_dict()
    for p in key.split("."):
        if not isinstance(node, dict) or p not in node:
            return None
        node = node[p]
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        return None
    return float(node)


def build_cases(meas: pd.DataFrame, unknowns: list, scenarios: dict | None, tweaks: dict,
                base_dir) -> dict:
    """case → :class:`_Case` of every case of the measurements, at the calibration setting
    ``tweaks`` (never finer than the scenario's own). A case not in ``scenarios`` is loaded
    by name ('summer', 'winter') or as a scenario TOML path relative to ``base_dir``; every
    case-scoped unknown must name one of them."""
    cases = {}
    for name in dict.fromkeys(meas["case"]):
        sc = (scenarios or {}).get(name)
        if sc is None:
            if name in ("summer", "winter"):
                sc = default_scenario(name)
            else:
                p = Path(name)
                p = p if p.is_absolute() else Path(base_dir) / p
                require(p.is_file(), "measurements: case", name, "must be 'summer', 'winter' or "
                        "a scenario TOML file (relative to the CSV)")
                sc = load_scenario(p)
        sc = sc.updated(_coarsest(sc, tweaks)) if tweaks else sc
        cases[name] = _Case(name, sc, meas[meas["case"] == name], progress=False)
    for u in unknowns:
        require(u.case is None or u.case in cases, "--unknown", u.label,
                f"names a case without measurements (cases: {', '.join(cases)})")
    return cases


def start_values(unknowns: list, cases: dict) -> tuple:
    """``(starts, defaults)`` of the unknowns: each one's value in its (first) case's
    scenario, and where the fit starts (the given start, else that value within the
    bounds); a key that is no number, or a bound the scenario refuses, is an error."""
    starts, defaults = [], []
    for u in unknowns:
        targets = [cases[u.case]] if u.case else list(cases.values())
        d = _default_value(targets[0].scenario, u.key)
        if d is None:
            raise InputError("--unknown", u.label, "must be a numeric scenario key",
                             "see docs/SCENARIO.md, e.g. weather.wind_speed_offset, "
                             "ship.solar_absorptivity.deck, weather.cloud_cover_offset")
        for c in targets:
            for v in (u.lower, u.upper):
                try:
                    c.scenario.updated({u.key: v})
                except InputError as exc:
                    raise InputError("--unknown", u.label, f"bound {v:g} is not accepted by the "
                                     f"scenario ({exc.field} {exc.allowed})")
        defaults.append(d)
        starts.append(u.start if u.start is not None else min(max(d, u.lower), u.upper))
    return starts, defaults


def case_changes(unknowns: list, case: str, x) -> dict:
    """The scenario changes of ``case`` for the unknowns' values ``x`` (its own and the
    unscoped unknowns)."""
    return {u.key: float(v) for u, v in zip(unknowns, x) if u.case in (None, case)}


def predict_rows(cases: dict, unknowns: list, x, n_rows: int) -> np.ndarray:
    """The model temperature of every measurement row for the unknowns' values ``x``."""
    out = np.empty(n_rows)
    for name, c in cases.items():
        out[c.rows.index.to_numpy()] = c.predict(case_changes(unknowns, name, x))
    return out
