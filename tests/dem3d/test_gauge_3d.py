"""The 3D gauges (`rockcal.labtests.rig.gauge_3d`) read what their definition says, to the bit: the
interquartile mean of displacements, computed with numpy's own (pairwise) sums."""

from types import SimpleNamespace

import numpy as np
import pytest

from rockcal.labtests.rig.gauge_3d import Gauge3D, central_mean, faces
from rockcal.specimens3d.specimen import Specimen3D


def interquartile_mean(values):
    values = np.sort(values)
    quarter = len(values) // 4
    return values[quarter:len(values) - quarter].mean()


def cloud(shape: str, n: int = 900, seed: int = 3) -> Specimen3D:
    """Spheres in a 10 x 10 x 20 mm prism, or the cylinder inside it."""
    rng = np.random.default_rng(seed)
    pos = rng.uniform(0, 1, (n, 3)) * (10e-3, 10e-3, 20e-3)
    if shape == "cylinder":
        pos = pos[np.hypot(pos[:, 0] - 5e-3, pos[:, 1] - 5e-3) < 4.5e-3]
    radius = rng.uniform(0.4e-3, 0.6e-3, len(pos))
    return Specimen3D(pos=pos, radius=radius, bonds=np.empty((0, 2), np.int64), shape=shape,
                      size_m=(10e-3, 10e-3, 20e-3), label="cloud", bond_draws=np.empty((0, 2)))


def test_compiled_interquartile_mean_is_numpys_to_the_bit():
    """Lengths about numpy's pairwise blocks (8 and 128 values) and beyond."""
    rng = np.random.default_rng(0)
    for n in [1, 2, 7, 8, 9, 31, 32, 33, 255, 256, 257, 515, 1000, 2001, 5003]:
        values = rng.normal(0, 1, n) * 10.0 ** rng.uniform(-6, 3)
        assert central_mean(values) == interquartile_mean(values)


@pytest.mark.parametrize("shape", ["cylinder", "cuboid"])
def test_strains_are_their_definition_to_the_bit(shape):
    """After random displacements: the axial strain from the end faces' displacements, the
    lateral strain from the side spheres' radial strains about the drifted axis (a cylinder)
    or from the two widths (a prism)."""
    specimen = cloud(shape)
    pos = specimen.pos.copy()
    gauge = Gauge3D(specimen, SimpleNamespace(particles=SimpleNamespace(pos=pos)))
    start = pos.copy()
    pos += np.random.default_rng(1).normal(0, 1e-6, pos.shape)
    moved = pos - start
    sets = faces(specimen)

    def central(array, name, a):
        return interquartile_mean(array[sets[name], a])

    height = central(start, "top", 2) - central(start, "bottom", 2)
    axial = (central(moved, "bottom", 2) - central(moved, "top", 2)) / height
    if shape == "cylinder":
        axis = 0.5 * (start[:, :2].min(axis=0) + start[:, :2].max(axis=0))
        r0 = np.hypot(*(start[sets["side"], :2] - axis).T)
        drifted = axis + moved[:, :2].mean(axis=0)
        r = np.hypot(*(pos[sets["side"], :2] - drifted).T)
        lateral = interquartile_mean((r - r0) / r0)
    else:
        lateral = np.mean([(central(moved, hi, a) - central(moved, lo, a))
                           / (central(start, hi, a) - central(start, lo, a))
                           for a, (lo, hi) in enumerate((("left", "right"), ("front", "back")))])
    assert gauge.strains() == (axial, lateral)
