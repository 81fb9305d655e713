"""Every command the documentation shows is run by a test, as written (placeholders
filled in with tiny inputs), so that README.md, docs/CLI.md and docs/SCENARIO.md cannot drift
from the program.

* every ``shipthermal …``, ``./run …`` and ``python -m shipthermal…`` command in a code block
  or inline code span parses (each optional ``[…]`` part with and without, each ``a | b``
  alternative on its own);
* each documented subcommand then runs end to end in its documented form on a tiny scenario
  (a 56 m patrol boat at 5.6 m edges); the full-size runs (``./run demo``, ``validate``
  without ``--quick``) are marked slow;
* the Python blocks of docs/SCENARIO.md run as written.
"""

import itertools
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import write_tiny

from shipthermal.app.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md", ROOT / "docs" / "CLI.md", ROOT / "docs" / "SCENARIO.md"]
DOCS += sorted((ROOT / "examples").glob("*/README.md"))
RUN_WORDS = {"demo", "test", "bench", "setup", "lock"}      # ./run's own commands

# placeholders of the docs -> tiny stand-ins (relative to the test's working folder)
PLACEHOLDERS = {"SCENARIO": "my.toml", "RUN_DIR": "runs/my", "SWEEP.toml": "sweep.toml",
                "DIR": "runs/other", "FILE": "report-copy.html", "N": "2", "M": "3",
                "NAME": "frigate", "ADDR": "tcp://127.0.0.1:8786", "tcp://host:8786":
                "tcp://127.0.0.1:8786", "<subcommand>": "--help"}


def _snippets(text):
    """Command lines in fenced code blocks and inline code spans."""
    out = []
    for block in re.findall(r"```[a-z]*\n(.*?)```", text, flags=re.S):
        out += block.splitlines()
    prose = re.sub(r"```.*?```", "", text, flags=re.S)
    out += re.findall(r"`([^`\n]+)`", prose)
    cmds = []
    for line in out:
        line = line.split("  #")[0].split(" # ")[0].strip()
        line = line.replace("\\|", "|")
        m = re.match(r"(?:\./run|shipthermal|python -m shipthermal)(\s|$)", line)
        if m:
            cmds.append(line)
    return cmds


def _expand(cmd):
    """The variants of a documented synopsis: every optional part left out, and every
    optional part in (its first alternative, then its second, ...)."""
    parts = re.split(r"(\[[^\[\]]*\])", cmd)
    options = [[a.strip() for a in p[1:-1].split("|")] if p.startswith("[") and p.endswith("]")
               else None for p in parts]
    n = max([len(o) for o in options if o] or [0])
    variants = {" ".join("".join("" if o else p for p, o in zip(parts, options)).split())}
    for k in range(n):
        line = "".join(o[min(k, len(o) - 1)] if o else p for p, o in zip(parts, options))
        variants.add(" ".join(line.split()))
    return variants


def _argv(cmd):
    words = shlex.split(cmd)
    words = [PLACEHOLDERS.get(w, w) for w in words]
    if words[0] == "./run":
        return ("run", words[1:])
    if words[:2] == ["python", "-m"]:
        return (words[2], words[3:])
    return ("shipthermal", words[1:])


def documented_commands():
    seen = {}
    for doc in DOCS:
        for cmd in _snippets(doc.read_text(encoding="utf-8")):
            for variant in sorted(_expand(cmd)):
                if len(variant.split()) > (3 if variant.startswith("python") else 1):
                    seen.setdefault(variant, doc.name)      # not a mere mention of the name
    return seen


COMMANDS = documented_commands()


def test_the_docs_show_commands():
    kinds = {_argv(c)[0] for c in COMMANDS}
    assert kinds >= {"run", "shipthermal"}, kinds
    subs = {_argv(c)[1][0] for c in COMMANDS if _argv(c)[0] == "shipthermal" and _argv(c)[1]}
    assert subs >= {"demo", "mesh", "run", "image", "crossover", "validate", "sweep", "report",
                    "check", "schema"}


@pytest.mark.parametrize("cmd", sorted(COMMANDS), ids=lambda c: c[:70])
def test_documented_command_parses(cmd):
    kind, argv = _argv(cmd)
    if kind == "run":
        if not argv or argv[0] in RUN_WORDS:
            text = (ROOT / "run").read_text()
            word = argv[0] if argv else "demo"
            assert re.search(rf"^\s+{word}\)", text, flags=re.M) or word == "demo", cmd
            return
        kind = "shipthermal"                   # ./run <args> is the shipthermal command line
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:
        if exc.code == 0 and ("--help" in argv or "--version" in argv):
            return
        pytest.fail(f"{cmd!r} (from {COMMANDS[cmd]}) does not parse: exit {exc.code}")
    assert callable(args.func)


# ---------------------------------------------------------------------------------------
# the documented subcommands, run as written on a tiny scenario
# ---------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    d = tmp_path_factory.mktemp("docs")
    sc = write_tiny(d, name="my", formats=("csv", "json", "png", "html"))
    text = sc.read_text().replace("[outputs]\n", '[outputs]\ndirectory = "runs/my"\n')
    sc.write_text(text)
    (d / "sweep.toml").write_text('name = "docs"\nbase = "my.toml"\nstages = ["thermal"]\n'
                                  '[axes]\n"ship.heading" = [0, 90]\n')
    return d


def _shipthermal(argv, d, monkeypatch):
    monkeypatch.chdir(d)
    return main(["-q"] + argv)


RUNS = [   # in order: later ones use what earlier ones wrote
    "shipthermal mesh my.toml",
    "shipthermal run my.toml --image",
    "shipthermal run my.toml --resume",
    "shipthermal image runs/my --step-min 10",
    "shipthermal crossover runs/my --csv",
    "shipthermal crossover runs/my",
    "shipthermal report runs/my",
    "shipthermal report runs/my --output report-copy.html",
    "shipthermal sweep sweep.toml --serial",
]


def test_runs_cover_the_documented_subcommands():
    documented = {_argv(c)[1][0] for c in COMMANDS
                  if _argv(c)[0] in ("shipthermal", "run") and _argv(c)[1]
                  and _argv(c)[1][0] not in RUN_WORDS | {"--help"}}
    ran = {r.split()[1] for r in RUNS} | {"demo", "validate", "background"}   # tests below
    ran |= {"calibrate"}      # tests/calibration/test_calibration_cli.py (slow: model runs)
    ran |= {"ensemble"}       # tests/cli/test_cli_ensemble.py (3 serial members)
    ran |= {"check", "schema"}   # test_scenario_check_and_schema_commands below
    ran |= {"calendar"}   # tests/cli/test_cli_weather.py::test_calendar_of_a_record
    ran |= {"--version"}  # tests/cli/test_cli_main.py (the version of the package's metadata)
    assert documented <= ran, documented - ran


@pytest.mark.parametrize("cmd", RUNS)
def test_documented_command_runs(cmd, workdir, monkeypatch, capsys):
    sub = _argv(cmd)[1][0]
    assert any(_argv(c)[1][:1] == [sub] for c in COMMANDS), f"{sub} is not documented"
    assert _shipthermal(_argv(cmd)[1], workdir, monkeypatch) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    if "crossover" in cmd:
        assert "crossover" in out or "season" in out
    if cmd.startswith("shipthermal run my.toml --image"):
        assert (workdir / "runs" / "my" / "COMPLETE").is_file()
    if "--output" in cmd:
        assert (workdir / "report-copy.html").stat().st_size > 10_000


def test_scenario_check_and_schema_commands(workdir):
    exe = subprocess.run([sys.executable, "-m", "shipthermal", "check", "my.toml"],
                         cwd=workdir, capture_output=True, text=True)
    assert exe.returncode == 0 and "my.toml: ok" in exe.stdout, exe.stderr
    exe = subprocess.run([sys.executable, "-m", "shipthermal", "schema"],
                         capture_output=True, text=True)
    assert exe.returncode == 0 and "| key |" in exe.stdout


def test_scenario_md_python_block_runs(workdir, monkeypatch):
    text = (ROOT / "docs" / "SCENARIO.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks
    monkeypatch.chdir(workdir)
    for block in blocks:
        exec(compile(block.replace("runs/x/", "runs/x-doc/"), "SCENARIO.md", "exec"), {})
    assert (workdir / "runs" / "x-doc" / "scenario.toml").is_file()


def test_background_example_as_documented(tmp_path, monkeypatch):
    """examples/real_port/README.md: `shipthermal background examples/real_port/background.toml
    --out runs/mersey-background` (the real Mersey crop, no user code)."""
    text = (ROOT / "examples" / "real_port" / "README.md").read_text(encoding="utf-8")
    cmd = "shipthermal background examples/real_port/background.toml --out runs/mersey-background"
    assert cmd in text
    monkeypatch.chdir(tmp_path)
    argv = shlex.split(cmd)[1:]
    argv[1] = str(ROOT / argv[1])
    assert main(["-q"] + argv) == 0
    assert (tmp_path / "runs" / "mersey-background" / "class_map.tif").is_file()


def test_demo_quick_as_documented(workdir, monkeypatch, capsys):
    """`shipthermal demo --quick --out runs/q` (4 m mesh, images every 30 min)."""
    assert _shipthermal(["demo", "--quick", "--out", "runs/q"], workdir, monkeypatch) == 0
    q = workdir / "runs" / "q"
    assert (q / "COMPLETE").is_file() and (q / "report.html").is_file()
    for season in ("summer", "winter"):
        assert (q / "imaging" / "background" / season / "background_K.tif").is_file()
    # a second call refuses to overwrite without --force
    assert _shipthermal(["demo", "--quick", "--out", "runs/q"], workdir, monkeypatch) == 2
    assert "--force" in capsys.readouterr().err


@pytest.mark.slow
def test_run_demo_as_documented(tmp_path):
    """`./run demo` on the built-in default (full size)."""
    exe = subprocess.run([str(ROOT / "run"), "demo", "--out", str(tmp_path / "demo")],
                         capture_output=True, text=True)
    assert exe.returncode == 0, exe.stderr[-3000:]
    assert (tmp_path / "demo" / "COMPLETE").is_file()


@pytest.mark.slow
def test_validate_as_documented(workdir, monkeypatch):
    """`shipthermal validate --quick --into runs/my` and `shipthermal validate` (the default 0.5 m mesh)."""
    assert _shipthermal(["validate", "--quick", "--into", "runs/my"], workdir,
                        monkeypatch) == 0
    assert _shipthermal(["validate", "--out", "runs/validation"], workdir, monkeypatch) == 0
