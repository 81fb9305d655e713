"""Fixtures of the whole suite.

Repaired ship surfaces are cached (:mod:`shipthermal.geometry.repair_cache`); the tests
use a cache of their own so that they neither read nor fill the user's.
"""

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_repair_cache(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    mp.setenv("SHIPTHERMAL_CACHE", str(tmp_path_factory.mktemp("repair-cache")))
    yield
    mp.undo()
