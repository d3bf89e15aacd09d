"""The semi-circular bend test (ISRM 2014) on tiny half disks: its rig's statics on a symmetric
lattice, K_IC from the peak by ISRM's formula, the granite's K_IC of the order of the notched
beam's, and its keys refused in one line."""

import numpy as np
import pytest

from rockcal import make_params
from rockcal.labtests.bending import Beam, notched_beam, simulate_bending
from rockcal.labtests.kic import scb_kic
from rockcal.labtests.rig import rig_for
from rockcal.labtests.scb import HalfDisk, half_disk, simulate_scb
from rockcal.specimens.carving import inside_circle, keep_particles, outside_rectangle
from rockcal.specimens.specimen import hexagonal
from test_cli import rockcal  # noqa: F401  (the command in this process)

SMALL = HalfDisk(10.0, 5.0, 0.8, 1.0)  # R 10 mm, beta 0.5
BEAM = Beam(44.0, 10.0, 3.6, 1.0, 32.0)  # as deep as SMALL's radius, a/W 0.36 and S/W 3.2 as the source's


def test_a_lattice_half_disk_bears_on_both_supports_alike():
    """A half disk of equal disks on a triangular lattice, symmetric about its notch, pressed
    elastically at rest: each support bears half the pin's load."""
    lattice = hexagonal(2 * SMALL.radius_mm, SMALL.radius_mm, 0.25)
    r, half = 1e-3 * SMALL.radius_mm, 0.5e-3 * SMALL.notch_width_mm
    keep = inside_circle(lattice.pos, lattice.radius, (r, 0.0), r) & outside_rectangle(
        lattice.pos, lattice.radius, r - half, r + half, -1.0, 1e-3 * SMALL.notch_mm)
    specimen = keep_particles(lattice, keep, "lattice half disk")
    params = make_params({"sigma_c": 1e4, "tau_c": 1e4})
    s = 1e-3 * SMALL.half_span_mm
    pins = rig_for(specimen).pins(specimen, params, r, (r - s, r + s), 1e-3 * SMALL.pin_radius_mm, 2e-8)
    pins.state.scale_density()
    pins.move(1.0)
    pins.state.advance(1500)
    pins.move(0.0)
    pins.state.advance(3000)
    left, right = pins.reactions()
    load = pins.state.particles.force[pins.is_pin, 1].sum()
    assert load > 0 and pins.state.n_broken() == 0
    assert left == pytest.approx(load / 2, rel=0.01) and right == pytest.approx(load / 2, rel=0.01)


@pytest.fixture(scope="module")
def result():
    return simulate_scb(make_params({}), half_disk(SMALL, 0.25, 1.65, seed=1), SMALL, stop_fraction=0.9)


def test_the_peak_gives_k_ic_by_isrm_formula_and_the_crack_starts_at_the_notch_tip(result):
    assert result.K_IC_scb_MPa_sqrt_m * 1e6 == pytest.approx(scb_kic(1e3 * result.P_max_kN_per_m, 0.01, 0.005, 0.008))
    tip = np.array([0.01, 0.005])
    distance = np.hypot(*(result.first_break_xy - tip).T)
    assert len(distance) > 0 and distance.min() < 4 * 2 * result.radius.mean()


def test_the_granite_k_ic_is_of_the_order_of_the_notched_beam_s(result):
    beam = simulate_bending(make_params({}), notched_beam(BEAM, 0.25, 1.65, seed=1), BEAM, stop_fraction=0.9)
    assert 0.5 < result.K_IC_scb_MPa_sqrt_m / beam.K_IC_MPa_sqrt_m < 2.0


@pytest.mark.parametrize("args, flag", [
    (["--notch-mm", "2"], "--notch-mm"),  # a/R 0.2, below ISRM's 0.4
    (["--span-ratio", "0.9"], "--span-ratio"),  # beyond ISRM's 0.8
    (["--radius-mm", "2", "--notch-mm", "1", "--notch-width-mm", "0.2"], "--radius-mm"),  # too small for its grains
    (["--notch-width-mm", "-1"], "--notch-width-mm"),
])
def test_a_bad_key_is_refused_in_one_line(rockcal, args, flag, tmp_path):
    run = rockcal("simulate", "scb", *args, "--out", str(tmp_path / "out"))
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"rockcal: error: {flag}"), run.stderr
    assert not (tmp_path / "out").exists()
