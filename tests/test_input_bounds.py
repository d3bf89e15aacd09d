"""The bounds a lab test's input is checked against before its run: a confinement is 0 or one
the side walls' servo holds (the command's option and a campaign's targets alike), a grip
holds two rows of grains, a material with no bonded element is no rock; and the readings no
elastic 2D solid gives."""

import math

import pytest
from pydantic import ValidationError

from rockcal import random_packing
from rockcal.errors import InputError
from rockcal.labtests import biaxial
from rockcal.labtests.direct_tension import check_grip_rows, simulate_direct_tension
from rockcal.labtests.result import out_of_range
from rockcal.materials import FLATJOINT, PARALLEL_BOND, parameters
from rockcal.materials.flat_joint import make_flatjoint_params


def test_a_confinement_is_zero_or_what_the_servo_holds():
    for fine in (0, 0.0, biaxial.MIN_CONFINEMENT_MPA, 5, biaxial.MAX_CONFINEMENT_MPA):
        biaxial.check_confinement(fine)
    biaxial.check_confinements([0.0, 0.1, 5.0])
    for bad in (1e-12, 0.0999, -1.0, math.nan, math.inf, True, "5"):
        with pytest.raises(InputError) as error:
            biaxial.check_confinement(bad)
        assert error.value.field == "confinement_mpa"


def test_a_campaigns_confinements_meet_the_same_bound():
    """[targets.biaxial] confinement_mpa goes through the same check, before any run."""
    with pytest.raises(ValidationError, match="confinement_mpa.*at least 0.1 MPa"):
        biaxial.BiaxialValues.model_validate({"confinement_mpa": [1e-12, 5], "phi_deg": 40})
    assert biaxial.BiaxialValues.model_validate({"confinement_mpa": [0, 5], "phi_deg": 40})


def test_a_grip_holds_two_rows_of_grains():
    check_grip_rows(0.1, 16, 1.06)  # the fingerprints' small prism: 1.6 mm grips
    with pytest.raises(InputError, match="at least 0.0663"):
        check_grip_rows(0.05, 16, 1.06)
    prism = random_packing(8, 16, 0.4, 1.65, seed=1)
    with pytest.raises(InputError, match="grip_fraction"):  # before the run, on the specimen itself
        simulate_direct_tension(None, prism, grip_fraction=0.02)


def test_a_material_with_no_bonded_element_is_no_rock():
    with pytest.raises(InputError, match="^fjm_B_frac: "):
        parameters(FLATJOINT, {"fjm_B_frac": 0.0, "fjm_G_frac": 0.3})
    with pytest.raises(InputError, match="^Ebar_c: "):
        parameters(PARALLEL_BOND, {"Ebar_c": 0.0})
    assert parameters(FLATJOINT, {"fjm_B_frac": 0.1}).fjm_B_frac == 0.1
    assert parameters(PARALLEL_BOND, {"E_c": 0.0, "Ebar_c": 20.0}).E_c == 0.0  # bonds only
    # the material itself still assigns any fractions (its own tests realise B = 0)
    assert make_flatjoint_params({"fjm_B_frac": 0.0}).slit_fraction == 1.0


def test_readings_no_elastic_solid_gives_are_named():
    assert out_of_range({"E_GPa": 40.0, "nu": 0.25}) == []
    assert out_of_range({"E_GPa": 40.0, "nu": 0.7}) == []  # a 2D solid may read nu above 0.5
    assert out_of_range({"sigma_t_MPa": 10.0}) == []  # a test without E or nu
    found = out_of_range({"E_GPa": math.nan, "nu": 9.479})
    assert len(found) == 2 and found[0].startswith("nu = 9.479 is outside (-1, 1)")
    assert found[1].startswith("E_GPa = nan is outside (0, inf)")
