"""Benchmark of the imaging stage: one 1024 x 1024 image and the paper's full experiment.

    python benchmarks/bench_imaging.py [--quick]

1. One 1024 x 1024 image (30 m pixels, a 30.7 km synthetic port) of the built-in frigate
   (~60k triangles) at 16 x 16 samples per pixel near the ship (sparse: pixels the ship or its
   shadow cannot touch get no samples), summer 13:00 and 07:00, 3-5 um. Prints the samples and
   rays actually traced, seconds per image (geometry and radiance separately) and rays/s,
   against the peer: raw Embree ``intersects_first`` / ``any_hit`` on the very same rays
   (``EmbreeTracer``, measured in the same run).
2. The full experiment: 24 h every 10 min x {3-5, 8-14} um x {summer, winter}
   (580 images of 334 x 334 pixels) with the synthetic stand-in temperatures, all products.
3. A calendar's dense series: 72 hourly frames x {3-5, 8-14} um of the summer scene
   (334 x 334 pixels), metrics only (frames neither stacked nor kept: each renders the local
   SCR's window, ``SceneRenderer.window_radiance``), against the peer: the same frames
   rendered whole (every frame stacked), measured in the same run; the two metrics tables
   must be equal.

Timings are wall clock on a shared 2-core machine (other agents run too): expect +-30 %.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "src"))

from imaging.background import build_port_background  # noqa: E402
from imaging.experiment import (ImagingScenario, render_series, run_experiment,  # noqa: E402
                                sun_positions)
from imaging.render import SceneRenderer, conditions_from_atmosphere  # noqa: E402
from imaging.scene import enu_direction  # noqa: E402
from imaging.thermal_history import synthetic_history  # noqa: E402
from shipthermal.geometry import frigate  # noqa: E402

WIND_SPEED = 5.0    # m/s: the sea's Cox-Munk slopes of the benchmark scenes


def _best(fn, repeat=3):
    best = np.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def one_image(size_px: int):
    print(f"== one {size_px} x {size_px} image, frigate, 16 x 16 samples per pixel near the ship")
    t0 = time.perf_counter()
    bg = build_port_background("summer", size_px=size_px)
    print(f"background (synthetic port, {size_px}^2 px): {time.perf_counter() - t0:.1f} s")
    ship = frigate()
    hist = synthetic_history(ship, "summer")
    scen = ImagingScenario.default("summer", background=bg)
    t0 = time.perf_counter()
    r = SceneRenderer(hist, bg, None, samples_per_pixel=16, wind_speed=WIND_SPEED)
    t_init = time.perf_counter() - t0
    print(f"ship: {ship.n_faces} triangles; renderer (BVH build + view rays): {t_init:.3f} s; "
          f"view samples {r.n_view_rays} in {len(r.view_pixels)} pixels "
          f"({r.n_view_rays / (size_px * size_px):.4f} per image pixel; a dense "
          f"16 x 16 render would trace {256 * size_px * size_px:.3g})")

    # the peer on the same view rays
    v = r.view_direction
    pts = r._pixel_samples(r.view_pixels)
    dist = (r.z_top + 1.0) / v[2]
    origins = np.column_stack([pts, np.zeros(len(pts))]) + dist * v
    dirs = np.ascontiguousarray(np.broadcast_to(-v, origins.shape))
    t_raw, _ = _best(lambda: r.tracer.intersects_first(origins, dirs, dist))
    t_view, _ = _best(lambda: r._trace_view())
    print(f"view rays: renderer {t_view * 1e3:.2f} ms ({r.n_view_rays / t_view / 1e6:.2f} M rays/s)"
          f" vs raw Embree intersects_first {t_raw * 1e3:.2f} ms "
          f"({len(origins) / t_raw / 1e6:.2f} M rays/s); ratio {t_view / t_raw:.2f}")

    for hour in (13.0, 7.0):
        zen, azi = sun_positions(scen, [hour * 3600.0])
        s = enu_direction(zen[0], azi[0])
        t_sun, sg = _best(lambda: r.sun_geometry(s))
        # the peer: the same sun rays, raw occlusion queries
        o_ship = r.ship_points[r.ship_normals @ s > 0] + r.tracer.offset * r.ship_normals[
            r.ship_normals @ s > 0]
        n_ground = sg.n_rays - len(o_ship)
        t_raw_sun, _ = _best(lambda: r.tracer.any_hit(o_ship, np.broadcast_to(s, o_ship.shape)))
        cond = conditions_from_atmosphere("summer", "3-5", 0.0, 0.0, zen[0], azi[0])
        temp_f = hist.at(hour * 3600.0)
        temp_bg = bg.temperature_at(hour)
        t_rad, fr = _best(lambda: r.render(cond, temp_f, temp_bg, sun=sg))
        total = t_sun + t_rad
        print(f"{hour:05.2f} h (sun zenith {zen[0]:.1f} deg): sun rays {sg.n_rays} "
              f"({n_ground} ground shadow + {len(o_ship)} ship self-shadow) in "
              f"{t_sun * 1e3:.1f} ms ({sg.n_rays / max(t_sun, 1e-9) / 1e6:.2f} M rays/s incl. "
              f"cover rasterisation; raw any_hit on the ship rays "
              f"{len(o_ship) / max(t_raw_sun, 1e-9) / 1e6:.2f} M rays/s); radiance + atmosphere "
              f"+ camera for {size_px}^2 px {t_rad:.3f} s; image {total:.3f} s "
              f"(+ view rays once {t_view:.3f} s); shadowed area {fr.shadow.sum() * 900:.0f} m2")


def dense_variant(size_px: int):
    """More rays: 64 x 64 samples per pixel, 30 deg off nadir (layover widens the footprint)."""
    bg = build_port_background("summer", size_px=size_px)
    ship = frigate()
    hist = synthetic_history(ship, "summer")
    r = SceneRenderer(hist, bg, None, view_zenith_deg=30.0, view_azimuth_deg=100.0,
                      samples_per_pixel=64, wind_speed=WIND_SPEED)
    v = r.view_direction
    pts = r._pixel_samples(r.view_pixels)
    dist = (r.z_top + 1.0) / v[2]
    origins = np.column_stack([pts, np.zeros(len(pts))]) + dist * v
    dirs = np.ascontiguousarray(np.broadcast_to(-v, origins.shape))
    t_raw, _ = _best(lambda: r.tracer.intersects_first(origins, dirs, dist))
    t_view, _ = _best(lambda: r._trace_view())
    print(f"== 64 x 64 samples per pixel, view zenith 30 deg: {r.n_view_rays} view rays in "
          f"{len(r.view_pixels)} pixels: renderer {t_view * 1e3:.1f} ms "
          f"({r.n_view_rays / t_view / 1e6:.2f} M rays/s) vs raw Embree intersects_first "
          f"{t_raw * 1e3:.1f} ms ({len(origins) / t_raw / 1e6:.2f} M rays/s); "
          f"ratio {t_view / t_raw:.2f}")


def full_experiment():
    print("== full experiment: 24 h every 10 min x 2 bands x 2 seasons (334^2 px, 580 images)")
    ship = frigate()
    hist = {s: synthetic_history(ship, s) for s in ("summer", "winter")}
    t0 = time.perf_counter()
    scen = {s: ImagingScenario.default(s) for s in hist}
    t_bg = time.perf_counter() - t0
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        res = run_experiment(hist, out, progress=False, scenarios=scen)
        wall = time.perf_counter() - t0
        n_img = sum(len(sr.times_s) for sr in res.series.values())
        rays = sum(res.series[(s, "3-5")].rays for s in hist)
    render = res.seconds["summer"] + res.seconds["winter"]
    print(f"backgrounds {t_bg:.1f} s; experiment {wall:.1f} s: rendering + metrics {render:.1f} s "
          f"for {n_img} images ({render / n_img * 1e3:.1f} ms per image, {rays} rays), "
          f"products (NetCDF, GeoTIFF, PNG, CSV) {res.seconds['outputs']:.1f} s")
    print(res.crossovers.to_string(index=False))


def dense_series():
    print("== a dense series: 72 hourly frames x 2 bands, summer (334^2 px), metrics only")
    ship = frigate()
    hist = synthetic_history(ship, "summer")
    scen = ImagingScenario.default("summer")
    frames = np.arange(0.0, 72 * 3600.0, 3600.0)
    r = scen.renderer(hist)
    bands = ("3-5", "8-14")
    t_win, win = _best(lambda: render_series(hist, scen, bands, frames, crop_px=32,
                                             progress=False, renderer=r, stack_step_s=1e12), 2)
    t_all, every = _best(lambda: render_series(hist, scen, bands, frames, crop_px=32,
                                               progress=False, renderer=r), 2)
    same = all(win[b].metrics.equals(every[b].metrics) for b in bands)
    n = len(frames) * len(bands)
    print(f"windows {t_win:.2f} s ({t_win / n * 1e3:.1f} ms a frame and band) vs whole frames "
          f"{t_all:.2f} s ({t_all / n * 1e3:.1f} ms); ratio {t_win / t_all:.2f}; metrics "
          f"{'identical' if same else 'DIFFER'}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="256^2 image, no full experiment")
    args = ap.parse_args()
    one_image(256 if args.quick else 1024)
    dense_variant(256 if args.quick else 1024)
    if not args.quick:
        full_experiment()
    dense_series()


if __name__ == "__main__":
    main()
