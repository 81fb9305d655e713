"""Fixtures of the command-line tests (helpers: cli_helpers.py)."""

import pytest
from cli_helpers import write_tiny

from shipthermal.app.cli import main


@pytest.fixture(scope="session")
def imaged_run(tmp_path_factory):
    """A finished tiny run with its imaging stage and report (run through the CLI)."""
    d = tmp_path_factory.mktemp("imaged")
    sc = write_tiny(d, formats=("csv", "json", "png", "html", "vtkhdf"))
    out = d / "runs" / "tiny"
    assert main(["-q", "run", str(sc), "--out", str(out), "--image"]) == 0
    return out
