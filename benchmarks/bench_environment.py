"""Benchmark of the environment stage (not a test).

1. ``Environment.at`` over a 10-day spin-up at a 300 s step (2880 instants): sun
   (SPA), clear-sky + cloud irradiance, sky long-wave, sea, relative wind — against
   the peer: raw pvlib ``spa_python`` + ``Location.get_clearsky`` on the same instants.
2. Mixed-convection coefficients for 200k ship faces at one instant
   (``h_exterior_air``: film properties, forced plate, tilted natural, Churchill
   blend) — against the peer: one bare Churchill–Chu evaluation in numpy on the
   same arrays (a lower bound for any correlation-based h).

Timings share 2 cores with other jobs: they are noisy; best of 5 is printed.

Run: python benchmarks/bench_environment.py
"""

import time

import numpy as np
import pandas as pd
import pvlib

from shipthermal.environment import Environment, climate_day
from shipthermal.environment import convection as cv


def best(fn, repeat=5):
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def main():
    day = climate_day("summer")
    env = Environment.from_climate_day(day, ship_heading=90.0, ship_speed=5.0)
    secs = np.arange(0, 10 * 86400, 300.0)
    t_ours = best(lambda: env.at(secs))

    times = env.start + pd.to_timedelta(np.mod(secs, 86400), unit="s")
    loc = pvlib.location.Location(day.latitude, day.longitude, day.tz, day.altitude)

    def peer():
        pos = pvlib.solarposition.spa_python(times, day.latitude, day.longitude, day.altitude)
        loc.get_clearsky(times, model="ineichen", solar_position=pos)

    t_peer = best(peer)
    print(f"Environment.at, {len(secs)} instants: {t_ours * 1e3:8.1f} ms "
          f"({len(secs) / t_ours:,.0f} instants/s)")
    print(f"peer pvlib spa_python + Ineichen:   {t_peer * 1e3:8.1f} ms  -> ratio ours/peer "
          f"{t_ours / t_peer:.2f}")

    n = 200_000
    rng = np.random.default_rng(0)
    ts = rng.uniform(280, 340, n)
    nz = rng.uniform(-1, 1, n)
    lf = rng.uniform(5, 100, n)
    lv = rng.uniform(1, 10, n)
    lh = rng.uniform(1, 10, n)
    t_h = best(lambda: cv.h_exterior_air(ts, 300.0, nz, 6.4, lf, lv, lh))
    props = cv.air_properties(0.5 * (ts + 300.0))
    ra = cv.rayleigh(ts, 300.0, lv, props)
    t_cc = best(lambda: cv.nusselt_vertical_plate(ra, 0.71))
    print(f"h_exterior_air, {n:,} faces:       {t_h * 1e3:8.1f} ms ({n / t_h / 1e6:.1f} M faces/s)")
    print(f"peer bare Churchill-Chu numpy:       {t_cc * 1e3:8.1f} ms  -> ratio ours/peer "
          f"{t_h / t_cc:.1f}")


if __name__ == "__main__":
    main()
