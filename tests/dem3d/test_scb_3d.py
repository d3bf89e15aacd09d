"""The semi-circular bend in 3D on an elastic lattice half disk: its compliance grows with the
notch as ISRM's K formula says."""

from dataclasses import replace

import numpy as np
import pytest

from rockcal.dem3d.laws import bond_springs
from rockcal.labtests.kic import scb_y
from rockcal.labtests.rig import rig_for
from rockcal.materials.parallel_bond import laws_3d
from rockcal.specimens3d.specimen import carve_half_disk, notched
from test_bending_3d import GAP, R, STRONG, lattice_beam

D = 2 * R * (1 + GAP)  # the lattice's spacing
LAYERS = 10  # the half disk's radius in spheres
SPAN_RATIO = 0.8


def lattice_half_disk(notch_layers: int):
    """A half disk of radius LAYERS x D cut from a simple-cubic lattice 2 spheres thick,
    centred in its box, its notch a cut through `notch_layers` layers of bonds."""
    lattice = lattice_beam(2 * LAYERS, 2, LAYERS)
    disk = carve_half_disk(replace(lattice, pos=lattice.pos + (D / 2 - R)))
    return notched(disk, LAYERS * D, 0.0, notch_layers * D)


def compliance(specimen) -> float:
    """The pin's travel per newton of load: the slope of the load against the travel over the
    second half of a slow push (at half this speed the compliance moves by 0.3 %)."""
    middle = LAYERS * D
    half_span = SPAN_RATIO * middle
    pins = rig_for(specimen).pins(specimen, STRONG, middle, (middle - half_span, middle + half_span), 2e-3, 3e-8)
    pins.state.scale_density()
    pins.move(1.0)
    readings = []
    for _ in range(25):
        pins.state.advance(100)
        readings.append((pins.displacement_m(), pins.load()))
    travel, load = np.array(readings[12:]).T
    assert load[0] > 0 and pins.state.n_broken() == 0
    return 1.0 / np.polyfit(travel, load, 1)[0]


def test_an_elastic_half_disk_softens_with_its_notch_as_its_k_formula_says():
    """The compliance method: dC/da = 2 B K^2 / (E P^2) = Y'^2 pi a / (2 R^2 B E) with ISRM's
    K = Y' P sqrt(pi a) / (2 R B), integrated from a/R 0.4 to 0.6; what the pins' own contacts
    add to C is the same on both notches. The bonded simple-cubic lattice with k_s = k_n is
    isotropic, E = k_n / D and nu 0 (`test_lattice_3d`), so plane stress and plane strain agree.
    A cut through k layers of bonds is a crack k D long to within a fraction of D: a quarter of
    D on both notches moves the integral by 15 % (the lattice reads 11 % below it)."""
    kbn, kbs, _, _ = bond_springs(R, 2 * R, laws_3d(STRONG))
    assert kbs == pytest.approx(kbn)
    modulus, radius, thickness = kbn / D, LAYERS * D, 2 * D
    a = np.linspace(0.4, 0.6, 201) * radius
    expected = np.trapezoid(scb_y(a / radius, SPAN_RATIO) ** 2 * np.pi * a, a) / (2 * radius**2 * thickness * modulus)
    short, long = (compliance(lattice_half_disk(n)) for n in (4, 6))
    assert long - short == pytest.approx(expected, rel=0.15)
