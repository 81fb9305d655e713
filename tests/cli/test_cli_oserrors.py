"""Failures of the operating system on the user's paths (and an empty export) are user
errors: exit 2, one line naming the path, what went wrong (with its errno name) and how to
fix it, no traceback, and nothing half-written left behind."""

import errno
import os
import pathlib

import pytest
from cli_helpers import write_tiny

from shipthermal.app.cli import main


def _tree(root):
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


def _run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


def _check(code, err, fragments, lines=1):
    assert code == 2, err
    assert err.startswith("error: ") and err.count("\n") == lines, err
    assert "Traceback" not in err and "internal error" not in err
    for f in fragments:
        assert f in err, f"{f!r} not in {err!r}"


def test_output_folder_not_writable(tmp_path, capsys, monkeypatch):
    sc = write_tiny(tmp_path)
    locked = tmp_path / "locked"
    locked.mkdir()
    if os.geteuid() == 0:
        # root writes anywhere: the refusal an ordinary user gets is raised where it would be
        original = pathlib.Path.mkdir

        def refuse(self, *a, **k):
            if locked in self.parents:
                raise PermissionError(errno.EACCES, "Permission denied", str(self))
            return original(self, *a, **k)

        monkeypatch.setattr(pathlib.Path, "mkdir", refuse)
    else:
        locked.chmod(0o555)
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--out", str(locked / "run")], capsys)
    _check(code, err, [str(locked / "run"), "permission denied", "(EACCES)",
                       "Choose a path you may read and write"])
    assert _tree(tmp_path) == before


def test_disk_full_while_writing_results(tmp_path, capsys, monkeypatch):
    from shipthermal.app import pipeline

    sc = write_tiny(tmp_path)
    out = tmp_path / "run"

    def full(result, out_dir, scenario, progress=False):
        raise OSError(errno.ENOSPC, "No space left on device", str(out_dir / "history.npz"))

    monkeypatch.setattr(pipeline, "write_thermal", full)
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--out", str(out)], capsys)
    _check(code, err, ["history.npz", "no space left on the device (ENOSPC)",
                       "Free disk space, or choose --out on another disk"])
    assert _tree(tmp_path) == before            # the fresh run folder is removed again


def test_name_too_long(tmp_path, capsys):
    sc = write_tiny(tmp_path)
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--out", str(tmp_path / ("x" * 300))], capsys)
    _check(code, err, ["(ENAMETOOLONG)", "255 bytes per name", "Use shorter names"])
    assert _tree(tmp_path) == before


def test_output_below_a_file(tmp_path, capsys):
    sc = write_tiny(tmp_path)
    (tmp_path / "notes.txt").write_text("mine")
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--out", str(tmp_path / "notes.txt" / "run")],
                     capsys)
    _check(code, err, ["notes.txt", "a part of the path is a file, not a folder (ENOTDIR)"])
    assert _tree(tmp_path) == before


def test_binary_scenario_file(tmp_path, capsys):
    f = tmp_path / "picture.toml"
    f.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe")
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(f), "--out", str(tmp_path / "run")], capsys)
    # one problem: one line, naming the file once
    _check(code, err, ["scenario = ", "must be UTF-8 text (byte 0 is not UTF-8)",
                       "not a binary one"], lines=1)
    assert err.count("picture.toml") == 1
    assert _tree(tmp_path) == before


def test_folder_given_as_mesh(tmp_path, capsys):
    (tmp_path / "ship.stl").mkdir()
    (tmp_path / "s.toml").write_text('[ship.files]\nmesh = "ship.stl"\nunits = "m"\n'
                                     'draught = 4.0\n')
    before = _tree(tmp_path)
    code, err = _run(["-q", "mesh", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o")],
                     capsys)
    assert code == 2 and "Traceback" not in err, err
    assert "ship.files.mesh = 'ship.stl': must be a file, not a folder" in err, err
    assert _tree(tmp_path) == before


@pytest.mark.parametrize("name", ["ENOSPC", "EACCES", "ENAMETOOLONG", "EROFS"])
def test_errors_inside_the_installation_stay_internal(name, capsys, monkeypatch):
    """An OS error on one of the package's own files is not the user's to fix."""
    from shipthermal.app import cli
    from shipthermal.errors import input_error_from_os

    own = pathlib.Path(cli.__file__)
    exc = OSError(getattr(errno, name), os.strerror(getattr(errno, name)), str(own))
    assert input_error_from_os(exc) is None
    user = OSError(getattr(errno, name), os.strerror(getattr(errno, name)), "/data/my/run")
    assert input_error_from_os(user).field == "path"
    assert input_error_from_os(ValueError("x")) is None


def test_header_only_weather_csv(tmp_path, capsys):
    """A weather CSV with its header and no rows (an export that stopped early)."""
    sc = write_tiny(tmp_path, name="h")
    sc.write_text(sc.read_text().replace("[ship]", '[weather]\nsource = "w.csv"\n\n[ship]'))
    (tmp_path / "w.csv").write_text("time,temp_air,relative_humidity,wind_speed,"
                                    "wind_direction,cloud_cover,temp_sea\n")
    before = _tree(tmp_path)
    code, err = _run(["-q", "run", str(sc), "--out", str(tmp_path / "run")], capsys)
    _check(code, err, ["w.csv", "holds no data rows"])
    assert _tree(tmp_path) == before


@pytest.mark.parametrize("fault", ["disk full", "not an OS error"])
def test_failing_writer_leaves_nothing(tmp_path, fault):
    """A writer that fails inside ``atomic_path`` leaves neither the target nor its
    temporary; an OS error on the temporary names the user's file, and the file already
    there is kept as it was."""
    from shipthermal.atomic import atomic_path

    target = tmp_path / "table.csv"

    def writer(tmp):
        tmp.write_text("half a ta")
        if fault == "disk full":
            raise OSError(errno.ENOSPC, "No space left on device", str(tmp))
        raise ValueError("the writer gave up")

    expected = OSError if fault == "disk full" else ValueError
    with pytest.raises(expected) as info:
        with atomic_path(target) as tmp:
            assert tmp.parent == tmp_path and tmp.name.endswith(".tmp.csv")
            writer(tmp)
    assert _tree(tmp_path) == []
    if fault == "disk full":
        assert info.value.filename == str(target) and info.value.errno == errno.ENOSPC
    target.write_text("kept\n")
    with pytest.raises(expected):
        with atomic_path(target) as tmp:
            writer(tmp)
    assert _tree(tmp_path) == ["table.csv"] and target.read_text() == "kept\n"
