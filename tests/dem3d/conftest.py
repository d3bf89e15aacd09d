"""Specimens shared by the 3D tests: one small genesis per test process."""

import pytest

from rockcal.specimens3d.specimen import carve_cylinder, random_specimen


@pytest.fixture(scope="session")
def small_cuboid():
    """A 10 x 10 x 20 mm cuboid packed by the 3D genesis' defaults at R_min 0.6 mm."""
    return random_specimen("cuboid", 10.0, 20.0, 0.6, seed=3, cache=False)


@pytest.fixture(scope="session")
def small_cylinder(small_cuboid):
    """The 10 x 20 mm cylinder carved from `small_cuboid`."""
    return carve_cylinder(small_cuboid)
