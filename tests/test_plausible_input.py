"""A lab value outside a rock's range for its unit (a UCS in Pa where MPa is meant) is refused
in one line naming its key and the unit it was likely given in, exit 2, before any run and
with nothing written: from a campaign file, a notebook's dict, and the command's options."""

import pytest

from rockcal.api import calibrate
from test_cli import rockcal  # noqa: F401  (the command in this process)
from rockcal.errors import InputError
from rockcal.labtests.plausible import PLAUSIBLE, implausible

GRANITE = {"E_GPa": 41.5, "nu": 0.23, "ucs_MPa": 138.8}


def campaign_text(**targets) -> str:
    given = GRANITE | targets
    return "[targets.ucs]\n" + "".join(f"{k} = {v!r}\n" for k, v in given.items())


@pytest.mark.parametrize("targets, message", [
    ({"ucs_MPa": 138.8e6}, "targets.ucs.ucs_MPa: 1.388e+08 MPa is not a rock's value; did you give Pa? (give MPa)"),
    ({"E_GPa": 41.5e9}, "targets.ucs.E_GPa: 4.15e+10 GPa is not a rock's value; did you give Pa? (give GPa)"),
    ({"E_GPa": 41500.0}, "targets.ucs.E_GPa: 4.15e+04 GPa is not a rock's value; did you give MPa? (give GPa)"),
])
def test_a_campaign_value_in_the_wrong_unit_is_refused_before_the_dry_run(tmp_path, rockcal, targets, message):
    path = tmp_path / "rock.toml"
    path.write_text(campaign_text(**targets))
    run = rockcal("calibrate", str(path), "--dry-run", "--out", str(tmp_path / "out"))
    assert run.returncode == 2
    assert run.stderr == f"rockcal: error: {message}\n"
    assert not (tmp_path / "out").exists()


def test_a_rocks_values_pass_and_one_beyond_any_unit_says_the_range():
    assert all(implausible(name, value) is None for name, value in GRANITE.items())
    assert implausible("confinement_mpa", [0, 5, 10]) is None  # 0: unconfined, a setting
    assert implausible("m_i", 1e9) is None  # no unit, no range
    low, high, _ = PLAUSIBLE["GPa"]
    assert implausible("E_GPa", 1e30) == f"1e+30 GPa is not a rock's value (a rock's is {low:g} to {high:g} GPa)"


@pytest.mark.parametrize("section, message", [
    ({"brazilian": {"sigma_t_MPa": 8.0e6}}, "targets.brazilian.sigma_t_MPa: 8e+06 MPa is not a rock's value; did you give Pa?"),
    ({"bending": {"K_IC_MPa_sqrt_m": 1.057, "diameter_mm": 0.05}},
     "targets.bending.diameter_mm: 0.05 mm is not a rock's value; did you give m?"),
    ({"biaxial": {"confinement_mpa": [0, 5e6], "sigma1_MPa": [138.8, 180.0]}},
     "targets.biaxial.confinement_mpa: 5e+06 MPa is not a rock's value; did you give Pa?"),
])
def test_a_notebooks_dict_in_the_wrong_unit_raises_naming_the_key(tmp_path, section, message):
    tables = {"targets": {"ucs": GRANITE, **section}}
    with pytest.raises(InputError, match="^" + message.replace("?", r"\?").replace("+", r"\+")):
        calibrate(tables, out=tmp_path / "out")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("args, message", [
    (["kic", "--pmax-kn", "1453", "--diameter-mm", "50", "--notch-mm", "18", "--span-mm", "160"],
     "--pmax-kn: 1453 kN is not a rock's value; did you give N? (give kN)"),
    (["simulate", "biaxial", "--confinement-mpa", "5e6"],
     "--confinement-mpa: 5e+06 MPa is not a rock's value; did you give Pa? (give MPa)"),
])
def test_a_command_option_in_the_wrong_unit_is_refused(rockcal, args, message):
    run = rockcal(*args)
    assert (run.returncode, run.stderr) == (2, f"rockcal: error: {message}\n")
