"""A full diurnal run of the default ship: spin-up included, time by stage, rays/s vs Embree.

Run: ``python benchmarks/bench_diurnal.py [--edge 0.5] [--season summer] [--max-days 10]``

Reports, for the built-in frigate on the built-in design day (scenario defaults):

* the stages: meshing (shell graph), ray tracing (view factors + sun lit fractions),
  forcing tables, and the time loop split into boundary balances, assembly and linear
  solves (from the solver's own timers), with Newton / PCG iteration counts;
* days to a periodic state and the energy balance of the whole run;
* the rays per second of our tracing pipeline (ray generation, tracing, bookkeeping) against
  raw Embree (trimesh's ``intersects_first`` through embreex) on the same view-factor rays
  in the same run.

Not a test. Other jobs share the 2 CPUs: timings move by ±30 % between runs.
"""

from __future__ import annotations

import argparse
import time



def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edge", type=float, default=None, help="surface edge length [m] "
                    "(default: the scenario's, i.e. the default ship at its default size)")
    ap.add_argument("--season", default="summer", choices=("summer", "winter"))
    ap.add_argument("--max-days", type=int, default=10)
    args = ap.parse_args()

    from shipthermal.app.thermal import run_scenario_thermal
    from shipthermal.app.scenario import default_scenario

    sc = default_scenario(args.season)
    changes = {"solver.spinup_max_days": args.max_days}
    if args.edge:
        changes["ship.edge_length"] = args.edge
    sc = sc.updated(changes)
    t0 = time.perf_counter()
    ship = sc.ship()
    t_ship = time.perf_counter() - t0
    print(f"ship: {ship.name}, {ship.n_faces} surface faces (built in {t_ship:.1f} s)")
    res = run_scenario_thermal(sc, ship=ship, progress=True, log=print)
    f = res.forcing
    tim = res.timings
    det = tim["solver_detail"]
    steps = len(res.energy.time)
    print("\n== diurnal run of the default ship ==")
    print(f"cells {res.graph.n_cells}, steps {steps} ({res.days} days, converged={res.converged}, "
          f"last day-to-day change {res.day_changes[-1]:.2e} K)")
    print(f"mesh            {tim['mesh']:8.1f} s")
    print(f"forcing total   {tim['forcing']:8.1f} s  (ray tracing: {f.seconds})")
    print(f"time loop       {tim['solve']:8.1f} s  = {tim['solve'] / steps * 1e3:.0f} ms/step")
    print(f"   boundary balances {det['boundary']:7.1f} s, assembly {det['assembly']:7.1f} s, "
          f"linear solves {det['solve']:7.1f} s, preconditioner {det['setup']:6.1f} s, "
          f"forcing f(t) {det['forcing']:6.1f} s")
    print(f"   Newton iterations/step {det['newton_iterations'] / max(steps, 1):.2f}, "
          f"PCG iterations/Newton {det['linear_iterations'] / max(det['newton_iterations'], 1):.1f}")
    print(f"energy: relative imbalance {res.energy.relative_imbalance:.2e}")

    # ---- rays/s: our pipeline vs raw Embree on the same rays -------------------------------
    from shipthermal.raytrace.viewfactors import view_factor_rays

    tr = f.traced
    n_view = tr.n_rays.get("view", 0)
    t_view = tr.seconds.get("view", float("nan"))
    faces = tr.shooters[: min(len(tr.shooters), 20000)]
    o, d = view_factor_rays(tr.tracer, tr.vertices, tr.faces, faces, 64, 0)
    o, d = o.reshape(-1, 3), d.reshape(-1, 3)
    import trimesh

    mesh = trimesh.Trimesh(tr.vertices, tr.faces, process=False)
    inter = mesh.ray  # embreex-backed when installed
    t1 = time.perf_counter()
    inter.intersects_first(o, d)
    t_raw = time.perf_counter() - t1
    print(f"\nrays/s: our view-factor pipeline {n_view / t_view / 1e6:.2f} M/s "
          f"({n_view} rays incl. generation and bookkeeping); raw Embree intersects_first "
          f"{len(o) / t_raw / 1e6:.2f} M/s on {len(o)} of the same rays "
          f"(trimesh embree: {trimesh.ray.has_embree}); ratio ours/raw "
          f"{(n_view / t_view) / (len(o) / t_raw):.2f}")


if __name__ == "__main__":
    main()
