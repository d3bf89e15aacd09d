"""The notched beam in 3D on tiny beams: an elastic simple-cubic lattice beam against beam
theory, the rig's statics, the notch carved through the thickness, and one test run."""

import numpy as np
import pytest

from rockcal.dem3d.laws import bond_springs
from rockcal.labtests.bending import Beam, simulate_bending
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


def test_the_notch_is_carved_through_the_thickness_or_cut(small_cuboid):
    """`conftest.small_cuboid` (10 x 10 x 20 mm) notched 1 mm wide and 6 mm up at x = 5 mm: no
    sphere left overlapping the slot; a cut of width 0 keeps every sphere and removes just the
    bonds across the plane below 6 mm."""
    carved = notched(small_cuboid, 5e-3, 1e-3, 6e-3)
    x, z, r = carved.pos[:, 0], carved.pos[:, 2], carved.radius
    assert not ((np.abs(x - 5e-3) < 0.5e-3 + r) & (z < 6e-3)).any()  # none beside the slot reaches into it
    assert not ((np.abs(x - 5e-3) < 0.5e-3) & (z - r < 6e-3)).any()  # nor any above its end
    assert 0 < small_cuboid.n_spheres - carved.n_spheres < 0.2 * small_cuboid.n_spheres
    cut = notched(small_cuboid, 5e-3, 0.0, 6e-3)
    assert cut.n_spheres == small_cuboid.n_spheres and 0 < len(small_cuboid.bonds) - len(cut.bonds)
    i, j = cut.bonds.T
    crossing = (cut.pos[i, 0] - 5e-3) * (cut.pos[j, 0] - 5e-3) < 0
    assert (np.minimum(cut.pos[i, 2], cut.pos[j, 2])[crossing] > 5e-3).all()


def test_a_3d_beam_reads_k_ic_from_its_peak_over_its_thickness():
    """A notched lattice beam run to failure (at 10 x the pin's speed: the formula, not the
    quasi-static peak, is checked here): K_IC is the beam formula at P_max in N over the beam's
    thickness, reported in kN, and the crack starts at the notch."""
    beam = Beam(45 * 1.02, 5 * 1.02, 1.5, 0.0, 8 * 5 * 1.02, pin_radius_mm=2.0)
    lattice = lattice_beam(45, 3, 5)
    specimen = notched(lattice, lattice.size_m[0] / 2, 0.0, 1.5e-3)
    weak = make_params({"E_c": 10, "Ebar_c": 30, "kn_ks": 2.0, "sigma_c": 10, "tau_c": 20, "sigma_c_cv": 0,
                        "tau_c_cv": 0})
    result = simulate_bending(weak, specimen, beam, rate_factor=10.0, stop_fraction=0.9)
    thickness = lattice.size_m[1]
    assert result.beam.thickness_mm == pytest.approx(1e3 * thickness)
    assert result.K_IC_MPa_sqrt_m * 1e6 == pytest.approx(senb_kic(1e3 * result.P_max_kN, 1e-3 * beam.span_mm,
                                                                  1e-3 * beam.height_mm, 1.5e-3, thickness))
    assert result.n_broken_tension > 0 and result.first_break_xy.shape[1] == 3
    assert np.abs(result.first_break_xy[:, 0] - lattice.size_m[0] / 2).max() < 2 * 2 * R
