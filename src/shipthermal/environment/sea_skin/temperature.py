"""The sea's skin temperature over a time series: bulk fluxes and warm layer coupled until
they agree, the cool skin from the fluxes.

References in brackets: :mod:`shipthermal.environment.sea_skin`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from shipthermal.errors import InputError, check_range, require

from .bulk import BulkFluxes, bulk_fluxes
from .coare_warm import coare_warm_layer_series
from .constants import _DT_PROBE, COARE_ALBEDO, STANDARD_PRESSURE, WARM_LAYER_DEPTH, WARM_LAYER_NU
from .thermodynamics import normal_gravity
from .zeng_beljaars import warm_layer_series, warm_layer_solar_fraction

WARM_LAYER_MODELS = ("fairall_coare", "zeng_beljaars")
"""The warm-layer models of :func:`sea_skin_temperature` by name."""
DEFAULT_WARM_LAYER = "fairall_coare"
"""The warm layer when none is named (why: :mod:`shipthermal.environment.sea_skin`)."""


@dataclass(frozen=True, eq=False)
class SeaSkin:
    """Skin temperature over a time series (:func:`sea_skin_temperature`).

    Attributes
    ----------
    seconds : numpy.ndarray
        Sample times [s].
    temp_bulk, temp_skin : numpy.ndarray
        Bulk SST (at ``depth``) and skin temperature [K];
        ``temp_skin = temp_bulk + delta_warm − delta_cool``.
    delta_warm, delta_cool : numpy.ndarray
        ΔT_warm ≥ 0, the warming between the bulk's depth and the surface, and ΔT_cool [K].
    fluxes : BulkFluxes
        Surface fluxes at the skin temperature.
    heat_flux_warm_layer : numpy.ndarray
        Heat flux into the warm layer [W m-2]: the non-solar flux into the sea plus the
        solar flux the layer keeps (Z&B: above d; COARE: f_x(D) of it).
    periodic : bool
    spinup_days : int
        Periodic forcing: days integrated (Z&B: until the warm layer repeated; COARE: 1,
        from its midnight reset); 0 for a record.
    day_change : float
        Periodic forcing [K]: Z&B: ΔT_warm at the end of the last day minus at its start;
        COARE: the ΔT_warm left at local midnight, which the reset discards.
    coupling_passes : int
        Passes of the flux / warm-layer coupling until it settled.
    warm_layer : str
        The warm-layer model (:data:`WARM_LAYER_MODELS`), or ``'none'``.
    layer_warming, layer_depth : numpy.ndarray
        The whole layer's warming [K] and depth [m]: COARE's ΔT and D (``delta_warm =
        ΔT min(1, depth / D)``); Z&B's ΔT_warm and d.
    """

    seconds: np.ndarray
    temp_bulk: np.ndarray
    temp_skin: np.ndarray
    delta_warm: np.ndarray
    delta_cool: np.ndarray
    fluxes: BulkFluxes
    heat_flux_warm_layer: np.ndarray
    periodic: bool
    spinup_days: int
    day_change: float
    coupling_passes: int
    warm_layer: str
    layer_warming: np.ndarray
    layer_depth: np.ndarray


def warm_layer_model(value) -> str:
    """The warm-layer model's name from a name or a switch (True: :data:`DEFAULT_WARM_LAYER`,
    False or None: ``'none'``)."""
    if value is True:
        return DEFAULT_WARM_LAYER
    if value is False or value is None:
        return "none"
    require(value in WARM_LAYER_MODELS + ("none",), "warm_layer", value,
            "must be " + ", ".join(repr(m) for m in WARM_LAYER_MODELS + ("none",))
            + " (or a bool)")
    return str(value)


def sea_skin_temperature(seconds, temp_bulk, wind_speed, temp_air, relative_humidity,
                         shortwave_down, longwave_down, albedo=COARE_ALBEDO,
                         pressure=STANDARD_PRESSURE, *, period=None, latitude=45.0,
                         height_wind=10.0, height_temp=2.0, depth=WARM_LAYER_DEPTH,
                         nu=WARM_LAYER_NU, warm_layer=DEFAULT_WARM_LAYER, solar_hours=None,
                         cool_skin_on=True, initial_warm=0.0, tolerance=1e-4, max_days=60,
                         max_passes=30) -> SeaSkin:
    """Skin temperature of the sea over a time series: bulk fluxes, cool skin, warm layer.

    Parameters
    ----------
    seconds : array_like
        Increasing sample times [s] (a step of ≤ 10 min keeps the time error of the warm
        layer to a few hundredths of a kelvin or less; see the tests).
    temp_bulk : array_like
        Bulk sea temperature at ``depth`` [K].
    wind_speed : array_like
        True wind at ``height_wind`` [m s-1].
    temp_air : array_like
        Air temperature at ``height_temp`` [K].
    relative_humidity : array_like
        [%] (at ``height_temp``).
    shortwave_down : array_like
        Downwelling solar irradiance on the horizontal (global horizontal) [W m-2].
    longwave_down : array_like
        Downwelling long-wave [W m-2].
    albedo : array_like
        Sea albedo for ``shortwave_down`` [-].
    pressure : array_like
        Surface pressure [Pa].
    period : float, optional
        The series is one period of a repeating cycle (a design day, ``seconds`` covering
        ``[t0, t0 + period)``): Z&B is spun up over repeated periods until it repeats to
        ``tolerance``; COARE integrates the day once from its midnight reset. None: a
        record, integrated from its first sample (Z&B from ``initial_warm``; COARE by the
        reference's rule for a first day, :func:`coare_warm_layer`).
    latitude : float
        [deg].
    height_wind, height_temp : float
        Measurement heights [m] (ASSUMPTION for weather records without them: 10 m wind,
        2 m screen-height air temperature and humidity).
    depth : float
        Depth of ``temp_bulk`` [m]: Z&B's layer base d; for COARE, where its linear profile
        is read.
    nu : float
        Z&B's profile exponent ν [-].
    warm_layer : {'fairall_coare', 'zeng_beljaars', 'none'} or bool
        The warm-layer model (True: the default, ``'fairall_coare'``; False or ``'none'``:
        ΔT_warm = 0).
    solar_hours : array_like, optional
        Local solar time of the samples [h] (COARE's midnight reset); default: the
        samples' own clock, ``seconds / 3600`` modulo 24 (seconds after local solar
        midnight).
    cool_skin_on : bool
        Switch the cool skin off (ΔT_cool = 0).
    initial_warm : float
        Z&B, record: ΔT_warm at the first sample [K].
    tolerance : float
        [K]: end-of-day repetition of a spun-up periodic day (Z&B), and the change between
        two passes of the flux / warm-layer coupling.
    max_days, max_passes : int
        Caps of the spin-up and of the coupling.

    Returns
    -------
    SeaSkin

    Notes
    -----
    The bulk fluxes depend on the skin temperature and the warm layer on the fluxes: the
    coupling is iterated — fluxes (:func:`bulk_fluxes`, vectorised over all samples) at
    ``T_bulk + ΔT_warm``, then the warm layer over the series — until ΔT_warm changes by
    less than ``tolerance``. Z&B (:func:`warm_layer_series`) with the layer's heat flux
    ``Q = −(H_s + H_l + LW_net) + f_d(d) R_ns`` (:func:`warm_layer_solar_fraction`), u*_w
    and the flux's linearised response to ΔT_warm (the fluxes respond with ~20–40 W m-2
    K-1 against the layer's heat capacity ρ_w c_w d ν/(ν+1) = 2.8 MJ m-2 K-1); COARE
    (:func:`coare_warm_layer_series`) with ``Q_out = H_s + H_l + LW_net`` (no rain heat
    flux: the weather carries no rain), R_ns and the stress, both ends of each step
    evaluated with the warm layer at the step's start: the layer's feedback on the fluxes
    explicit, as in the reference code (which takes the fluxes of the step before), so that
    the morning onset (a threshold) depends only on the past and the passes settle; the
    forcing itself integrated to second order. All the fluxes are those of the skin over
    the warm layer (the reference's COARE 3.6 version takes its net long-wave from the bulk
    temperature without the warm layer: 6 W m-2 less loss per kelvin of warming).
    """
    model = warm_layer_model(warm_layer)
    f = _skin_forcing(seconds, temp_bulk, wind_speed, temp_air, relative_humidity,
                      shortwave_down, longwave_down, albedo, pressure, period=period,
                      latitude=latitude, height_wind=height_wind, height_temp=height_temp,
                      solar_hours=solar_hours, cool_skin_on=cool_skin_on)
    f_d = float(warm_layer_solar_fraction(depth))
    dtw = np.zeros(f.n)
    fl = f.fluxes_at(dtw)
    if model == "zeng_beljaars":
        c = _couple_zeng_beljaars(f, fl, f_d, depth, nu, initial_warm, tolerance, max_days,
                                  max_passes)
    elif model == "fairall_coare":
        c = _couple_coare(f, fl, depth, tolerance, max_passes)
    else:
        c = _Coupled(dtw, fl, fl.heat_flux_nonsolar + f_d * f.rns, np.zeros(f.n),
                     np.full(f.n, float(depth)), 0, 0, 0.0)
    return SeaSkin(seconds=f.t, temp_bulk=f.tb, temp_skin=f.tb + c.dtw - c.fl.delta_cool,
                   delta_warm=c.dtw, delta_cool=c.fl.delta_cool, fluxes=c.fl,
                   heat_flux_warm_layer=c.q_warm, periodic=f.period is not None,
                   spinup_days=c.days, day_change=c.change, coupling_passes=c.passes,
                   warm_layer=model, layer_warming=c.layer_dt, layer_depth=c.layer_d)


def _series_input(x, name, n):
    """An input broadcast to the ``n`` samples as floats; it must be finite."""
    a = np.broadcast_to(np.asarray(x, dtype=float), (n,)).astype(float)
    if not np.all(np.isfinite(a)):
        raise InputError(name, a, "must be finite")
    return a


@dataclass(frozen=True, eq=False)
class _SkinForcing:
    """The validated forcing of :func:`sea_skin_temperature` at its ``n`` samples."""

    t: np.ndarray               #: sample times [s]
    n: int
    tb: np.ndarray              #: bulk SST [K]
    u: np.ndarray               #: wind [m s-1]
    ta: np.ndarray              #: air temperature [K]
    rh: np.ndarray              #: relative humidity [%]
    rns: np.ndarray             #: net solar flux into the sea [W m-2]
    rl: np.ndarray              #: downwelling long-wave [W m-2]
    p: np.ndarray               #: pressure [Pa]
    hours: np.ndarray           #: local solar time [h, 0–24)
    period: float | None        #: [s]
    gravity: float              #: [m s-2]
    latitude: float
    height_wind: float
    height_temp: float
    cool_skin_on: bool

    def fluxes_at(self, dtw) -> BulkFluxes:
        """The bulk fluxes over the warm layer ``dtw`` [K] (the water at ``T_bulk + dtw``)."""
        return bulk_fluxes(self.tb + dtw, self.u, self.ta, self.rh, self.rns, self.rl, self.p,
                           height_wind=self.height_wind, height_temp=self.height_temp,
                           latitude=self.latitude, cool_skin_on=self.cool_skin_on)


def _skin_forcing(seconds, temp_bulk, wind_speed, temp_air, relative_humidity, shortwave_down,
                  longwave_down, albedo, pressure, *, period, latitude, height_wind,
                  height_temp, solar_hours, cool_skin_on) -> _SkinForcing:
    """The inputs of :func:`sea_skin_temperature` checked and broadcast to the samples."""
    t = np.asarray(seconds, dtype=float).ravel()
    n = t.size
    require(n >= 2 and bool(np.all(np.diff(t) > 0)), "seconds", t[:3].tolist(),
            "must hold >= 2 increasing times [s]")
    tb = _series_input(temp_bulk, "temp_bulk", n)
    check_range("temp_bulk", tb, 268.0, 315.0, "K")
    u = np.maximum(_series_input(wind_speed, "wind_speed", n), 0.0)
    ta = _series_input(temp_air, "temp_air", n)
    rh = np.clip(_series_input(relative_humidity, "relative_humidity", n), 1.0, 100.0)
    rs = np.maximum(_series_input(shortwave_down, "shortwave_down", n), 0.0)
    rl = _series_input(longwave_down, "longwave_down", n)
    alb = _series_input(albedo, "albedo", n)
    check_range("albedo", alb, 0.0, 1.0)
    p = _series_input(pressure, "pressure", n)
    hours = np.mod(t / 3600.0 if solar_hours is None
                   else _series_input(solar_hours, "solar_hours", n), 24.0)
    rns = (1.0 - alb) * rs
    if period is not None:
        period = float(period)
        require(period > t[-1] - t[0], "period", period,
                f"must exceed the span of the samples ({t[-1] - t[0]:g} s)")
    gravity = float(normal_gravity(latitude))
    return _SkinForcing(t=t, n=n, tb=tb, u=u, ta=ta, rh=rh, rns=rns, rl=rl, p=p, hours=hours,
                        period=period, gravity=gravity, latitude=latitude,
                        height_wind=height_wind, height_temp=height_temp,
                        cool_skin_on=cool_skin_on)


class _Coupled(NamedTuple):
    """The settled coupling of fluxes and warm layer (fields of :class:`SeaSkin`)."""

    dtw: np.ndarray             #: ΔT_warm [K]
    fl: BulkFluxes
    q_warm: np.ndarray          #: heat flux into the warm layer [W m-2]
    layer_dt: np.ndarray        #: the whole layer's warming [K]
    layer_d: np.ndarray         #: its depth [m]
    passes: int
    days: int
    change: float


def _couple_zeng_beljaars(f: _SkinForcing, fl: BulkFluxes, f_d, depth, nu, initial_warm,
                          tolerance, max_days, max_passes) -> _Coupled:
    """Fluxes and the Z&B warm layer, passes until ΔT_warm settles; a periodic day spun up
    over repeated days in each pass (:func:`_spin_up_day`)."""
    dtw = np.zeros(f.n)
    q_warm = fl.heat_flux_nonsolar + f_d * f.rns
    passes, days, change = 0, 0, 0.0
    start = float(initial_warm)
    for passes in range(1, max_passes + 1):
        # the surface flux's response to the warm layer, linearised around this pass
        slope = (f.fluxes_at(dtw + _DT_PROBE).heat_flux_nonsolar
                 - fl.heat_flux_nonsolar) / _DT_PROBE
        if f.period is None:
            new = warm_layer_series(f.t, q_warm, fl.ustar_water, f.tb, start, depth, nu, None,
                                    slope, dtw)
        else:
            new, days, change, start = _spin_up_day(f, q_warm, fl, slope, dtw, start, depth,
                                                    nu, tolerance, max_days)
        diff = float(np.max(np.abs(new - dtw)))
        dtw = new
        fl = f.fluxes_at(dtw)
        q_warm = fl.heat_flux_nonsolar + f_d * f.rns
        if diff <= tolerance:
            break
    return _Coupled(dtw, fl, q_warm, dtw, np.full(f.n, float(depth)), passes, days, change)


def _spin_up_day(f: _SkinForcing, q_warm, fl: BulkFluxes, slope, dtw, start, depth, nu,
                 tolerance, max_days):
    """A periodic day of the Z&B warm layer integrated over and over until its end repeats
    its start to ``tolerance`` (at most ``max_days``).

    Returns ΔT_warm at the samples, the days integrated, the last day's end-minus-start
    change and the ΔT_warm the next integration starts from."""
    for days in range(1, max_days + 1):
        full = warm_layer_series(f.t, q_warm, fl.ustar_water, f.tb, start, depth, nu, f.period,
                                 slope, dtw)
        change = float(full[-1] - full[0])
        start = float(full[-1])
        if abs(change) <= tolerance:
            break
    return full[:-1], days, change, start


def _couple_coare(f: _SkinForcing, fl: BulkFluxes, depth, tolerance, max_passes) -> _Coupled:
    """Fluxes and the COARE warm layer, passes until ΔT_warm settles."""
    dtw = np.zeros(f.n)
    passes, change = 0, 0.0
    days = 0 if f.period is None else 1
    end = fl
    for passes in range(1, max_passes + 1):
        wl = coare_warm_layer_series(f.t, f.hours, f.rns, -fl.heat_flux_nonsolar, fl.tau, f.tb,
                                     heat_loss_end=-end.heat_flux_nonsolar,
                                     tau_end=end.tau, period=f.period, gravity=f.gravity)
        new = wl.delta * np.minimum(1.0, float(depth) / wl.depth)
        diff = float(np.max(np.abs(new - dtw)))
        dtw = new
        fl = f.fluxes_at(dtw)
        # each step's end with the warm layer at its start (explicit in the layer's
        # feedback on the fluxes, as the reference; the passes converge step by step)
        end = f.fluxes_at(np.roll(dtw, 1) if f.period is not None
                          else np.concatenate((dtw[:1], dtw[:-1])))
        if diff <= tolerance:
            break
    q_warm = fl.heat_flux_nonsolar + wl.solar_fraction * f.rns
    if f.period is not None:
        last = int(np.flatnonzero(f.hours < np.roll(f.hours, 1))[0]) - 1
        change = float(dtw[last])
    return _Coupled(dtw, fl, q_warm, wl.delta, wl.depth, passes, days, change)
