"""The PFC export of both materials as FISHTank reads it: written, parsed back, equal in SI;
and every parameter FISHTank's checks and material assignment read is set.

The names FISHTank reads come from FISHTank 6.6 as published in itascaconsulting/2021_ARMA_frac
(`fistSrc/ft.fis`): `_mpCheckAllParams` (`_mpCheckCommonParams`, `_mpCheckPackingParams`,
`_mpCheckPBParams` or `_mpCheckFJParams`, each ending with `_mpCheckLinParams`), then the
genesis' `_mpFinalizationPhase`: `ft_setMatBehavior` (the linear group for contacts that form
later) and `_mpAssignPB` (`_mpAssignPBprops`) or `_mpAssignFJ` (`_mpAssignFJProps`,
`_mpFJrmulReduce`, `_mpFJsetMicroStruc`).

The files are read back by the tests' own reader (`fish_values`), not by PFC: the names and
values written are checked, not that PFC runs them."""

import json
import re
from types import SimpleNamespace

import pytest

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.pfc.json_file import to_json
from rockcal.pfc.parameter_file import to_fish
from rockcal.pfc.python_script import to_python
from rockcal.materials.flat_joint import make_flatjoint_params
from rockcal.params import make_params

COMMON = ("cm_matName", "cm_matType", "cm_localDampFac", "cm_densityCode", "cm_densityVal",
          "cm_shape", "cm_nSD", "cm_typeSD", "cm_Dlo", "cm_Dup", "cm_Vfrac", "cm_Dmult")
PACKING = ("pk_seed", "pk_Pm", "pk_procCode", "pk_nc")
LINEAR = ("lnm_emod", "lnm_krat", "lnm_fric")
READ = {  # by cm_matType
    2: COMMON + PACKING + LINEAR + (
        "pbm_emod", "pbm_krat", "pbm_fric", "pbm_igap", "pbm_rmul", "pbm_bemod", "pbm_bkrat",
        "pbm_mcf", "pbm_ten_m", "pbm_ten_sd", "pbm_coh_m", "pbm_coh_sd", "pbm_fa"),
    4: COMMON + PACKING + LINEAR + (
        "fjm_igap", "fjm_B_frac", "fjm_G_frac", "fjm_G_m", "fjm_G_sd", "fjm_Nr", "fjm_rmulCode",
        "fjm_rmulVal", "fjm_emod", "fjm_krat", "fjm_fric", "fjm_ten_m", "fjm_ten_sd",
        "fjm_coh_m", "fjm_coh_sd", "fjm_fa", "fjm_trackMS"),
}
# Read too but left to FISHTank's defaults, which are what a rockcal material means or which
# only steer PFC's own genesis: cm_matNameSAV (set to cm_matName), cm_modName (cm_matType 5),
# cm_ctName (a ball material's; a clumped one sets it), pk_PTol, pk_ARatLimit, pk_stepLimit (its genesis tolerances), pk_fricCA, pk_vLimit (boundary
# contraction), fjm_Nal (3D).

SPECIMEN = SpecimenSettings(rmin_mm=0.4, radius_ratio=1.5, install_gap=0.5, cloud_porosity=0.1,
                            pressure_mpa=0.2, contact_stiffness="pfc5")
FLATJOINTED = {"fj_emod": 35.0, "fj_kratio": 2.5, "fj_ten": 20.0, "fj_ten_cv": 0.2,
               "fj_coh": 60.0, "fj_coh_sd": 9.0, "fj_fa": 35.0, "fj_fric": 0.6, "fj_nr": 3,
               "fj_rmul": 0.9, "fjm_rmulCode": 1, "fjm_B_frac": 0.7, "fjm_G_frac": 0.1,
               "fjm_G_m": 0.002, "fjm_G_sd": 0.0005, "lnm_emod": 25.0, "lnm_krat": 1.5,
               "lnm_fric": 0.4, "density": 2650.0, "damping": 0.6}
# The same material in FISHTank's names and SI units, written out by hand.
FLATJOINTED_PFC = {
    "cm_matName": "rockcal_flatjoint", "cm_matType": 4, "cm_localDampFac": 0.6, "cm_densityCode": 0,
    "cm_densityVal": 2650.0, "cm_shape": 0, "cm_nSD": 1, "cm_typeSD": 0, "cm_Dlo": 0.8e-3,
    "cm_Dup": 1.2e-3, "cm_Vfrac": 1.0, "cm_Dmult": 1.0, "pk_seed": 10001, "pk_Pm": 0.2e6, "pk_procCode": 1,
    "pk_nc": 0.1, "fjm_igap": 0.2e-3, "fjm_B_frac": 0.7, "fjm_G_frac": 0.1, "fjm_G_m": 2e-6,
    "fjm_G_sd": 5e-7, "fjm_Nr": 3, "fjm_rmulCode": 1, "fjm_rmulVal": 0.9, "fjm_emod": 35e9,
    "fjm_krat": 2.5, "fjm_fric": 0.6, "fjm_ten_m": 20e6, "fjm_ten_sd": 4e6, "fjm_coh_m": 60e6,
    "fjm_coh_sd": 9e6, "fjm_fa": 35.0, "fjm_trackMS": False, "lnm_emod": 25e9, "lnm_krat": 1.5,
    "lnm_fric": 0.4}


def calibrated(params):
    origin = {"rock": "Lac du Bonnet", "accepted": True, "dem_runs": 1, "campaign": "c",
              "engine": "e", "targets": {"E_GPa": 70.0}, "verified": {}, "identified": {}}
    return SimpleNamespace(params=params, specimen=SPECIMEN, origin=origin)


def fish_values(text: str) -> dict:
    """The assignments of a FISH parameter file (an array's first entry under its name)."""
    values = {}
    for name, value in re.findall(r"^  (\w+)(?:\(1\))? = (.+?)(?:  ;.*)?$", text, re.M):
        if value.startswith("'"):
            values[name] = value.strip("'")
        elif value in ("true", "false"):
            values[name] = value == "true"
        elif re.fullmatch(r"[-+0-9.e]+", value):
            values[name] = int(value) if re.fullmatch(r"[-+]?\d+", value) else float(value)
    return values


def read_back(params) -> list[dict]:
    """The parameters of each export format, parsed back."""
    c = calibrated(params)
    data = json.loads(to_json(c))
    scope = {}
    exec(to_python(c), scope)
    return [fish_values(to_fish(c)), scope["PARAMETERS"], data["parameters"]]


@pytest.mark.parametrize("form", ["fish", "python", "json"])
def test_flat_jointed_export_reads_back_in_si(form):
    values = read_back(make_flatjoint_params(FLATJOINTED))[["fish", "python", "json"].index(form)]
    assert set(values) == set(FLATJOINTED_PFC)
    for name, value in FLATJOINTED_PFC.items():
        assert type(values[name]) is type(value), name  # integers stay integers, as FISH wants
        assert values[name] == (pytest.approx(value, rel=1e-12) if type(value) is float else value), name


def test_the_fish_file_is_fishtanks_layout():
    text = to_fish(calibrated(make_flatjoint_params(FLATJOINTED)))
    order = [line for line in text.splitlines() if line.startswith(("def ", "@"))]
    assert order == ["def mpSetCommonParams", "@mpSetCommonParams", "def mpSetPackingParams",
                     "@mpSetPackingParams", "def mpSetFJParams", "@mpSetFJParams", "@_mpCheckAllParams"]
    assert "  cm_matNameSAV = cm_matName" in text
    for name in ("cm_typeSD", "cm_Dlo", "cm_Dup", "cm_Vfrac"):
        assert f"  {name} = array.create(cm_nSD)" in text


@pytest.mark.parametrize("params, material_type", [
    (make_params({"E_c": 20.0, "sigma_c_cv": 0.2}), 2),
    (make_flatjoint_params(FLATJOINTED), 4),
])
def test_every_parameter_fishtank_reads_is_set(params, material_type):
    for values in read_back(params):
        assert values["cm_matType"] == material_type
        missing = set(READ[material_type]) - set(values)
        assert not missing, sorted(missing)
        prefix = {2: "fjm_", 4: "pbm_"}[material_type]  # the other material's group: none
        assert not [name for name in values if name.startswith(prefix)]


def test_flat_jointed_specimen_lists_read_back(tmp_path):
    """export-specimen of a flat-jointed material: each joint's type, initial gap, λ and
    strengths, as the engine assigns them."""
    import csv

    import numpy as np

    from rockcal.pfc.specimen_lists import write_specimen
    from rockcal.specimens.specimen import hexagonal
    from rockcal.materials.flat_joint import flatjointed

    spec = hexagonal(4, 4, 0.25)
    params = make_flatjoint_params(FLATJOINTED)
    _, bonds_path = write_specimen(spec, params, tmp_path)
    with open(bonds_path) as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["ball1", "ball2", "type", "initial_gap_m", "radius_multiplier",
                       "tensile_strength_Pa", "cohesion_Pa"]
    table = np.array(rows[1:], float)
    m = flatjointed(spec.pos, spec.radius, spec.bonds, params, spec.joint_draws)
    np.testing.assert_array_equal(table[:, :2] - 1, spec.bonds)
    for column, values in zip(table[:, 2:].T, (m.kind, m.gap0, m.rmul, m.ten[:, 0], m.coh[:, 0])):
        np.testing.assert_array_equal(column, values)
    assert set(m.kind) == {1, 2, 3}


@pytest.mark.parametrize("value", [0.23 * 35.61e6, 0.1 + 0.2, 21.65e9, 1e-9, 2.0, 0.5e-3 * 1.65])
def test_a_float_is_written_to_a_doubles_precision_as_a_float(value):
    from rockcal.pfc.fish_value import fish_value as _fish_value

    text = _fish_value(value)
    assert float(text) == pytest.approx(value, rel=1e-15)
    assert len(text.replace(".", "").split("e")[0].lstrip("0")) <= 15
    assert "." in text or "e" in text


def test_a_pfc4_contact_calibration_says_that_no_fishtank_file_reproduces_it():
    """Calibrated with PFC 3.x/4.0's contacts (kn = t E_c), the header gives their kn, ks (and
    PFC 3.x/4.0's ball stiffnesses, 2 t E_c in series) and says that FISHTank's PFC 5+ contacts
    are not those, and how to calibrate for PFC 5+; a flat-jointed or pfc5 calibration says
    nothing of it."""
    from rockcal.pfc.header import header_lines

    lines = {}
    for stiffness in ("pfc5", "pfc4"):
        c = calibrated(make_params({"E_c": 20.0, "kn_ks": 2.0}))
        c.specimen = SPECIMEN.model_copy(update={"contact_stiffness": stiffness})
        lines[stiffness] = header_lines(c)
    flat = calibrated(make_flatjoint_params(FLATJOINTED))
    flat.specimen = SPECIMEN.model_copy(update={"contact_stiffness": "pfc4"})
    assert not any("PFC 3.x/4.0" in line for line in lines["pfc5"] + header_lines(flat))
    (kn,) = [line for line in lines["pfc4"] if "PFC 3.x/4.0" in line]
    assert 'contact_stiffness = "pfc4"' in kn and "kn = t E_c = 2e+10 N/m, ks = 1e+10 N/m" in kn
    assert "ball kn 4e+10, ks 2e+10 N/m" in kn
    (note,) = [line for line in lines["pfc4"] if "no FISHTank file" in line]
    assert 'calibrate with contact_stiffness = "pfc5"' in note
    assert fish_values(to_fish(c))["pbm_emod"] == 20e9  # E_c itself, in PFC 5's formula
