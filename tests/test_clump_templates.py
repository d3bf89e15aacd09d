"""Clump templates: the random pebble cloud ("cloud"), drawn reproducibly from a seed, one body
of overlapping pebbles usable as a grain shape; and bad templates refused in one line naming
the field: no pebble, pebbles that are not one body, a clump the specimen cannot hold."""

import numpy as np
import pytest

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.materials.clump_templates import (CLOUD_PEBBLES, CLOUD_SEED, GRAIN_SHAPES, MAX_EXTENT, _one_body,
                                         from_pebbles, pebble_cloud, template)
from rockcal.dem.clumps import union_properties
from rockcal.specimens.specimen import random_packing
from rockcal.errors import InputError


def test_the_cloud_is_drawn_from_its_seed_the_same_every_time():
    shape = template("cloud")
    again = pebble_cloud(CLOUD_SEED)
    np.testing.assert_array_equal(shape.offsets, again.offsets)
    np.testing.assert_array_equal(shape.radii, again.radii)
    other = pebble_cloud(CLOUD_SEED + 1)
    assert not np.array_equal(other.radii, shape.radii)


@pytest.mark.parametrize("seed", range(20))
@pytest.mark.parametrize("n", [2, CLOUD_PEBBLES, 7])
def test_a_cloud_is_one_body_of_random_pebbles_of_unit_equivalent_radius(seed, n):
    shape = pebble_cloud(seed, n)
    assert shape.n_pebbles == n and len(set(shape.radii)) == n  # random radii, each its own
    assert _one_body(shape.offsets, shape.radii)
    area, centroid, _ = union_properties(shape.offsets, shape.radii)
    assert area == pytest.approx(np.pi, rel=1e-12)
    np.testing.assert_allclose(centroid, 0.0, atol=1e-12)


def test_the_cloud_is_a_grain_shape():
    assert "cloud" in GRAIN_SHAPES
    assert SpecimenSettings(grain_shape="cloud").grain_shape == "cloud"


def test_a_cloud_specimen_is_made_of_whole_clumps():
    spec = random_packing(6.0, 6.0, 0.5, 1.25, seed=1, grain_shape="cloud", cache=False)
    assert spec.n_particles == CLOUD_PEBBLES * spec.n_grains
    assert (np.bincount(spec.clump_of) == CLOUD_PEBBLES).all()
    assert (spec.clump_of[spec.bonds[:, 0]] != spec.clump_of[spec.bonds[:, 1]]).all()
    assert "cloud clumps" in spec.label


@pytest.mark.parametrize("name", GRAIN_SHAPES)
def test_every_template_fits_the_smallest_specimen_rockcal_makes(name):
    """check_geometry asks for 4 grain diameters on each side (8 largest radii): a template
    reaching less than MAX_EXTENT equivalent radii from its centroid, turned any way, fits it."""
    assert template(name).extent < MAX_EXTENT


@pytest.mark.parametrize("centres, radii, problem", [
    (np.empty((0, 2)), [], "needs one or more pebbles"),
    ([[0, 0], [3, 0]], [1, 1], "must overlap into one body"),
    ([[0, 0], [1.5, 0], [10, 0], [11, 0]], [1, 1, 1, 1], "must overlap into one body"),
    ([[0, 0]], [-1], "radius > 0"),
    ([[0, np.nan]], [1], "finite centre"),
])
def test_a_bad_template_is_refused_in_one_line_naming_the_field(centres, radii, problem):
    with pytest.raises(InputError) as refused:
        from_pebbles("mine", centres, radii)
    assert str(refused.value).startswith("grain_shape: template 'mine'") and problem in str(refused.value)
    assert "\n" not in str(refused.value)


@pytest.mark.parametrize("n", [0, -1, 2.5, True])
def test_a_cloud_of_no_pebble_is_refused(n):
    with pytest.raises(InputError, match="^grain_shape: template 'cloud' needs one or more pebbles"):
        pebble_cloud(1, n)
