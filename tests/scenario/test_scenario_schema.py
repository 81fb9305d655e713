"""Keep the scenario's schema in sync with its documentation and its examples."""

import dataclasses
import re
import tomllib
from pathlib import Path

import pytest

from shipthermal.app import scenario as S

ROOT = Path(__file__).resolve().parents[2]


# ---- schema ---------------------------------------------------------------------------------
def _all_fields(cls, prefix=""):
    for f in dataclasses.fields(cls):
        if f.metadata.get("internal"):
            continue
        spec = f.metadata["spec"]
        key = f"{prefix}.{f.name}" if prefix else f.name
        yield key, spec
        if spec.kind == "section":
            yield from _all_fields(spec.cls, key)
        if spec.kind == "layups":
            yield from _all_fields(S.LayerSpec, key + ".<part>[i]")


def test_schema_lists_every_field():
    keys = S.schema_keys()
    table = S.schema_markdown()
    fields = list(_all_fields(S.Scenario))
    assert len(fields) > 90
    for key, spec in fields:
        shown = f"[{key}]" if spec.kind == "section" else key
        assert any(k == shown or k.startswith(shown + ".<") for k in keys), key
        assert spec.doc, f"{key} has no description"
    # one table row per key, each row has 6 cells
    rows = [l for l in table.splitlines()[2:]]
    assert len(rows) == len(keys)
    assert all(l.count(" | ") >= 5 for l in rows)


def test_docs_table_is_current():
    text = (ROOT / "docs" / "SCENARIO.md").read_text(encoding="utf-8")
    m = re.search(r"<!-- schema:begin -->\n(.*)<!-- schema:end -->", text, re.S)
    assert m, "docs/SCENARIO.md lost its schema markers"
    assert m.group(1) == S.schema_markdown(), \
        "regenerate: shipthermal schema (between the markers)"


def _flatten(d, prefix=""):
    for k, v in d.items():
        key = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            yield from _flatten(v, key)
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                yield from _flatten(item, key + "[i]")
        else:
            yield key


def _pattern(key):
    out = re.escape(key).replace(re.escape("<part>"), r"[A-Za-z_]+")
    return re.compile("^" + out.replace(re.escape("<band>"), r"[0-9.\-]+") + "$")


@pytest.mark.parametrize("season", S.SEASONS)
def test_example_keys_are_documented(season):
    # every key in the example, and every key the commented alternatives show, is in the
    # schema (commented lines are un-commented to check them)
    text = S.example_path(season).read_text(encoding="utf-8")
    patterns = [_pattern(k.replace("<part>[i]", "<part>[i]")) for k in S.schema_keys()]
    raw = tomllib.loads(text)
    for key in _flatten(raw):
        key = re.sub(r"\.(\w+)\[i\]", r".\1[i]", key)
        assert any(p.match(key) for p in patterns), key
    section, checked = "", 0
    for line in text.splitlines():
        header = re.match(r"^(?:# )?\[([a-z_.]+)\]", line)
        if header:                       # a real or a commented-out [section]
            section = header.group(1)
            continue
        if not re.match(r"^# [a-z_]+ = ", line):
            continue
        checked += 1
        key = line[2:].split("=")[0].strip()
        full = f"{section}.{key}" if section else key
        assert any(p.match(full) or p.match(full + ".hull") or p.match(full + ".deck")
                   or p.match(full + "[i].material") for p in patterns), full
    assert checked >= 15   # the alternatives are really looked at


def test_package_ships_the_examples():
    for season in S.SEASONS:
        p = S.example_path(season)
        assert p.is_file() and p.parent.name == "scenarios"
