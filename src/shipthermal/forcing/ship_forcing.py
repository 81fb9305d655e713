"""The forcing of a ship, built: :class:`ShipForcing` holds the per-face tables of one
design day or a weather record and serves them to the solver as boundary conditions
(:meth:`ShipForcing.conditions`, each ``f(t)`` interpolating the tables), the face-to-face
long-wave exchange (:meth:`ShipForcing.radiative_exchange`) and a summary per part.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.sparse as sp

from ..conditions import Convection, ConvectionLaw, SurfaceBalance, law_h
from ..environment import convection as conv
from ..units import DAY, SIGMA
from .convection import AirFaces
from .tables import PeriodicTable, RecordTable
from .tracing import TracedShip

@dataclass(eq=False)
class ShipForcing:
    """Precomputed per-face forcing of a ship for one periodic design day.

    Build with :func:`~shipthermal.forcing.build.build_ship_forcing`. All tables are
    indexed by table time (rows) and by face in ``graph.patch_faces(patch)`` order
    (columns).

    Attributes
    ----------
    times : (n,) float
        Table times, seconds after local midnight in [0, 86400) [s].
    table : PeriodicTable or RecordTable
        The interpolator (t folded modulo 86 400 s for a design day; over the whole
        record, not folded, for non-periodic weather).
    outer_bfaces : (K,) int
        Boundary faces of the outer patches (increasing); ``traced.faces[c]`` is the
        triangle of ``outer_bfaces[c]``.
    traced : TracedShip
        Geometry, tracer, view factors, lit-fraction cache.
    absorptivity, emissivity : dict
        Per part [-].
    alpha, epsilon : (K,) float
        Per outer face [-].
    temp_air, longwave_down, sea_longwave_up, temp_sea, h_water : (n,) float
        Scalar series at the table times [K], [W m-2], [W m-2], [K], [W m-2 K-1].
    convection_model : str or dict
        The exterior convection model of the air faces as chosen (a name, or names per
        part); ``convection_models`` gives the model of every part.
    convection_models : dict
        Part → model name (air parts).
    seconds : dict
        Wall time of each stage [s].
    """

    times: np.ndarray
    table: PeriodicTable | RecordTable
    outer_bfaces: np.ndarray
    outer_part: np.ndarray
    outer_is_air: np.ndarray
    traced: TracedShip
    part_names: tuple
    absorptivity: dict
    emissivity: dict
    alpha: np.ndarray
    epsilon: np.ndarray
    temp_air: np.ndarray
    longwave_down: np.ndarray
    sea_longwave_up: np.ndarray
    temp_sea: np.ndarray
    h_water: np.ndarray
    compartment_temperature: dict
    patches: dict
    _sw: dict          # patch -> (n, m) absorbed short-wave (air patches)
    _h: dict           # patch -> (n, m) convection coefficient: forced part (air patches,
                       # with the law of :meth:`convection_law`), the whole (inner patches)
    _lit: np.ndarray   # (n, k) lit fraction of the receivers
    inner_bfaces: np.ndarray
    unforced_patches: tuple
    sun_ship: np.ndarray
    convection_model: str | dict = conv.DEFAULT_CONVECTION_MODEL
    seconds: dict = field(default_factory=dict)
    _est: dict = field(default_factory=dict)   # patch -> (n, m) quasi-steady T_s (air)
    air_faces: AirFaces | None = None
    convection_models: dict = field(default_factory=dict)
    convection_roughness: str | dict | None = None

    # ---- geometry and view factors per outer face -----------------------------------
    @property
    def F_sky(self) -> np.ndarray:
        """Sky view factor per outer face [-]."""
        return self.traced.view.F_sky

    @property
    def F_sea(self) -> np.ndarray:
        """Sea view factor per outer face [-]."""
        return self.traced.view.F_sea

    @property
    def F_ship(self) -> np.ndarray:
        """View factor to other ship faces per outer face [-]."""
        return np.asarray(self.traced.view.F_faces.sum(axis=1)).ravel()

    @property
    def n_rays(self) -> dict:
        """Rays traced: sun and view factors."""
        return dict(self.traced.n_rays)

    # ---- time series -----------------------------------------------------------------
    def _column_values(self, tables: dict, t: float, kind: str) -> np.ndarray:
        out = np.zeros(len(self.outer_bfaces))
        for name, p in self.patches.items():
            if p.kind == kind and name in tables:
                out[p.cols] = self.table(tables[name], t)
        return out

    def absorbed_shortwave(self, t: float) -> np.ndarray:
        """Absorbed short-wave of every outer face at ``t`` [W m-2] (0 on wetted faces),
        in ``outer_bfaces`` order."""
        return self._column_values(self._sw, t, "air")

    @functools.cached_property
    def _lit_rows(self) -> np.ndarray:
        """(n,) bool: some face absorbs short-wave at the table time."""
        lit = np.zeros(len(self.times), bool)
        for tab in self._sw.values():
            lit |= np.any(tab > 0.0, axis=1)
        return lit

    def dark(self, start: float, end: float) -> bool:
        """True when no face absorbs short-wave anywhere in ``[start, end]`` [s].

        A table row with short-wave reaches, through the linear interpolation, the open
        interval from the row before it to the row after it (on a periodic table folded
        over the period; the end rows of a record reach beyond it): the interval is dark
        when it meets none of those.
        """
        lit = self._lit_rows
        if not lit.any():
            return True
        tt = self.times
        if isinstance(self.table, PeriodicTable):
            period = self.table.period
            before = np.r_[tt[-1] - period, tt[:-1]][lit]
            after = np.r_[tt[1:], tt[0] + period][lit]
            # the first shift k·period with after + kP > start; it reaches the interval
            # when also before + kP < end
            k = np.floor((start - after) / period) + 1.0
            return not bool(np.any(before + k * period < end))
        before = np.r_[-np.inf, tt[:-1]][lit]
        after = np.r_[tt[1:], np.inf][lit]
        return not bool(np.any((before < end) & (after > start)))

    def lit_fraction(self, t: float) -> np.ndarray:
        """Lit fraction of the sun-receiving faces (``traced.receivers``) at ``t`` [-],
        linear in time between table times."""
        return self.table(self._lit, t)

    # ---- solver conditions -------------------------------------------------------------
    def conditions(self, with_exchange: bool = True) -> dict:
        """Boundary conditions ``{patch: SurfaceBalance | Convection}`` for the solver.

        Parameters
        ----------
        with_exchange : bool
            True when the model also gets :meth:`radiative_exchange` (the surface balance
            then carries only the environment share of each face's emission, see the
            notes of :mod:`shipthermal.forcing`); False to replace the ship faces a face sees
            by black bodies at the air temperature.

        Returns
        -------
        dict
            Values are numbers, per-face arrays or ``f(t)`` returning per-face arrays in
            ``graph.patch_faces(patch)`` order (t in seconds after local midnight of day 0;
            folded modulo 86 400 s).
        """
        out = {}
        tab = self.table
        t_air = self.temp_air
        lw_down = self.longwave_down
        lw_sea = self.sea_longwave_up
        f_ship_all = self.F_ship
        for name, p in self.patches.items():
            if p.kind == "air":
                c = p.cols
                f_sky = self.F_sky[c].copy()
                f_sea = self.F_sea[c].copy()
                eps = self.epsilon[c].copy()
                if with_exchange:
                    env = f_sky + f_sea
                    inv = np.divide(1.0, env, out=np.zeros_like(env), where=env > 0)
                    w_sky, w_sea, w_ship = f_sky * inv, f_sea * inv, None
                    eps_eff = eps * env
                else:
                    w_sky, w_sea, w_ship = f_sky, f_sea, f_ship_all[c].copy()
                    eps_eff = eps

                def longwave_in(t, w_sky=w_sky, w_sea=w_sea, w_ship=w_ship):
                    lw = w_sky * tab(lw_down, t) + w_sea * tab(lw_sea, t)
                    if w_ship is not None:
                        lw = lw + w_ship * (SIGMA * tab(t_air, t) ** 4)
                    return lw

                sw = self._sw[name]
                hh = self._h[name]
                out[name] = SurfaceBalance(
                    absorbed_shortwave=lambda t, sw=sw: tab(sw, t),
                    emissivity=eps_eff,
                    longwave_in=longwave_in,
                    h=lambda t, hh=hh: tab(hh, t),
                    temp_air=lambda t: tab(t_air, t),
                    law=self.convection_law(name))
            elif p.kind == "sea":
                out[name] = Convection(h=lambda t: tab(self.h_water, t),
                                       temp_fluid=lambda t: tab(self.temp_sea, t))
            else:
                hh = self._h[name]
                out[name] = Convection(h=lambda t, hh=hh: tab(hh, t),
                                       temp_fluid=float(self.compartment_temperature[p.part]))
        return out

    def _air_positions(self, patch: str) -> np.ndarray:
        """Positions among the air faces of an air patch's faces."""
        air = self.air_faces
        pos = np.full(len(self.outer_bfaces), -1)
        pos[air.cols] = np.arange(len(air.cols))
        return pos[self.patches[patch].cols]

    def _still_air_flow(self, pos) -> conv.ExteriorFlow:
        """The flow of the air faces at positions ``pos`` without wind (the law's natural
        part and its other terms need only their geometry)."""
        air = self.air_faces
        return conv.ExteriorFlow(normal_z=air.normals[pos, 2], wind_speed=0.0,
                                 length_flow=1.0, length_vertical=air.lengths.vertical[pos],
                                 length_horizontal=air.lengths.horizontal[pos],
                                 perimeter_over_area=air.convection.perimeter_over_area[pos],
                                 roughness=air.convection.roughness[pos])

    @functools.cached_property
    def _natural_groups(self) -> dict:
        """Film-dependent model name → its :class:`_NaturalRows` over the air patches that
        use it."""
        air = self.air_faces
        groups: dict = {}
        for name, p in self.patches.items():
            if p.kind != "air":
                continue
            pos = self._air_positions(name)
            model = air.convection.models[air.convection.model_index[pos[0]]]
            if model.film_dependent:
                groups.setdefault(model.name, (model, []))[1].append(name)
        return {key: _NaturalRows(self, model, names) for key, (model, names) in groups.items()}

    def convection_law(self, patch: str) -> ConvectionLaw:
        """The law of the surface temperature of an air patch's coefficient
        (:class:`~shipthermal.conditions.ConvectionLaw`, with the forced part tabulated):
        natural convection of the part's model, its blending and roughness multiplier.
        Flat-plate models take the air properties at the film temperature of the
        quasi-steady estimate at the table times, their law's coefficients interpolated
        between them like every table; the others have none."""
        air = self.air_faces
        pos = self._air_positions(patch)
        model = air.convection.models[air.convection.model_index[pos[0]]]
        flow = self._still_air_flow(pos)
        nz = flow.normal_z
        if model.film_dependent:
            natural = self._natural_groups[model.name].patch(patch)
        else:
            natural = np.ascontiguousarray(model.terms(np.full(len(pos), 300.0), flow)[1].natural)
        law = model.terms(np.full(len(pos), 300.0), flow)[1]
        return ConvectionLaw(natural=natural, blend=np.broadcast_to(law.blend, nz.shape).copy(),
                             multiplier=np.broadcast_to(law.multiplier, nz.shape).copy(),
                             normal_z=nz.copy())

    def convection_coefficient(self, patch: str, t: float, temp_surface=None) -> np.ndarray:
        """The coefficient of an air patch's faces at ``t`` [W m-2 K-1]: the law at
        ``temp_surface`` [K] (default the quasi-steady estimate)."""
        return self._coefficient(patch, self.convection_law(patch), t, temp_surface)

    def _coefficient(self, patch: str, law: ConvectionLaw, t: float,
                     temp_surface=None) -> np.ndarray:
        """:meth:`convection_coefficient` with the patch's law given (building it
        evaluates the model's law at 300 K: not once per time of a series)."""
        nat = law.natural(t) if callable(law.natural) else law.natural
        ts = self.table(self._est[patch], t) if temp_surface is None else temp_surface
        return law_h(self.table(self._h[patch], t),
                     ConvectionLaw(nat, law.blend, law.multiplier, law.normal_z),
                     np.asarray(ts, dtype=float) - self.table(self.temp_air, t))

    def radiative_exchange(self):
        """Face-to-face long-wave exchange for ``RadiativeExchange(bfaces, area_exchange)``.

        Returns
        -------
        bfaces : (k,) int
            Boundary-face indices of the outer faces that see at least one other face.
        area_exchange : scipy.sparse.csr_matrix (k, k)
            Symmetric, entries ``A_i ε_i ε_j F_ij`` [m²] (reciprocity imposed on the traced
            F by :func:`~shipthermal.raytrace.symmetrize`, then averaged with its
            transpose so it is symmetric to the last bit).
        """
        F = self.traced.view.F_faces.tocsr()
        A = self.traced.view.areas
        R = sp.diags(A * self.epsilon) @ F @ sp.diags(self.epsilon)
        R = (0.5 * (R + R.T)).tocsr()
        R.eliminate_zeros()
        deg = np.asarray((R != 0).sum(axis=1)).ravel()
        keep = np.flatnonzero(deg > 0)
        R = R[keep][:, keep].tocsr()
        R.sum_duplicates()
        return self.outer_bfaces[keep].copy(), R

    # ---- reporting ---------------------------------------------------------------------
    def summary(self) -> pd.DataFrame:
        """Forcing per part: area-weighted view factors, solar and convection figures.

        Columns: ``medium``, ``faces``, ``area`` [m²], ``alpha``, ``epsilon`` [-],
        ``F_sky``, ``F_sea``, ``F_ship`` (area means) [-], ``sw_peak_mean`` (largest
        area-mean absorbed short-wave over the day) [W m-2], ``sw_peak_face`` (largest on
        any face) [W m-2], ``sw_time_of_peak`` [h], ``sw_daily_mean`` [W m-2], ``h_mean``
        (time and area mean, outer) [W m-2 K-1], ``h_inner_mean`` [W m-2 K-1],
        ``temp_compartment`` [K]. ``DataFrame.attrs`` holds rays traced and timings.
        """
        A = self.traced.areas
        h_air = self._air_coefficients_at_table_times()
        rows = []
        for part in self.part_names:
            outer = [p for p in self.patches.values()
                     if p.part == part and p.kind in ("air", "sea")]
            inner = [p for p in self.patches.values() if p.part == part and p.kind == "inner"]
            if not outer and not inner:
                continue
            row = dict(part=part, faces=0, area=0.0)
            if outer:
                cols = np.concatenate([p.cols for p in outer])
                a = A[cols]
                area = a.sum()
                row.update(medium=outer[0].kind, faces=len(cols), area=float(area),
                           alpha=self.absorptivity[part], epsilon=self.emissivity[part],
                           F_sky=float(a @ self.F_sky[cols] / area),
                           F_sea=float(a @ self.F_sea[cols] / area),
                           F_ship=float(a @ self.F_ship[cols] / area))
                air = [p for p in outer if p.kind == "air"]
                if air:
                    sw = np.concatenate([self._sw[p.name] for p in air], axis=1).astype(float)
                    hh = np.concatenate([h_air[p.name] for p in air], axis=1)
                    ca = np.concatenate([p.cols for p in air])
                    aa = A[ca]
                    mean_t = sw @ aa / aa.sum()
                    k = int(np.argmax(mean_t))
                    row.update(sw_peak_mean=float(mean_t[k]), sw_peak_face=float(sw.max()),
                               sw_time_of_peak=float(self.times[k] / 3600.0),
                               sw_daily_mean=float(self._daily_mean(mean_t)),
                               h_mean=float(self._daily_mean(hh @ aa / aa.sum())))
                else:
                    row.update(sw_peak_mean=0.0, sw_peak_face=0.0, sw_time_of_peak=np.nan,
                               sw_daily_mean=0.0,
                               h_mean=float(self._daily_mean(self.h_water)))
            if inner:
                hh = np.concatenate([self._h[p.name] for p in inner], axis=1).astype(float)
                row["h_inner_mean"] = float(self._daily_mean(hh.mean(axis=1)))
                row["temp_compartment"] = float(self.compartment_temperature[part])
            rows.append(row)
        df = pd.DataFrame(rows).set_index("part")
        df.attrs["n_rays"] = self.n_rays
        df.attrs["seconds"] = dict(self.seconds)
        df.attrs["n_times"] = len(self.times)
        df.attrs["unforced_patches"] = self.unforced_patches
        return df

    def _air_coefficients_at_table_times(self) -> dict:
        """Air patch → its coefficients at every table time, (n_times, faces) [W m-2 K-1],
        at the quasi-steady estimate. Each patch's law is built once (building it evaluates
        the model's law at 300 K) and the table times are taken in turn with every patch at
        each, so the natural law's rows (:class:`_NaturalRows`, which keeps a few) are
        computed once per time: asked patch by patch and law by law, the summary took 5.4 s
        of writing the default ship's day under the profiler, and 4.0 s of a two-day
        record's at 0.5 m when the rows were computed once per part and time."""
        names = [name for name, p in self.patches.items() if p.kind == "air"]
        laws = {name: self.convection_law(name) for name in names}
        at = [[self._coefficient(name, laws[name], t) for name in names] for t in self.times]
        return {name: np.stack([row[k] for row in at]) for k, name in enumerate(names)}

    def _daily_mean(self, series) -> float:
        """Time mean over the periodic day (or the whole record) of a series at the table
        times (trapezoid)."""
        if isinstance(self.table, RecordTable):
            y = np.asarray(series, dtype=float)
            return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(self.times))
                         / self.table.period)
        t = np.concatenate([self.times, [self.times[0] + DAY]])
        y = np.concatenate([series, series[:1]])
        return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)) / DAY)

    def report(self) -> str:
        """The summary as text (one line per part) with ray counts and timings."""
        df = self.summary()
        with pd.option_context("display.width", 200, "display.max_columns", 30,
                               "display.float_format", "{:.3f}".format):
            text = df.to_string()
        rays = ", ".join(f"{k} {v:,}" for k, v in self.n_rays.items())
        secs = ", ".join(f"{k} {v:.2f} s" for k, v in self.seconds.items())
        return f"{text}\nrays traced: {rays}\ntimings: {secs}"


class _NaturalRows:
    """The natural part of a film-dependent model's law over all the air patches that use
    it, at the film temperature of the quasi-steady estimate of each table time, for the
    solver's steps.

    One evaluation of the law per table time for all those faces (not one per patch: at
    2 m a patch has a few hundred faces and the law's ~60 array operations cost more in
    calls than in arithmetic), kept for the few table times the solver is between; the
    value at a step's time interpolated once for all of them. The faces are stored patch
    after patch, so a patch's rows are a contiguous view."""

    _KEEP_ROWS = 4

    def __init__(self, forcing: ShipForcing, model, patches: list):
        pos = [forcing._air_positions(name) for name in patches]
        bounds = np.cumsum([0] + [len(q) for q in pos])
        self._slices = {name: slice(int(a), int(b))
                        for name, a, b in zip(patches, bounds[:-1], bounds[1:])}
        self._model = model
        self._flow = forcing._still_air_flow(np.concatenate(pos))
        # the estimate's columns of every patch, in this group's face order
        self._est = [forcing._est[name] for name in patches]
        self._table, self._temp_air = forcing.table, forcing.temp_air
        self._rows: dict = {}
        self._last = (None, None)

    def _at_row(self, i: int) -> np.ndarray:
        if i not in self._rows:
            if len(self._rows) >= self._KEEP_ROWS:
                self._rows.pop(next(iter(self._rows)))
            est = np.concatenate([e[i] for e in self._est]).astype(float)
            film = 0.5 * (est + float(self._temp_air[i]))
            self._rows[i] = self._model.natural_law(film, self._flow)
        return self._rows[i]

    def at(self, t: float) -> np.ndarray:
        """The law's natural part of all the group's faces at ``t``, linear in time between
        table times (the value of the last ``t`` asked is kept: every patch asks it)."""
        if self._last[0] != t:
            i, j, w = self._table.weights(t)
            value = (self._at_row(i) if w == 0.0
                     else (1.0 - w) * self._at_row(i) + w * self._at_row(j))
            value.flags.writeable = False   # shared by the patches' views
            self._last = (t, value)
        return self._last[1]

    def patch(self, name: str):
        """``f(t)``: the natural part of one patch's faces (a view of :meth:`at`)."""
        cols = self._slices[name]
        return lambda t: self.at(t)[cols]
