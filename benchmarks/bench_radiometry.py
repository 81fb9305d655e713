"""Benchmark: band radiance of a 1024 x 1024 temperature image.

Ours: Gauss-Legendre band quadrature (8 nodes, ``imaging.radiometry.band_radiance``) and the
cubic-Hermite temperature table (``band_radiance_table``).
Peer, measured in the same run: a high-resolution trapezoid over wavelength
(``scipy.integrate.trapezoid`` on 2001 wavelengths, evaluated in image chunks), the direct
way to integrate the Planck function over a band. Accuracy reference: ``scipy.integrate.quad``
on 200 random pixels (and the exact series for all pixels).

Run: ``python benchmarks/bench_radiometry.py``. Timings share 2 cores with other work: noisy.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.integrate import quad, trapezoid

from shipthermal.optics.planck import (band_radiance, band_radiance_rectangular_exact,
                                       band_radiance_table, planck_radiance)

N = 1024
N_WAVELENGTHS = 2001
CHUNK = 2048  # 2048 x 2001 doubles = 33 MB per temporary: stays out of swap-like page faulting


def trapezoid_band(temp, lo, hi, n=N_WAVELENGTHS):
    wl = np.linspace(lo, hi, n)
    flat = temp.ravel()
    out = np.empty_like(flat)
    for i in range(0, flat.size, CHUNK):
        t = flat[i:i + CHUNK, None]
        out[i:i + CHUNK] = trapezoid(planck_radiance(wl[None, :], t), wl, axis=1)
    return out.reshape(temp.shape)


def timed(fn, *args, repeat=3, **kw):
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(*args, **kw)
        best = min(best, time.perf_counter() - t0)
    return best, out


def main():
    rng = np.random.default_rng(0)
    # a port-like scene: 275-320 K with smooth structure plus noise
    yy, xx = np.mgrid[0:N, 0:N] / N
    temp = (290 + 12 * np.sin(6 * xx) * np.cos(4 * yy) + 8 * (yy > 0.6)
            + rng.normal(0, 1.0, (N, N)))
    print(f"image {N}x{N}, T in [{temp.min():.1f}, {temp.max():.1f}] K; "
          "timings: best of 3 (trapezoid: 1 run), shared 2-core machine, noisy")
    for band, (lo, hi) in (("3-5", (3.0, 5.0)), ("8-14", (8.0, 14.0))):
        t_gl, l_gl = timed(band_radiance, temp, band)
        t_build, table = timed(band_radiance_table, band, 250.0, 350.0, 1.0, repeat=1)
        t_tab, l_tab = timed(table, temp)
        t_tr, l_tr = timed(trapezoid_band, temp, lo, hi, repeat=1)
        exact = band_radiance_rectangular_exact(temp, lo, hi)
        idx = rng.choice(temp.size, 200, replace=False)
        tq = temp.ravel()[idx]
        ref = np.array([quad(lambda w, t=t: float(planck_radiance(w, t)), lo, hi,
                             epsabs=0, epsrel=1e-13)[0] for t in tq])

        def rel(a):
            return np.max(np.abs(a.ravel()[idx] / ref - 1))

        print(f"\n[{band} um]")
        print(f"  Gauss-Legendre 8 nodes : {t_gl:7.3f} s  max rel err vs quad {rel(l_gl):.1e}"
              f"  (vs exact series, all pixels {np.max(np.abs(l_gl / exact - 1)):.1e})")
        print(f"  Hermite table (1 K)    : {t_tab:7.3f} s  max rel err vs quad {rel(l_tab):.1e}"
              f"  (build {t_build:.3f} s, stated {table.max_rel_error:.1e})")
        print(f"  peer: trapezoid {N_WAVELENGTHS} wl: {t_tr:7.3f} s  max rel err vs quad "
              f"{rel(l_tr):.1e}")
        print(f"  ratio peer / Gauss-Legendre = {t_tr / t_gl:.0f}x, "
              f"peer / table = {t_tr / t_tab:.0f}x")


if __name__ == "__main__":
    main()
