"""Benchmark: embedded-table atmosphere lookup vs a live LOWTRAN 7 call.

Run: ``python benchmarks/bench_atmosphere.py``. Realistic use: the 24 h × 2 bands ×
2 seasons experiment asks for one geometry per 10-minute step (576 queries), each with the
frame's own weather (a new state, so no cache hit). Timings are wall-clock on a shared
2-core machine (other jobs running): noisy, compare ratios.
"""

from __future__ import annotations

import time

import numpy as np

from imaging.atmosphere import AtmosphereState, atmosphere, lowtran_available, sky_radiance


def _time(fn, n):
    fn()  # warm-up (loading, PCHIP construction, LOWTRAN compilation check)
    t0 = time.perf_counter()
    for _ in range(n):
        fn()
    return (time.perf_counter() - t0) / n


def main() -> None:
    rng = np.random.default_rng(0)
    views = rng.uniform(0.0, 60.0, 576)
    suns = rng.uniform(0.0, 120.0, 576)
    it = iter(range(10 ** 9))

    temps = rng.uniform(285.0, 300.0, 576)

    def table_band():
        i = next(it) % 576
        atmosphere("summer", "8-14", views[i], suns[i], spectral=False,
                   state=AtmosphereState(temp_air_K=temps[i], rel_humidity=70.0),
                   cloud_cover=0.3)

    def table_full():
        i = next(it) % 576
        atmosphere("summer", "8-14", views[i], suns[i])

    t_band = _time(table_band, 576)
    t_full = _time(table_full, 200)
    z = np.linspace(0.0, 89.0, 10000)
    t_sky = _time(lambda: sky_radiance("winter", "3-5", z), 20)
    print(f"table lookup, band values only     : {t_band * 1e3:8.3f} ms/query")
    print(f"table lookup, with spectral arrays : {t_full * 1e3:8.3f} ms/query")
    print(f"table sky radiance, 10k directions : {t_sky * 1e3:8.3f} ms/call")
    print(f"24 h x 2 bands x 2 seasons at 10 min (576 queries): {576 * t_band:.2f} s")
    if not lowtran_available():
        print("live LOWTRAN not installed: no peer timing (see lowtran_backend.INSTALL_HINT)")
        return
    from imaging.atmosphere import lowtran_backend as lb

    t_raw = _time(lambda: lb.upward("summer", 30.0), 30)
    t_ss = _time(lambda: lb.scattered_sky("summer", 30.0, 40.0, 90.0), 10)
    t_live = _time(lambda: atmosphere("summer", "8-14", 30.0, 120.0, backend="lowtran"), 1)
    print(f"peer: one LOWTRAN 7 card-deck run (2.9-14.5 um, 5 cm-1): {t_raw * 1e3:8.1f} ms")
    print(f"peer: one single-scattered sunlight run (IEMSCT=2): {t_ss * 1e3:8.1f} ms")
    print(f"peer: live atmosphere() at night (all quantities + sky irradiance): {t_live:8.2f} s")
    print("      (by day add ~100 IEMSCT=2 runs for the hemispherical scattered sunlight)")
    print(f"ratio live atmosphere() / table lookup (band): {t_live / t_band:10.0f} x")
    print(f"ratio live atmosphere() / table lookup (spectral): {t_live / t_full:10.0f} x")
    print(f"ratio one LOWTRAN run / table lookup (band): {t_raw / t_band:10.1f} x")


if __name__ == "__main__":
    main()
