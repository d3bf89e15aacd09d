"""K_IC formulas: the lab's round bar (the source study's numbers), the notched beam against published tables."""

import json
import math
import subprocess
import sys

import pytest

from rockcal.labtests.kic import (ouchterlony_Y, pmax_kic_disagreement, round_bar_kic, senb_k,
                                  senb_k_astm, senb_kic)


def rockcal(*args):
    return subprocess.run([sys.executable, "-m", "rockcal", *args], capture_output=True, text=True)


def test_round_bar_formula_gives_the_granite_value():
    """The source's bar: P_max 1.453 kN, D 50 mm, a 18 mm, S 160 mm -> Y 9.362, K_IC 0.973 MPa m^0.5."""
    assert ouchterlony_Y(18 / 50) == pytest.approx(9.362, abs=5e-4)
    assert round_bar_kic(1453.0, 0.050, 0.018, 0.160) / 1e6 == pytest.approx(0.973, abs=5e-4)


def test_stated_pmax_and_kic_that_disagree_get_a_warning():
    warning = pmax_kic_disagreement(1453.0, 1.057e6, 0.050, 0.018, 0.160)
    assert warning is not None and "0.973" in warning and "1.057" in warning
    assert pmax_kic_disagreement(1453.0, 0.975e6, 0.050, 0.018, 0.160) is None


@pytest.mark.parametrize("a_over_W, f_astm", [(0.45, 2.29), (0.50, 2.66), (0.55, 3.14)])
def test_beam_formula_at_span_4_matches_the_astm_e399_table(a_over_W, f_astm):
    """ASTM E399 tabulates f(a/W) of K = P S / (B W^1.5) f for S/W = 4; k = 2/3 f."""
    assert 1.5 * senb_k(a_over_W, 4.0) == pytest.approx(f_astm, abs=0.006)
    assert senb_k(a_over_W, 4.0) == pytest.approx(senb_k_astm(a_over_W), rel=1e-12)


def test_beam_formula_for_long_spans_tends_to_the_edge_crack_in_bending():
    """A shallow edge crack under pure bending: K -> 1.122 sigma sqrt(pi a) (Tada et al.)."""
    a = 1e-4
    assert senb_k(a, 1e9) / math.sqrt(math.pi * a) == pytest.approx(1.122, abs=1e-3)
    # shorter spans lower K at the same nominal bending stress (the load point's compression)
    assert senb_k(0.36, 3.2) < senb_k(0.36, 4.0) < senb_k(0.36, 8.0)


def test_beam_kic_scales_with_load_and_size():
    """K = sigma_N sqrt(W) k: twice the load doubles K; the same shape at 4x size, same
    nominal stress, doubles K (sqrt of the size)."""
    base = senb_kic(40e3, 0.16, 0.05, 0.018)
    assert senb_kic(80e3, 0.16, 0.05, 0.018) == pytest.approx(2 * base)
    assert senb_kic(160e3, 0.64, 0.20, 0.072) == pytest.approx(2 * base)


@pytest.mark.slow
def test_kic_command():
    run = rockcal("kic", "--pmax-kn", "1.453", "--diameter-mm", "50", "--notch-mm", "18",
                  "--span-mm", "160", "--json")
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["K_IC_MPa_sqrt_m"] == pytest.approx(0.973, abs=5e-4)


@pytest.mark.slow
@pytest.mark.parametrize("args, field", [
    (["--notch-mm", "60"], "--notch-mm"),
    (["--pmax-kn", "-1"], "--pmax-kn"),
    (["--diameter-mm", "0"], "--diameter-mm"),
    (["--span-mm", "nan"], "--span-mm"),
])
def test_kic_bad_input_is_one_line_and_exit_2(args, field):
    values = {"--pmax-kn": "1.453", "--diameter-mm": "50", "--notch-mm": "18", "--span-mm": "160"}
    values.update(dict(zip(args[::2], args[1::2])))
    run = rockcal("kic", *[x for kv in values.items() for x in kv])
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and field in lines[0], run.stderr
