"""The flat-jointed material as FISHTank assigns it (`rockcal.materials.flat_joint`): its
parameters' validation, the microstructure realised on packings, reproducibly by seed, and the
reduction of λ where two faces of a grain would overlap."""

import math

import numpy as np
import pytest

from rockcal.dem import flatjoint as fj
from rockcal.dem.neighbours import pair_gaps
from rockcal.specimens.specimen import SHIPPED_DIR, hexagonal
from rockcal.errors import InputError
from rockcal.materials import flat_joint as fjm

MPA = 1e6


@pytest.mark.parametrize("values, field", [
    ({"fjm_B_frac": -0.1}, "fjm_B_frac"),
    ({"fjm_G_frac": -0.2}, "fjm_G_frac"),
    ({"fjm_B_frac": 1.2, "fjm_G_frac": 0.0}, "fjm_B_frac"),
    ({"fjm_B_frac": 0.7, "fjm_G_frac": 0.4}, "fjm_G_frac"),
    ({"fj_nr": 0}, "fj_nr"),
    ({"fj_nr": 2.5}, "fj_nr"),
    ({"fj_fa": 90.0}, "fj_fa"),
    ({"fj_fa": -1.0}, "fj_fa"),
    ({"fjm_G_m": -0.01}, "fjm_G_m"),
    ({"fjm_rmulCode": 3}, "fjm_rmulCode"),
    ({"fj_ten_sd": 5.0, "fj_ten_cv": 0.1}, "fj_ten_cv"),
    ({"fj_emod": float("nan")}, "fj_emod"),
    ({"pb_ten": 10.0}, "pb_ten"),
])
def test_bad_parameters_name_their_field(values, field):
    with pytest.raises(InputError) as err:
        fjm.make_flatjoint_params(values)
    assert err.value.field == field


def test_parameters_take_pfc_names_and_default_the_linear_group_to_the_flat_joints():
    p = fjm.make_flatjoint_params({"fj_nr": 3.0, "fjm_B_frac": 0.7, "fjm_G_frac": 0.3,
                                   "fj_emod": 40.0, "fj_kratio": 2.5, "fj_fric": 0.6})
    assert p.fj_nr == 3 and isinstance(p.fj_nr, int)
    assert p.slit_fraction == 0.0
    assert (p.lnm_emod, p.lnm_krat, p.lnm_fric) == (40.0, 2.5, 0.6)
    assert fjm.make_flatjoint_params({"lnm_emod": 10.0}).lnm_emod == 10.0


def lattice():
    spec = hexagonal(6.0, 6.0, 0.25)
    return spec.pos, spec.radius


def shipped_packing():
    data = np.load(SHIPPED_DIR / "3e43361a9e8e85ca.npz")  # 3253 grains, R_min 0.48 mm
    return data["pos"], data["radius"]


@pytest.mark.parametrize("b, g", [(0.6, 0.15), (1.0, 0.0), (0.0, 0.3), (0.25, 0.75)])
def test_fractions_are_realised_on_a_packing(b, g):
    """Of the n flat joints of a real packing, round(B n) are bonded, round(G n) gapped, the
    rest slit: every element of a bonded joint bonded, of the others unbonded; only gapped
    joints have an initial gap."""
    pos, radius = shipped_packing()
    params = fjm.make_flatjoint_params({"fjm_B_frac": b, "fjm_G_frac": g, "fjm_G_m": 0.01,
                                        "fjm_G_sd": 0.003, "fj_nr": 3})
    mat = fjm.assign_flatjointed(pos, radius, params, 0.1 * radius.min(), seed=4)
    n = len(mat.pairs)
    assert n > 5000
    fractions = mat.fractions()
    for name, target in (("bonded", b), ("gapped", g), ("slit", 1 - b - g)):
        assert abs(fractions[name] - target) <= 1.0 / n
    joints = mat.joints()
    bonded = mat.kind == fjm.BONDED
    assert np.all(joints.state[bonded] == fj.BONDED) and np.all(joints.state[~bonded] == fj.UNBONDED)
    assert np.all(mat.gap0[mat.kind != fjm.GAPPED] == 0.0)
    assert np.all(joints.table[fj.GAP] == mat.gap0)
    if g:
        gaps = mat.gap0[mat.kind == fjm.GAPPED] / 1e-3
        assert np.all(gaps >= 0.0)
        assert abs(gaps.mean() - 0.01) < 4 * 0.003 / np.sqrt(len(gaps))
        assert gaps.std() == pytest.approx(0.003, rel=0.1)


def test_flat_joints_at_pairs_within_the_installation_gap_linear_contacts_elsewhere():
    """Flat joints exactly at the grain pairs whose gap is <= the installation gap; their k_n is
    E*/(R_i + R_j), k_s = k_n/κ*; the other pairs keep the linear group's constants."""
    pos, radius = shipped_packing()
    igap = 0.1 * radius.min()
    params = fjm.make_flatjoint_params({"fj_emod": 30.0, "fj_kratio": 2.0, "lnm_emod": 12.0,
                                        "lnm_krat": 1.5, "lnm_fric": 0.3})
    mat = fjm.assign_flatjointed(pos, radius, params, igap)
    pi, pj, gap = pair_gaps(pos, radius, 3 * igap)
    near = {(int(i), int(j)): g for i, j, g in zip(pi, pj, gap)}
    joined = {tuple(map(int, p)) for p in mat.pairs}
    assert joined == {p for p, g in near.items() if g <= igap * (1 + 1e-6)}
    assert len(near) > len(joined) > 0
    i, j = mat.pairs.T
    np.testing.assert_allclose(mat.kn, 30e9 / (radius[i] + radius[j]), rtol=1e-12)
    np.testing.assert_allclose(mat.ks, mat.kn / 2.0, rtol=1e-12)
    assert (mat.lnm_emod, mat.lnm_krat, mat.lnm_fric) == (12e9, 1.5, 0.3)


def test_the_microstructure_is_reproducible_by_seed_and_keeps_its_ranks():
    """One seed, one material; another seed, another choice of bonded joints; raising the bonded
    fraction only adds bonded joints (a joint keeps its rank whatever the fractions)."""
    pos, radius = lattice()
    params = fjm.make_flatjoint_params({"fjm_B_frac": 0.5, "fjm_G_frac": 0.2, "fjm_G_m": 0.01,
                                        "fjm_G_sd": 0.002, "fj_ten_sd": 8.0, "fj_coh_sd": 20.0})
    a = fjm.assign_flatjointed(pos, radius, params, 0.0, seed=7)
    b = fjm.assign_flatjointed(pos, radius, params, 0.0, seed=7)
    c = fjm.assign_flatjointed(pos, radius, params, 0.0, seed=8)
    for name in ("kind", "gap0", "ten", "coh"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.kind, c.kind) and not np.array_equal(a.ten, c.ten)
    more = fjm.assign_flatjointed(pos, radius, params.model_copy(update={"fjm_B_frac": 0.6}),
                                  0.0, seed=7)
    assert np.all(more.kind[a.kind == fjm.BONDED] == fjm.BONDED)
    assert np.count_nonzero(more.kind == fjm.BONDED) > np.count_nonzero(a.kind == fjm.BONDED)


def test_strengths_follow_their_truncated_normal_distributions():
    """Tensile strength and cohesion per joint: means and sds within sampling error, none
    negative (FISHTank redraws negative values), all elements of a joint alike (fj_ten and
    fj_coh are properties of the contact)."""
    pos, radius = shipped_packing()
    params = fjm.make_flatjoint_params({"fj_ten": 30.0, "fj_ten_cv": 0.25, "fj_coh": 10.0,
                                        "fj_coh_sd": 8.0, "fj_nr": 4})
    mat = fjm.assign_flatjointed(pos, radius, params, 0.1 * radius.min(), seed=3)
    n = len(mat.pairs)
    ten = mat.ten[:, 0] / MPA
    assert abs(ten.mean() - 30.0) < 4 * 7.5 / np.sqrt(n)
    assert ten.std() == pytest.approx(7.5, rel=0.05)
    assert np.all(mat.ten == mat.ten[:, :1]) and np.all(mat.coh == mat.coh[:, :1])
    coh = mat.coh[:, 0] / MPA
    assert coh.min() >= 0.0
    # the normal (10, 8) truncated at zero: its mean
    a = 10.0 / 8.0
    truncated_mean = 10.0 + 8.0 * math.exp(-a * a / 2) / math.sqrt(2 * math.pi) / (0.5 * (1 + math.erf(a / math.sqrt(2))))
    assert abs(coh.mean() - truncated_mean) < 4 * 8.0 / np.sqrt(n)


# --- λ reduction ---------------------------------------------------------------------------

def three_grains(beta_deg, gap_fraction):
    """A grain of radius R with two neighbours of radius R at angle β, across a gap g = f R."""
    r = 1e-3
    d = (2 + gap_fraction) * r
    b = math.radians(beta_deg)
    pos = np.array([[0.0, 0.0], [d, 0.0], [d * math.cos(b), d * math.sin(b)]])
    return pos, np.full(3, r)


@pytest.mark.parametrize("code", [1, 2])
@pytest.mark.parametrize("gap_fraction", [0.0, 0.1])
def test_lambda_is_reduced_until_the_faces_of_a_grain_do_not_overlap(code, gap_fraction):
    """Two joints of a grain at β = 80°, their faces at l = R + g/2 from its centre (the contact
    point is mid-gap): each face spans atan(λ R / l), so λ is multiplied by 0.99 until
    2 atan(λ R / l) <= 80°, by either code."""
    pos, radius = three_grains(80.0, gap_fraction)
    params = fjm.make_flatjoint_params({"fjm_rmulCode": code})
    mat = fjm.assign_flatjointed(pos, radius, params, 0.2e-3)
    assert len(mat.pairs) == 2
    k = 0
    while 2 * math.atan(0.99**k / (1 + gap_fraction / 2)) > math.radians(80.0):
        k += 1
    np.testing.assert_allclose(mat.rmul, 0.99**k, rtol=1e-12)
    assert not fjm.faces_overlap(pos, radius, mat.pairs, mat.rmul).any()
    assert fjm.faces_overlap(pos, radius, mat.pairs, mat.rmul / 0.99).any()


def test_no_reduction_without_overlap_or_with_code_0():
    pos, radius = three_grains(170.0, 0.0)
    mat = fjm.assign_flatjointed(pos, radius, fjm.make_flatjoint_params({"fjm_rmulCode": 1}), 0.0)
    np.testing.assert_array_equal(mat.rmul, 1.0)
    pos, radius = three_grains(40.0, 0.0)
    mat = fjm.assign_flatjointed(pos, radius, fjm.make_flatjoint_params({"fjm_rmulCode": 0}), 0.0)
    np.testing.assert_array_equal(mat.rmul, 1.0)
    assert fjm.faces_overlap(pos, radius, mat.pairs, mat.rmul).any()


def test_uniform_reduction_on_the_hexagonal_lattice():
    """Neighbours 60° apart at l = R: uniformly reduced (code 2), λ = 0.99^k with k the least
    for which 2 atan λ <= 60°, λ <= tan 30°; reduced per joint (code 1, both joints of an
    overlapping pair at once, grain after grain), no face overlaps either, and the λ differ
    from joint to joint."""
    pos, radius = lattice()
    uniform = fjm.assign_flatjointed(pos, radius, fjm.make_flatjoint_params({"fjm_rmulCode": 2}), 0.0)
    k = math.ceil(math.log(math.tan(math.radians(30.0))) / math.log(0.99))
    np.testing.assert_allclose(uniform.rmul, 0.99**k, rtol=1e-12)
    assert not fjm.faces_overlap(pos, radius, uniform.pairs, uniform.rmul).any()
    per_joint = fjm.assign_flatjointed(pos, radius, fjm.make_flatjoint_params({"fjm_rmulCode": 1}), 0.0)
    assert not fjm.faces_overlap(pos, radius, per_joint.pairs, per_joint.rmul).any()
    assert per_joint.rmul.max() < 1.0 and len(np.unique(per_joint.rmul)) > 5
