"""Fixtures shared by the scenario tests that inspect what each stage receives."""

import numpy as np
import pytest


@pytest.fixture(scope="module")
def background():
    """A 100 x 100 port of 30 m pixels: water in the west half, land in the east, 290 K."""
    from imaging.scene import GriddedBackground

    n = 100
    cm = np.full((n, n), 3, dtype=np.uint8)
    cm[:, : n // 2] = 1
    return GriddedBackground(cm, np.array([0.0]), np.full((1, n, n), 290.0), 30.0)


@pytest.fixture(scope="module")
def ship():
    """The ship every case hands the imaging (the thermal stage's ship in a real run): the
    same one for every case, so what is compared is what the scenario hands the imaging."""
    from shipthermal.geometry import patrol_boat

    return patrol_boat(edge_length=5.6)
