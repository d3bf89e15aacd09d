"""The notched beam in 3D on tiny beams: an elastic simple-cubic lattice beam against beam
theory, the rig's statics, the notch carved through the thickness, and one test run."""

import numpy as np
import pytest

from rockcal.dem3d.laws import bond_springs
from rockcal.labtests.bending import Beam, notched_beam_3d, simulate_bending
from rockcal.labtests.kic import senb_kic
from rockcal.labtests.rig import rig_for
from rockcal.materials.parallel_bond import laws_3d, make_params
from rockcal.specimens3d.specimen import Specimen3D, notched

R = 0.5e-3
GAP = 0.02  # the lattice's spheres 2 R (1 + GAP) apart: their contacts stay open, the bonds alone bear
# bonds that do not break; frictionless pins, the free rollers beam theory takes (friction at the
# supports holds the bottom fibre back and stiffens the beam by 6 %)
STRONG = make_params({"E_c": 10, "Ebar_c": 30, "kn_ks": 2.0, "knbar_ksbar": 1.0, "sigma_c": 1e5,
                      "tau_c": 1e5, "mu": 0.0})


def lattice_beam(nx: int, ny: int, nz: int) -> Specimen3D:
    """nx x ny x nz spheres of radius R on a simple-cubic lattice, neighbours bonded."""
    d = 2 * R * (1 + GAP)
    index = np.array([(i, j, k) for k in range(nz) for j in range(ny) for i in range(nx)])
    flat = {tuple(v): n for n, v in enumerate(index)}
    bonds = [(flat[tuple(v)], flat[tuple(v + step)]) for v in index for step in np.eye(3, dtype=int)
             if tuple(v + step) in flat]
    return Specimen3D(index * d + R, np.full(len(index), R), np.array(bonds), "cuboid",
                      (nx * d, ny * d, nz * d), "simple cubic", np.full((len(bonds), 2), 0.5))


def test_an_elastic_lattice_beam_bends_as_timoshenko_says_and_its_supports_share_the_load():
    """Midspan deflection of the neutral axis against the supports' sections, at rest under the
    pin: P S^3 / (48 EI) + P S / (4 kappa G A). The lattice's EI is its x-chains' (bond axial
    springs at their heights, plus each bond's bending spring: sum k_n d z^2 + N k_b d); its
    shear stiffness G A is the bonds' shear springs over the chains, k_s N d, with
    Timoshenko's kappa 5/6 (nu 0). Spans 8 depths: shear adds 2 % of the deflection."""
    nx, ny, nz = 45, 3, 5
    beam = lattice_beam(nx, ny, nz)
    d = 2 * R * (1 + GAP)
    middle, half_span = beam.size_m[0] / 2, 4 * beam.size_m[2]
    pins = rig_for(beam).pins(beam, STRONG, middle, (middle - half_span, middle + half_span), 2e-3, 1.5e-8)
    state = pins.state
    state.scale_density()
    start = state.particles.pos[:beam.n_spheres].copy()
    pins.move(1.0)
    state.advance(4000)  # 60 um down (the first 20 um close the gaps to the pins), then at rest
    pins.move(0.0)
    state.advance(6000)
    reactions, load = pins.reactions(), pins.load()
    moved = state.particles.pos[:beam.n_spheres, 2] - start[:, 2]
    x, z = start[:, 0], start[:, 2]
    core = np.abs(z - beam.size_m[2] / 2) < d  # the two layers about the neutral axis
    column = lambda at: core & (np.abs(x - at) < 0.6 * d)
    support = 0.5 * (moved[column(middle - half_span)].mean() + moved[column(middle + half_span)].mean())
    deflection = support - moved[column(middle)].mean()
    kbn, kbs, _, kbb = bond_springs(R, 2 * R, laws_3d(STRONG))
    heights = (np.arange(nz) - (nz - 1) / 2) * d
    chains = ny * nz
    EI = kbn * d * ny * np.sum(heights**2) + chains * kbb * d
    GA = kbs * chains * d
    span = 2 * half_span
    expected = load * span**3 / (48 * EI) + load * span / (4 * 5 / 6 * GA)
    assert deflection == pytest.approx(expected, rel=0.03)
    assert reactions[0] == pytest.approx(reactions[1], rel=0.01)
    assert sum(reactions) == pytest.approx(state.particles.force[pins.is_pin, 2].sum(), rel=0.01)
