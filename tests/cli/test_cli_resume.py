"""Safe run directories: a killed or interrupted thermal run leaves nothing that looks
complete, and `run --resume` continues from the last checkpoint to the uninterrupted
result (bit for bit: same inputs, same seeds, single-threaded step loop)."""

import json
import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pandas as pd
import pytest
from cli_helpers import write_tiny

from shipthermal.app.cli import main
from shipthermal.errors import InputError
from shipthermal.app.rundir import RunDir

# three full days (a tolerance below one ulp of 300 K, which no run meets unless a day
# repeats bit for bit), checkpoints every simulated hour
DAYS = 3


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted run."""
    d = tmp_path_factory.mktemp("ref")
    sc = write_tiny(d, days=DAYS, tolerance=1e-15)
    out = d / "run"
    assert main(["-q", "run", str(sc), "--out", str(out)]) == 0
    return sc, out


def _same_result(a, b):
    ha, hb = (np.load(x / "thermal" / "tiny" / "history.npz") for x in (a, b))
    np.testing.assert_array_equal(ha["face_temperature"], hb["face_temperature"])
    np.testing.assert_array_equal(ha["times_s"], hb["times_s"])
    pa, pb = (pd.read_csv(x / "thermal" / "tiny" / "part_means.csv") for x in (a, b))
    pd.testing.assert_frame_equal(pa, pb)
    sa, sb = (json.loads((x / "thermal" / "tiny" / "thermal_summary.json").read_text())
              for x in (a, b))
    assert sa["days"] == sb["days"] == DAYS
    assert sa["day_changes_K"] == sb["day_changes_K"]
    # the energy log of the whole run (spin-up included) is continued, not restarted
    ea, eb = (pd.read_csv(x / "thermal" / "tiny" / "energy.csv") for x in (a, b))
    pd.testing.assert_frame_equal(ea, eb)


def _nothing_complete(out):
    assert not (out / "COMPLETE").exists()
    assert not (out / "thermal").exists()          # the stage folder appears only when done
    assert not (out / "report.html").exists()


# A run in a child process that parks itself, blocked on its stdin, right after it has
# written the first checkpoint later than argv[1] seconds of simulated time, and says so on
# stdout: the test acts on that event, never on wall time.
PARKED_RUN = textwrap.dedent("""
    import sys
    from shipthermal import simulation
    from shipthermal.app.cli import main

    after = float(sys.argv[1])
    save = simulation.Simulation.save_checkpoint

    def save_then_park(self, *args, **kwargs):
        out = save(self, *args, **kwargs)
        if self.time > after:
            print(f"checkpoint {self.time}", flush=True)
            sys.stdin.readline()
        return out

    simulation.Simulation.save_checkpoint = save_then_park
    sys.exit(main(sys.argv[2:]))
""")


def _parked_run(sc, out, after_s):
    """Start ``shipthermal run`` in a child and return it once it has written a checkpoint
    later than ``after_s`` and stopped there (its stdin is the way to release it)."""
    proc = subprocess.Popen([sys.executable, "-c", PARKED_RUN, str(after_s), "-q", "run",
                             str(sc), "--out", str(out)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    assert line.startswith("checkpoint"), (line, proc.communicate(timeout=60))
    return proc, float(line.split()[1])


def test_sigkill_mid_run_then_resume(reference, tmp_path, capsys):
    sc, ref = reference
    out = tmp_path / "run"
    ckpt = out / "checkpoints" / "tiny.npz"
    # killed inside day 2, right after a checkpoint was written
    proc, t_parked = _parked_run(sc, out, 86400.0)
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate()
    _nothing_complete(out)
    m = json.loads((out / "manifest.json").read_text())
    assert m["status"] == "running"               # killed: it could not say more
    assert not [p.name for p in out.iterdir() if p.name.startswith(".stage-")]
    assert (out / ".lock").read_text().split()[0] == str(proc.pid)     # stale: pid gone
    with np.load(ckpt) as c:
        t_killed = float(c["time"])
    assert t_killed == t_parked and 86400.0 < t_killed < DAYS * 86400.0

    # a plain run on that folder stops, names the stale lock and offers --resume / --force
    before = sorted(str(p.relative_to(out)) for p in out.rglob("*"))
    assert main(["run", str(sc), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "holds an unfinished run with checkpoints (tiny.npz)" in err, err
    assert f"its process {proc.pid} is gone (stale .lock)" in err
    assert "--resume" in err and "--force" in err and "Traceback" not in err
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == before
    # another scenario in its place is named as such
    other = sc.with_name("other.toml")
    other.write_text(sc.read_text().replace("time_step = 1800", "time_step = 900"))
    assert main(["run", str(other), "--out", str(out)]) == 2
    assert "of a different scenario (changed: solver.time_step" in capsys.readouterr().err

    # --resume takes the stale lock over (and says so) and continues from the checkpoint
    assert main(["run", str(sc), "--out", str(out), "--resume"]) == 0
    assert f"took over the stale lock of process {proc.pid}" in capsys.readouterr().err
    assert (out / "COMPLETE").is_file()
    assert not (out / "checkpoints").exists()
    assert not [p for p in out.rglob("*") if p.name.startswith((".stage-", ".lock"))]
    m = json.loads((out / "manifest.json").read_text())
    assert m["status"] == "complete" and len(m["attempts"]) == 1
    _same_result(ref, out)


def test_sigterm_is_an_interruption(reference, tmp_path):
    """SIGTERM (e.g. a batch system's time limit) stops the run like Ctrl-C: exit 143,
    manifest 'interrupted', staging folder and lock removed, checkpoint kept."""
    sc, _ = reference
    out = tmp_path / "run"
    ckpt = out / "checkpoints" / "tiny.npz"
    proc, _ = _parked_run(sc, out, 0.0)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err[-2000:]
    _nothing_complete(out)
    assert json.loads((out / "manifest.json").read_text())["status"] == "interrupted"
    assert not [p for p in out.iterdir() if p.name.startswith((".stage-", ".lock"))]
    assert ckpt.is_file()


def test_injected_interrupt_then_resume(reference, tmp_path, monkeypatch, capsys):
    """Ctrl-C after some steps of day 2 (the step loop raises KeyboardInterrupt): exit 130,
    manifest 'interrupted', checkpoint kept, staging folder removed; resume = reference."""
    from shipthermal import simulation

    sc, ref = reference
    out = tmp_path / "run"
    original = simulation.Simulation.run_until

    def interrupted(self, *a, **k):
        if self.time >= 1.5 * 86400.0:
            raise KeyboardInterrupt
        return original(self, *a, **k)

    monkeypatch.setattr(simulation.Simulation, "run_until", interrupted)
    assert main(["-q", "run", str(sc), "--out", str(out)]) == 130
    monkeypatch.setattr(simulation.Simulation, "run_until", original)
    _nothing_complete(out)
    assert not [p for p in out.iterdir() if p.name.startswith((".stage-", ".lock"))]
    m = json.loads((out / "manifest.json").read_text())
    assert m["status"] == "interrupted"
    assert "interrupted" in capsys.readouterr().err
    with np.load(out / "checkpoints" / "tiny.npz") as c:
        assert float(c["time"]) == pytest.approx(1.5 * 86400.0)
    # resuming with a changed scenario is refused (nothing changes in the folder)
    changed = sc.with_name("changed.toml")
    changed.write_text(sc.read_text().replace("time_step = 1800", "time_step = 900"))
    assert main(["-q", "run", str(changed), "--out", str(out), "--resume"]) == 2
    assert "scenario differs from the run's copy scenario.toml (changed: solver.time_step)" \
        in capsys.readouterr().err
    assert (out / "checkpoints" / "tiny.npz").is_file()
    assert main(["-q", "run", str(sc), "--out", str(out), "--resume"]) == 0
    _same_result(ref, out)


def test_finished_run_is_protected(reference, capsys):
    sc, ref = reference
    before = sorted(p.name for p in ref.iterdir())
    assert main(["-q", "run", str(sc), "--out", str(ref)]) == 2
    assert "is a finished run (COMPLETE exists)" in capsys.readouterr().err
    assert main(["run", str(sc), "--out", str(ref), "--resume"]) == 0
    assert "already complete" in capsys.readouterr().err
    # --resume with a changed scenario on a complete run is refused, naming the keys
    changed = sc.with_name("changed-complete.toml")
    changed.write_text(sc.read_text().replace("time_step = 1800", "time_step = 900"))
    assert main(["-q", "run", str(changed), "--out", str(ref), "--resume"]) == 2
    err = capsys.readouterr().err
    assert "is a finished run of a different scenario (changed: solver.time_step)" in err, err
    assert sorted(p.name for p in ref.iterdir()) == before


# ---- RunDir on its own ----------------------------------------------------------------
def test_stage_is_renamed_only_when_done(tmp_path):
    with pytest.raises(RuntimeError):
        with RunDir(tmp_path / "r", command=["test"]) as run:
            with run.stage("thermal/a") as d:
                (d / "x.csv").write_text("1")
                assert not (tmp_path / "r" / "thermal" / "a").exists()
            assert (tmp_path / "r" / "thermal" / "a" / "x.csv").read_text() == "1"
            with run.stage("imaging") as d:
                (d / "y.csv").write_text("half")
                raise RuntimeError("crash while writing")
    r = tmp_path / "r"
    assert not (r / "imaging").exists() and not (r / "COMPLETE").exists()
    assert not [p for p in r.iterdir() if p.name.startswith(".stage-")]
    assert json.loads((r / "manifest.json").read_text())["status"] == "failed"
    assert not (r / ".lock").exists()


def test_lock_refuses_a_live_writer_and_takes_a_dead_ones(tmp_path):
    r = tmp_path / "r"
    with RunDir(r, command=["test"]) as run:
        with pytest.raises(InputError, match=f"is in use by process {os.getpid()}"):
            RunDir(r, command=["second"], resume=True)
        run.release()
        # a lock left by a process that no longer exists, and debris of its writers
        dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                              capture_output=True, text=True).stdout.strip()
        import socket

        (r / ".lock").write_text(f"{dead} {socket.gethostname()}")
        (r / ".stage-imaging.999").mkdir()
        (r / ".report.html.tmp123").write_text("half")
        run.claim("thermal")                # listed in the manifest before it is written
        (r / "thermal").mkdir()
        (r / "thermal" / "x.csv.part-77").write_text("half")
    with RunDir(r, command=["again"], resume=True) as run2:
        assert run2.manifest["attempts"]
    left = sorted(str(p.relative_to(r)) for p in r.rglob("*"))
    assert left == ["COMPLETE", "manifest.json", "thermal"]


def test_user_error_in_a_fresh_run_leaves_nothing(tmp_path):
    r = tmp_path / "new"
    with pytest.raises(InputError):
        with RunDir(r, command=["test"]):
            raise InputError("weather.source", "w.csv", "must have a temp_air column")
    assert not r.exists()


def test_non_run_folder_and_file_are_refused(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match="not a shipthermal run directory"):
        RunDir(tmp_path)
    with pytest.raises(InputError, match="must be a folder"):
        RunDir(tmp_path / "notes.txt")
    assert (tmp_path / "notes.txt").read_text() == "mine"


# ---- a weather record: checkpoints at the end of every day ----------------------------------
def test_record_interrupted_in_day_3_resumes_to_the_uninterrupted_result(tmp_path, monkeypatch,
                                                                          capsys):
    """Three days of the buoy record: Ctrl-C early in day 3 (exit 130) leaves the checkpoint
    of day 2 and the outputs' parts of days 1-2; --resume skips the spin-up and those days
    and writes what the uninterrupted run writes (history.h5, part means, energy log)."""
    import shutil

    import h5py

    from shipthermal import simulation

    from test_cli_weather import BUOY, NDBC, _with

    shutil.copy(NDBC, tmp_path / "buoy.txt")
    sc = _with(write_tiny(tmp_path, name="buoy", season="winter"),
               BUOY.replace("days = 2", "days = 3"), "2013-03-04")
    ref, out = tmp_path / "ref", tmp_path / "run"
    assert main(["-q", "run", str(sc), "--out", str(ref)]) == 0
    original = simulation.Simulation.run_until

    def interrupted(self, end_time, *a, **k):
        if end_time > 2 * 86400.0:
            raise KeyboardInterrupt
        return original(self, end_time, *a, **k)

    monkeypatch.setattr(simulation.Simulation, "run_until", interrupted)
    assert main(["-q", "run", str(sc), "--out", str(out)]) == 130
    monkeypatch.setattr(simulation.Simulation, "run_until", original)
    _nothing_complete(out)
    with np.load(out / "checkpoints" / "buoy.npz") as c:
        assert float(c["time"]) == 2 * 86400.0 and int(c["extra_record_day"]) == 2
    parts = sorted(p.name for p in (out / "checkpoints" / "buoy.record" / "parts").iterdir())
    assert parts == ["part_00000.npz", "part_00001.npz"]
    capsys.readouterr()
    assert main(["-v", "run", str(sc), "--out", str(out), "--resume"]) == 0
    err = capsys.readouterr().err
    assert "resumed from" in err and "after 2 of 3 recorded day(s)" in err
    assert not (out / "checkpoints").exists()
    with h5py.File(ref / "thermal" / "buoy" / "history.h5") as a, \
            h5py.File(out / "thermal" / "buoy" / "history.h5") as b:
        for name in ("times", "face_temperature", "part_means", "energy/imbalance"):
            np.testing.assert_array_equal(a[name][:], b[name][:])
    for name in ("part_means.csv", "energy.csv"):
        pd.testing.assert_frame_equal(pd.read_csv(ref / "thermal" / "buoy" / name),
                                      pd.read_csv(out / "thermal" / "buoy" / name))
    sa, sb = (json.loads((x / "thermal" / "buoy" / "thermal_summary.json").read_text())
              for x in (ref, out))
    assert sa["days"] == sb["days"] and sa["record_days"] == sb["record_days"] == 3


def test_a_split_record_interrupted_stops_its_processes_quietly_and_resumes(tmp_path):
    """Three days of the buoy split over two processes (``solver.jobs = 2``): Ctrl-C in the
    first segment's day 2 (SIGINT sent there, in a subprocess of the test) while the other
    segment's process is busy: exit 130 at once, one line on stderr — the other process
    stopped without a traceback or a leaked semaphore — and ``--resume`` writes what the
    uninterrupted split run writes."""
    import shutil

    import h5py

    from test_cli_weather import BUOY, NDBC, _with

    shutil.copy(NDBC, tmp_path / "buoy.txt")
    sc = _with(write_tiny(tmp_path, name="buoy", season="winter"),
               BUOY.replace("days = 2", "days = 3"), "2013-03-04")
    sc.write_text(sc.read_text().replace("[solver]\n", "[solver]\njobs = 2\n"))
    ref, out = tmp_path / "ref", tmp_path / "run"
    assert main(["-q", "run", str(sc), "--out", str(ref)]) == 0
    script = textwrap.dedent(f"""
        import multiprocessing, os, signal, sys, time
        from shipthermal import simulation
        from shipthermal.app.cli import main
        # (a test run in the background may have inherited SIGINT ignored)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        original = simulation.Simulation.run_until
        slept = []
        def interrupted(self, end_time, *a, **k):
            # (spawned, the segment's process runs this file too, without the main block)
            if multiprocessing.parent_process() is not None:
                if not slept:
                    slept.append(time.sleep(60))   # the other segment: busy at Ctrl-C
            elif end_time > 86400.0 + 3600.0:
                os.kill(os.getpid(), signal.SIGINT)    # Ctrl-C, to this process alone
            return original(self, end_time, *a, **k)
        simulation.Simulation.run_until = interrupted
        if __name__ == "__main__":
            sys.exit(main(["-q", "run", {str(sc)!r}, "--out", {str(out)!r}]))
        """)
    (tmp_path / "interrupt.py").write_text(script)
    done = subprocess.run([sys.executable, str(tmp_path / "interrupt.py")],
                          capture_output=True, text=True, timeout=240)
    assert done.returncode == 130, done.stderr[-3000:]
    assert done.stderr.strip().splitlines() == [
        "interrupted (an unfinished run resumes with --resume)"], done.stderr[-3000:]
    _nothing_complete(out)
    assert main(["-q", "run", str(sc), "--out", str(out), "--resume"]) == 0
    with h5py.File(ref / "thermal" / "buoy" / "history.h5") as a, \
            h5py.File(out / "thermal" / "buoy" / "history.h5") as b:
        for name in ("times", "face_temperature", "part_means", "energy/imbalance"):
            np.testing.assert_array_equal(a[name][:], b[name][:])
