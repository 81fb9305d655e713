"""The package layers, read from the source with ``ast`` (no module is imported).

Three layers, lowest first:

* **physics** — every module of ``shipthermal`` outside ``shipthermal.app`` (geometry, mesh,
  environment, optics, raytrace, forcing, model, simulation, diurnal, results, ...);
* **imaging** — ``src/imaging``; it may use only the thermal package's lower layers
  (:data:`IMAGING_MAY_USE`);
* **application** — ``shipthermal.app`` (scenario, pipeline, command line, sweeps, run
  folders, reports, validation, calibration), ``python -m shipthermal`` and the package's
  front door ``shipthermal/__init__.py`` (``shipthermal.Simulation`` re-exported from
  ``shipthermal.app.chain``, imported on first use): the only place that wires stages
  together.

A module never imports from a layer above its own, and no module imports a module that
imports it back (directly or through others). Every import counts, also those inside
functions: a lazy import is still a dependency.

Imports stand at the top of a module, so that its header says what it depends on. An import
of the project's own modules inside a function says why it waits there (a start-up cost it
keeps out, a test that forbids it at load) in a comment beside or above it.
"""

from __future__ import annotations

import ast
import io
import tokenize
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGES = ("shipthermal", "imaging")

#: What the imaging package may import from the thermal package (with submodules)
IMAGING_MAY_USE = ("shipthermal.geometry", "shipthermal.environment", "shipthermal.raytrace",
                   "shipthermal.optics", "shipthermal.errors", "shipthermal.units",
                   "shipthermal.parameters", "shipthermal.figures", "shipthermal.atomic")

#: Modules of the application layer besides ``shipthermal.app``: the command line's entry
#: and the top-level package, whose exports are the application's front door
APP_ENTRY = ("shipthermal.__main__", "shipthermal")


def module_name(path: Path, root: Path = SRC) -> tuple[str, bool]:
    """Dotted name of a source file, and whether it is a package's ``__init__``."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    is_package = parts[-1] == "__init__"
    if is_package:
        parts = parts[:-1]
    return ".".join(parts), is_package


def import_graph(root: Path = SRC) -> dict:
    """``{module: {imported module: first line}}`` over the project's own modules.

    ``from pkg import name`` counts as an import of ``pkg.name`` when that is a module,
    otherwise of ``pkg``; relative imports are resolved against the importing module.
    """
    files = {}
    for pkg in PACKAGES:
        for path in sorted((root / pkg).rglob("*.py")):
            files[module_name(path, root)[0]] = path
    graph = {}
    for mod, path in files.items():
        _, is_package = module_name(path, root)
        edges: dict = {}
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            targets = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = mod.split(".") if is_package else mod.split(".")[:-1]
                    base = base[:len(base) - (node.level - 1)]
                    pkg = ".".join(base + ([node.module] if node.module else []))
                else:
                    pkg = node.module or ""
                for a in node.names:
                    sub = f"{pkg}.{a.name}"
                    targets.append(sub if sub in files else pkg)
            for t in targets:
                if t.split(".")[0] in PACKAGES:
                    while t not in files and "." in t:     # `import a.b.c` of a name in a.b
                        t = t.rsplit(".", 1)[0]
                    if t != mod:
                        edges.setdefault(t, node.lineno)
        graph[mod] = edges
    return graph


def layer(mod: str) -> str:
    if mod.startswith("imaging"):
        return "imaging"
    if mod == "shipthermal.app" or mod.startswith("shipthermal.app.") or mod in APP_ENTRY:
        return "app"
    return "physics"


def _within(mod: str, prefixes) -> bool:
    return any(mod == p or mod.startswith(p + ".") for p in prefixes)


def layer_violations(graph: dict) -> list[str]:
    rank = {"physics": 0, "imaging": 1, "app": 2}
    out = []
    for mod, edges in graph.items():
        for target, line in edges.items():
            a, b = layer(mod), layer(target)
            if rank[b] > rank[a]:
                out.append(f"{mod} (line {line}) imports {target}: the {a} layer must not "
                           f"use the {b} layer")
            elif a == "imaging" and b == "physics" and not _within(target, IMAGING_MAY_USE):
                out.append(f"{mod} (line {line}) imports {target}: imaging may use only "
                           f"{', '.join(IMAGING_MAY_USE)}")
    return out


def cycles(graph: dict) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, out = {}, {}, set(), [], []
    counter = [0]
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(graph.get(start, ())))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, it = work[-1]
            for nxt in it:
                if nxt not in index:
                    index[nxt] = low[nxt] = counter[0]
                    counter[0] += 1
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(graph.get(nxt, ()))))
                    break
                if nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        m = stack.pop()
                        on_stack.discard(m)
                        comp.append(m)
                        if m == node:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


GRAPH = import_graph()


def test_the_graph_covers_the_layers():
    layers = {layer(m) for m in GRAPH}
    assert layers == {"physics", "imaging", "app"}, layers
    assert "shipthermal.app.scenario.wiring" in GRAPH["shipthermal.app.scenario"]
    assert "shipthermal.app.pipeline" in GRAPH["shipthermal.app.cli"]


OPTICS_MODULES = ("water", "responses", "planck", "sea", "brdf", "quadrature")


def test_the_optics_room_is_shared_by_both_stages():
    """Planck and the bands, spectral responses, water and Fresnel, the sea's emissivity and
    the BRDFs have one home below both stages: ``shipthermal.optics`` imports nothing of the
    physics layer but errors, units and parameters; the thermal stage and the imaging take
    their optics from it; and no other module defines a module-level function of the same
    name."""
    assert layer("shipthermal.optics") == "physics"
    assert _within("shipthermal.optics", IMAGING_MAY_USE)
    rooms = ["shipthermal.optics"] + [f"shipthermal.optics.{m}" for m in OPTICS_MODULES]
    assert all(r in GRAPH for r in rooms), [r for r in rooms if r not in GRAPH]
    allowed = set(rooms) | {"shipthermal", "shipthermal.errors", "shipthermal.units",
                            "shipthermal.parameters"}
    for room in rooms:
        assert set(GRAPH[room]) <= allowed, (room, set(GRAPH[room]) - allowed)
    assert "shipthermal.optics" in GRAPH["shipthermal.environment"]
    assert "shipthermal.optics.planck" in GRAPH["imaging.radiometry"]
    assert "shipthermal.optics.sea" in GRAPH["imaging.radiometry"]
    assert "shipthermal.optics.brdf" in GRAPH["imaging.scene"]
    assert "shipthermal.optics.water" in GRAPH["shipthermal.optics.brdf"]
    optics_functions = set()
    for m in OPTICS_MODULES:
        tree = ast.parse((SRC / "shipthermal" / "optics" / f"{m}.py").read_text())
        optics_functions |= {n.name for n in tree.body if isinstance(n, ast.FunctionDef)
                             and not n.name.startswith("_")}
    assert {"planck_radiance", "band_radiance", "fresnel_reflectance", "cox_munk_brdf",
            "sea_emissivity", "named_band"} <= optics_functions
    twins = []
    for pkg in PACKAGES:
        for path in sorted((SRC / pkg).rglob("*.py")):
            if path.parent == SRC / "shipthermal" / "optics":
                continue
            for n in ast.parse(path.read_text()).body:  # module-level functions
                if isinstance(n, ast.FunctionDef) and n.name in optics_functions:
                    twins.append(f"{path.relative_to(SRC)}: {n.name}")
    assert not twins, twins


def test_the_front_door_is_the_application_layer():
    """``import shipthermal`` re-exports the chain; no lower module may import the package
    itself (it would then depend on the application layer through it)."""
    assert layer("shipthermal") == "app"
    assert "shipthermal.app.chain" in GRAPH["shipthermal"]
    users = sorted(m for m, edges in GRAPH.items() if "shipthermal" in edges)
    assert all(layer(m) == "app" for m in users), users


def test_no_module_imports_a_layer_above_its_own():
    bad = layer_violations(GRAPH)
    assert not bad, "\n".join(bad)


def test_no_import_cycles():
    found = cycles(GRAPH)
    assert not found, "import cycles: " + "; ".join(" <-> ".join(c) for c in found)


# ---- the checks themselves fail on a violation -----------------------------------------
def _tree(tmp_path, files: dict) -> Path:
    for name, text in files.items():
        p = tmp_path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    return tmp_path


@pytest.mark.parametrize("importer, text, expected", [
    ("shipthermal/forcing.py", "def f():\n    from .app.pipeline import x\n",
     "the physics layer must not use the app layer"),
    ("shipthermal/model.py", "import imaging.render\n",
     "the physics layer must not use the imaging layer"),
    ("imaging/render.py", "from shipthermal.app.scenario import Scenario\n",
     "the imaging layer must not use the app layer"),
    ("imaging/render.py", "from shipthermal import diurnal\n",
     "imaging may use only"),
])
def test_a_violation_is_reported(tmp_path, importer, text, expected):
    files = {f"{p}/__init__.py": "" for p in ("shipthermal", "shipthermal/app", "imaging")}
    files |= {"shipthermal/app/pipeline.py": "", "shipthermal/app/scenario.py": "",
              "shipthermal/diurnal.py": "", "shipthermal/forcing.py": "",
              "shipthermal/model.py": "", "imaging/render.py": ""}
    files[importer] = text
    bad = layer_violations(import_graph(_tree(tmp_path, files)))
    assert len(bad) == 1 and expected in bad[0], bad


def test_a_cycle_is_reported(tmp_path):
    files = {"shipthermal/__init__.py": "", "imaging/__init__.py": "",
             "shipthermal/a.py": "from . import b\n",
             "shipthermal/b.py": "def f():\n    from .c import x\n",
             "shipthermal/c.py": "from shipthermal.a import y\n",
             "shipthermal/d.py": "from . import a\n"}
    assert cycles(import_graph(_tree(tmp_path, files))) == [
        ["shipthermal.a", "shipthermal.b", "shipthermal.c"]]


# ---- imports at the top: one inside a function says why -----------------------------------
def _own_import(node) -> bool:
    if isinstance(node, ast.ImportFrom):
        return bool(node.level) or (node.module or "").split(".")[0] in PACKAGES
    if isinstance(node, ast.Import):
        return any(a.name.split(".")[0] in PACKAGES for a in node.names)
    return False


def unexplained_deferred_imports(text: str) -> list[str]:
    """``"line N: source"`` of each import of the project's own modules inside a function
    without a reason: a ``#`` comment on its line(s), on the line directly above it, or
    above the first of the consecutive import statements it stands among. A module's PEP 562
    ``__getattr__`` (the lazy exports of a package) says why once, in a comment before its
    first statement."""
    tree = ast.parse(text)
    lines = text.splitlines()
    comments = {tok.start[0] for tok in tokenize.generate_tokens(io.StringIO(text).readline)
                if tok.type == tokenize.COMMENT}
    said_once = set()
    for fn in tree.body:
        if (isinstance(fn, ast.FunctionDef) and fn.name == "__getattr__"
                and any(fn.lineno < ln < fn.body[0].lineno for ln in comments)):
            said_once |= {id(n) for n in ast.walk(fn)}
    deferred = {id(n) for fn in ast.walk(tree)
                if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef))
                for n in ast.walk(fn) if _own_import(n)} - said_once
    out = []
    for node in ast.walk(tree):
        for field in ("body", "orelse", "finalbody"):
            stmts = getattr(node, field, None)
            block_head = None
            for stmt in stmts if isinstance(stmts, list) else ():
                if not isinstance(stmt, (ast.Import, ast.ImportFrom)):
                    block_head = None
                    continue
                block_head = block_head or stmt
                if id(stmt) not in deferred:
                    continue
                near = set(range(stmt.lineno - 1, stmt.end_lineno + 1))
                near |= set(range(block_head.lineno - 1, block_head.end_lineno + 1))
                if not near & comments:
                    out.append(f"line {stmt.lineno}: {lines[stmt.lineno - 1].strip()}")
    return sorted(out, key=lambda s: int(s.split(":")[0][5:]))


#: Imports inside functions that cost nothing at start-up and are still to move to their
#: module's top, by module and statement (an entry that no longer matches fails the test)
NOT_YET_AT_THE_TOP: set = set()


def test_deferred_imports_say_why():
    """Every own-module import inside a function carries its reason (what it keeps out of
    the start-up, or the test that forbids it at load)."""
    bad, pending = [], set()
    for pkg in PACKAGES:
        for path in sorted((SRC / pkg).rglob("*.py")):
            mod = module_name(path)[0]
            for found in unexplained_deferred_imports(path.read_text(encoding="utf-8")):
                key = (mod, found.split(": ", 1)[1])
                if key in NOT_YET_AT_THE_TOP:
                    pending.add(key)
                else:
                    bad.append(f"{mod} {found}")
    assert not bad, "imports inside functions without a reason:\n" + "\n".join(bad)
    assert pending == NOT_YET_AT_THE_TOP, f"moved already: {NOT_YET_AT_THE_TOP - pending}"


def test_an_unexplained_deferred_import_is_reported():
    text = """\
import os                              # at the top: not checked


def reasons():
    from .a import b                   # deferred: on the line
    # deferred: above a block of imports
    import json

    from shipthermal.c import d
    from . import e
    try:    # deferred: on the try above
        from imaging.f import g
    except ImportError:
        g = None
    return b, json, d, e, g


def no_reason():
    x = 1
    from imaging.render import SceneRenderer
    return x, SceneRenderer


def not_own():
    import numpy as np
    return np


def a_string_is_no_comment():
    s = "# not a comment"
    from .h import (i,
                    j)
    return s, i, j


def __getattr__(name):
    # PEP 562: the exports are imported on first use (said once)
    if name == "k":
        from . import k

        return k
    raise AttributeError(name)
"""
    assert unexplained_deferred_imports(text) == [
        "line 20: from imaging.render import SceneRenderer", "line 31: from .h import (i,"]


# ---- rooms with one job: sizes ------------------------------------------------------------
#: A module's lines at most, and a function's (its ``def`` to its last line, docstring included)
MODULE_LINES, FUNCTION_LINES = 800, 120
#: Functions allowed to be longer, by name: the command line's argument parser (one
#: declaration per option, read top to bottom). numba kernels (decorated ``@njit``, e.g.
#: ``shipthermal.raytrace._bvh.build_bvh``) are excepted too: splitting one costs a call
#: boundary in the compiled loop.
LONG_FUNCTIONS = ("shipthermal.app.cli.build_parser",)


def _is_numba_kernel(node) -> bool:
    for d in node.decorator_list:
        f = d.func if isinstance(d, ast.Call) else d
        name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
        if name in ("njit", "jit"):
            return True
    return False


def size_violations(root: Path = SRC) -> list[str]:
    out = []
    for pkg in PACKAGES:
        for path in sorted((root / pkg).rglob("*.py")):
            mod = module_name(path, root)[0]
            text = path.read_text(encoding="utf-8")
            if text.count("\n") > MODULE_LINES:
                out.append(f"{mod}: {text.count(chr(10))} lines (at most {MODULE_LINES})")
            for node in ast.walk(ast.parse(text, str(path))):
                if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    continue
                n = node.end_lineno - node.lineno + 1
                if (n > FUNCTION_LINES and f"{mod}.{node.name}" not in LONG_FUNCTIONS
                        and not _is_numba_kernel(node)):
                    out.append(f"{mod}.{node.name} (line {node.lineno}): {n} lines "
                               f"(at most {FUNCTION_LINES})")
    return out


def test_rooms_and_functions_stay_small():
    """No module over 800 lines, no function over 120 (the named exceptions aside): a room
    that grows past this is doing more than one job."""
    bad = size_violations()
    assert not bad, "\n".join(bad)


def test_a_long_module_or_function_is_reported(tmp_path):
    long_fn = "def f():\n" + "    x = 1\n" * FUNCTION_LINES
    kernel = "from numba import njit\n\n\n@njit(cache=True)\ndef k():\n" + "    x = 1\n" * 200
    files = {"shipthermal/__init__.py": "", "imaging/__init__.py": "",
             "shipthermal/a.py": long_fn, "shipthermal/b.py": "x = 1\n" * (MODULE_LINES + 1),
             "shipthermal/c.py": kernel}
    bad = size_violations(_tree(tmp_path, files))
    assert len(bad) == 2, bad
    assert bad[0].startswith("shipthermal.a.f (line 1)") and "shipthermal.b:" in bad[1]
