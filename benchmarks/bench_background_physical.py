"""Benchmark of the physical port background against the paper's chain, in one run.

Both build the hourly background of the same synthetic port (``--size`` x ``--size`` pixels
of 30 m, default 1000 x 1000 = 30 km) for the built-in Dalian summer design day, then give
the temperature of every pixel every 10 minutes over 24 h (145 frames, what the imaging
stage asks for):

* **ours, physical**: :func:`imaging.background.physical.build_physical_background`: the
  environment (sun, weather, sea) on the column grid, orientation groups, the column solve
  (numba), then :meth:`temperature_at` per frame;
* **peer, the paper's chain**: :func:`imaging.background.build_port_background` on the same
  port (synthetic Landsat scene, DEM and met grid written and read back in the real
  formats, single-channel LST, classification, kriging of 24 hourly grids every 5th pixel,
  terrain regression), then :meth:`temperature_at` per frame. The writing of the synthetic
  files is part of its time (it is how the built-in default runs).

The first call of the column kernel compiles it (cached on disk afterwards): a warm-up on a
small port runs first so that neither side pays a compilation.

Run: ``python benchmarks/bench_background_physical.py [--size 1000]``. Wall times on a shared
2-core machine are noisy: compare the ratio, and rerun.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def frames(bg, n: int = 145) -> float:
    t = time.perf_counter()
    acc = 0.0
    for h in np.linspace(0.0, 24.0, n):
        acc += float(bg.temperature_at(h)[0, 0])
    return time.perf_counter() - t


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=1000, help="scene side [pixels of 30 m]")
    args = ap.parse_args(argv)
    from shipthermal.environment import Environment, climate_day

    from imaging.background import build_port_background
    from imaging.background.physical import build_physical_background, ground_from_synthetic

    day = climate_day("summer")
    env = Environment.from_climate_day(day)
    build_physical_background(ground_from_synthetic(day.latitude, day.longitude, 100), env)

    n = args.size
    print(f"Port background, {n} x {n} pixels of 30 m, Dalian summer design day, 145 frames")
    t = time.perf_counter()
    ground = ground_from_synthetic(day.latitude, day.longitude, n)
    t_ground = time.perf_counter() - t
    t = time.perf_counter()
    bg = build_physical_background(ground, env)
    t_build = time.perf_counter() - t
    t_frames = frames(bg)
    ours = t_build + t_frames
    print(f"  ours, physical: ground (synthetic layout) {t_ground:6.2f} s (not counted)")
    print(f"                  build {t_build:6.2f} s "
          f"({', '.join(f'{k} {v:.2f}' for k, v in bg.timings.items() if k != 'total')}), "
          f"{bg.column_temperature.shape[1]} columns")
    print(f"                  145 frames {t_frames:6.2f} s; total {ours:6.2f} s")

    t = time.perf_counter()
    paper = build_port_background("summer", size_px=n)
    t_paper = time.perf_counter() - t
    t_pframes = frames(paper)
    peer = t_paper + t_pframes
    print(f"  peer, paper's chain: build {t_paper:6.2f} s "
          f"({', '.join(f'{k} {v:.2f}' for k, v in paper.timings.items() if k != 'total')})")
    print(f"                  145 frames {t_pframes:6.2f} s; total {peer:6.2f} s")
    print(f"  ratio peer / ours: {peer / ours:6.1f}")
    # the two side by side on the same port and day (the paper's chain: its generated Landsat
    # scene and met grid of the design day; ours: the design day's weather through physics)
    names = {1: "water", 2: "vegetation", 3: "land", 4: "building"}
    st = env.at(np.arange(0.0, 86400.0, 6 * 3600.0))
    print("  median per class [K]: physical / paper (air, sea skin)")
    for k, h in enumerate((0.0, 6.0, 12.0, 18.0)):
        a, b = bg.temperature_at(h), paper.temperature_at(h)
        cells = "  ".join(f"{n} {np.median(a[bg.class_map == c]):.1f}/"
                          f"{np.median(b[paper.class_map == c]):.1f}" for c, n in names.items())
        print(f"    {h:04.1f} h  {cells}  (air {st.temp_air[k]:.1f}, sea {st.temp_sea_skin[k]:.1f})")


if __name__ == "__main__":
    main()
