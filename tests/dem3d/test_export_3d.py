"""The PFC3D export (`rockcal.pfc`): FISHTank's mpParams.p3dat, its vessel file mvParams.p3dat
and the ball/bond lists.

- the parameter file read back gives the material's parameters in SI, under FISHTank's names,
  with the cm_matType of the FISHTank asked for, and the calibration's packing seed;
- it sets every name FISHTank's own PFC3D parallel-bonded example sets;
- its layout is the 2D export's, line for line;
- the vessel file sets every name FISHTank's own mvParams.p3dat examples set, with the UCS
  specimen's cylinder and the packing vessel's modulus; a finished 3D campaign's export
  (`rockcal export --to`) writes both files, whose values are the calibration's as
  `read_calibration` reads it back;
- the ball and bond lists read back give the specimen bit for bit, and each bond's strengths
  are those the engine gives it, its gap the one it takes as its zero.

The FISH here is read by the tests' own reader (`read_fish`), not by PFC: it checks the names
and values written, not that PFC runs them.
"""

import csv
import re

import numpy as np
import pytest

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.dem3d.bonds import Bond
from rockcal.materials import new_state
from rockcal.specimens3d.specimen import Specimen3D
from rockcal.errors import InputError
from rockcal.materials.fishtank import MATERIAL_TYPES
from rockcal.materials.parallel_bond import make_params
from rockcal.pfc.calibrated import Calibrated
from rockcal.pfc.parameter_file import PARAMETER_FILE, fish_groups, to_fish_3d, write_p3dat
from rockcal.pfc.vessel_file import VESSEL_FILE, to_vessel_fish
from rockcal.pfc.parameters import pfc_parameters
from rockcal.pfc.specimen_lists import BALL_COLUMNS, BOND_COLUMNS, write_specimen_3d

PARAMS = make_params({"E_c": 62, "Ebar_c": 55, "kn_ks": 2.5, "knbar_ksbar": 2.0, "sigma_c": 175,
                      "tau_c": 160, "sigma_c_cv": 0.23, "tau_c_cv": 0.2, "phi_b": 12.5,
                      "mu": 0.5, "lambda": 0.8, "mcf": 0.9, "density": 2630})
SETTINGS = SpecimenSettings(rmin_mm=0.75, radius_ratio=1.65, install_gap=0.4, cloud_porosity=0.35,
                            pressure_mpa=0.2, seed=7, width_mm=12.0, height_mm=24.0, dimensions=3)
# FISHTank's PFC3D parallel-bonded example (siyuanxu/PFC-fishPKG,
# ExampleProjects/MatGen-ParallelBonded/mpParams.p3dat): the names it sets
FISHTANK_EXAMPLE = {"cm_matName", "cm_matType", "cm_localDampFac", "cm_densityCode", "cm_densityVal",
                    "cm_nSD", "cm_typeSD", "cm_Dlo", "cm_Dup", "cm_Vfrac", "pk_Pm", "pk_procCode",
                    "pk_nc", "pbm_emod", "pbm_krat", "pbm_fric", "pbm_igap", "pbm_rmul", "pbm_bemod",
                    "pbm_bkrat", "pbm_mcf", "pbm_ten_m", "pbm_ten_sd", "pbm_coh_m", "pbm_coh_sd",
                    "pbm_fa", "lnm_emod", "lnm_krat", "lnm_fric"}
# FISHTank's own mvParams.p3dat examples (itascaconsulting/2021_ARMA_frac, cube/ and coupled/,
# a cylinder): the names they set; ft.fis (`_mvCheckParams`) reads them
FISHTANK_VESSEL = {"mv_type", "mv_shape", "mv_H", "mv_W", "mv_D", "mv_emod", "_mvCylRes"}


def read_fish(text: str) -> dict:
    """The FISH assignments `name = value` (`name(1) = value` for an array) of a parameter file,
    values as FISH reads them: a quoted string, an integer, a float."""
    values = {}
    for line in text.splitlines():
        m = re.fullmatch(r"\s+(\w+)(?:\(1\))? = ('[^']*'|[-+.\w]+)(?:\s+;.*)?", line)
        if not m or re.fullmatch(r"[A-Za-z_]\w*", m.group(2)):  # cm_matNameSAV = cm_matName
            continue
        name, value = m.groups()
        if value.startswith("'"):
            values[name] = value.strip("'")
        elif re.fullmatch(r"[-+]?\d+", value):
            values[name] = int(value)
        else:
            values[name] = float(value)
    return values


@pytest.mark.parametrize("fishtank", [5, 6, 7])
def test_the_parameter_file_reads_back_as_the_material_in_SI(fishtank):
    values = read_fish(to_fish_3d(PARAMS, SETTINGS, fishtank=fishtank))
    assert values["cm_matType"] == MATERIAL_TYPES[fishtank]["parallel-bonded"] == 2
    expected = {"pbm_emod": 62e9, "lnm_emod": 62e9, "pbm_bemod": 55e9, "pbm_krat": 2.5, "lnm_krat": 2.5,
                "pbm_bkrat": 2.0, "pbm_fric": 0.5, "lnm_fric": 0.5, "pbm_rmul": 0.8, "pbm_mcf": 0.9,
                "pbm_ten_m": 175e6, "pbm_ten_sd": 0.23 * 175e6, "pbm_coh_m": 160e6,
                "pbm_coh_sd": 0.2 * 160e6, "pbm_fa": 12.5, "pbm_igap": 0.4 * 0.75e-3,
                "cm_Dlo": 1.5e-3, "cm_Dup": 1.65 * 1.5e-3, "cm_densityVal": 2630.0,
                "cm_localDampFac": 0.7, "pk_Pm": 0.2e6, "pk_nc": 0.35, "pk_procCode": 1,
                "cm_densityCode": 0, "cm_Vfrac": 1.0, "cm_typeSD": 0, "cm_nSD": 1, "pk_seed": 10007}
    for name, value in expected.items():
        assert values[name] == pytest.approx(value, rel=1e-14), name
    assert values["cm_matName"] == "rockcal_parallel_bond"
    written = pfc_parameters(Calibrated(PARAMS, SETTINGS, {}, fishtank))
    assert values.keys() == written.keys()
    for name, value in written.items():
        assert values[name] == (pytest.approx(value, rel=1e-15) if isinstance(value, float) else value)


def test_it_sets_every_name_of_fishtanks_own_pfc3d_example():
    assert FISHTANK_EXAMPLE <= read_fish(to_fish_3d(PARAMS, SETTINGS)).keys() | {"cm_ctName"}


def test_its_groups_are_the_2D_exports_line_for_line(tmp_path):
    text = to_fish_3d(PARAMS, SETTINGS, fishtank=5, header=["a line\nthat breaks"])
    comments = [line for line in text.split("\n") if line.startswith(";")]
    body = [line for line in text.split("\n") if not line.startswith(";")]
    assert body == fish_groups(pfc_parameters(Calibrated(PARAMS, SETTINGS, {}, 5)), "mpSetPBParams")
    assert comments[0] == "; a line\\nthat breaks"  # no header text leaves its comment
    assert any("PFC3D" in line for line in comments) and text.endswith("@_mpCheckAllParams\n")
    path, vessel = write_p3dat(tmp_path, PARAMS, SETTINGS, fishtank=5, header=["a line\nthat breaks"])
    assert path.name == PARAMETER_FILE and path.read_text() == text
    assert vessel.name == VESSEL_FILE and vessel.read_text() == to_vessel_fish(SETTINGS, ["a line\nthat breaks"])


def test_the_vessel_file_is_the_ucs_cylinder_in_fishtanks_names():
    text = to_vessel_fish(SETTINGS, ["a line\nthat breaks"])
    values = read_fish(text)
    assert values.keys() == FISHTANK_VESSEL
    assert values == {"mv_type": 0, "mv_shape": 1, "mv_H": 24e-3, "mv_W": 12e-3, "mv_D": 12e-3,
                      "mv_emod": 1e9, "_mvCylRes": pytest.approx(2 * np.pi / 100, rel=1e-14)}
    # FISHTank's layout: the group function, its call, FISHTank's own check
    body = [line for line in text.splitlines() if not line.startswith(";")]
    assert (body[0], *body[-3:]) == ("def mvSetParams", "end", "@mvSetParams", "@_mvCheckParams")
    assert text.startswith("; a line\\nthat breaks\n")  # no header text leaves its comment


def test_bad_versions_and_materials_are_refused():
    with pytest.raises(InputError, match="--fishtank"):
        to_fish_3d(PARAMS, SETTINGS, fishtank=4)
    with pytest.raises(InputError, match="grain_shape"):
        to_fish_3d(PARAMS, SETTINGS.model_copy(update={"grain_shape": "cloud"}))  # no 3D template


@pytest.mark.parametrize("shape", ["two-pebble", "three-pebble"])
def test_a_clumped_3d_material_creates_the_engines_3d_template_first(shape):
    """PFC3D's `clump template create ... pebbles N` with each pebble's radius, x, y, z (the 3D
    engine's template to the bit), before FISHTank's groups, which name it (cm_shape 1,
    cm_ctName) as FISHTank's ft.fis reads them in PFC3D too."""
    from rockcal.materials.clump_templates import template

    text = to_fish_3d(PARAMS, SETTINGS.model_copy(update={"grain_shape": shape}))
    values = read_fish(text)
    assert values["cm_shape"] == 1 and values["cm_ctName"] == f"rockcal_{shape.replace('-', '_')}"
    t, lines = template(shape, dimensions=3), text.splitlines()
    k = lines.index(f"clump template create pebcalculate name {values['cm_ctName']} pebbles {t.n_pebbles} ...")
    rows = np.array([lines[k + 1 + i].removesuffix(" ...").split() for i in range(t.n_pebbles)], float)
    np.testing.assert_array_equal(rows, np.column_stack([t.radii, t.offsets]))
    assert text.index("clump template create") < text.index("def mpSetCommonParams")
    assert "3D: clumps of" in text and "x, y, z" in text


def jittered_block() -> Specimen3D:
    """4 x 4 x 4 spheres of unequal radii on a jittered simple-cubic lattice, lattice neighbours
    bonded: some pairs overlap, some have a gap."""
    rng = np.random.default_rng(5)
    r = 1e-3
    grid = np.array([(i, j, k) for k in range(4) for j in range(4) for i in range(4)], float)
    pos = grid * 2 * r + rng.uniform(-0.05, 0.05, grid.shape) * r
    radius = rng.uniform(0.95, 1.05, len(pos)) * r
    flat = {tuple(v): n for n, v in enumerate(grid.astype(int))}
    bonds = np.array([(flat[tuple(v)], flat[tuple(v + s)]) for v in grid.astype(int)
                      for s in np.eye(3, dtype=int) if tuple(v + s) in flat])
    return Specimen3D(pos, radius, bonds, "cuboid", (8e-3, 8e-3, 8e-3), "block",
                      rng.random((len(bonds), 2)), rmin_mm=0.95)


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], float)


def test_the_ball_and_bond_lists_read_back_as_the_specimen_and_its_engine_bonds(tmp_path):
    block = jittered_block()
    balls, bonds = write_specimen_3d(block, PARAMS, tmp_path)
    header, table = read_csv(balls)
    assert tuple(header) == BALL_COLUMNS
    np.testing.assert_array_equal(table[:, 0], np.arange(1, block.n_spheres + 1))
    np.testing.assert_array_equal(table[:, 1:4], block.pos)
    np.testing.assert_array_equal(table[:, 4], block.radius)
    header, table = read_csv(bonds)
    assert tuple(header) == BOND_COLUMNS
    np.testing.assert_array_equal(table[:, 0], np.arange(1, len(block.bonds) + 1))
    np.testing.assert_array_equal(table[:, 1:3] - 1, block.bonds)
    gap = table[:, BOND_COLUMNS.index("gap_m")]
    assert (gap < 0).any() and (gap > 0).any()
    np.testing.assert_array_equal(table[:, BOND_COLUMNS.index("rgap_m")], np.minimum(gap, 0))
    ri, rj = block.radius[block.bonds].T
    np.testing.assert_array_equal(table[:, BOND_COLUMNS.index("bond_radius_m")], 0.8 * np.minimum(ri, rj))
    # what the engine's bonds hold, pair by pair
    state = new_state(PARAMS, block)
    nb = state.neighbours.n_bonds
    engine = {(int(i), int(j)): p for p, (i, j) in enumerate(zip(state.neighbours.pi[:nb],
                                                                 state.neighbours.pj[:nb]))}
    p = np.array([engine[(int(i), int(j))] for i, j in block.bonds])
    for column, row in (("tensile_strength_Pa", Bond.TEN), ("cohesion_Pa", Bond.COH)):
        np.testing.assert_array_equal(table[:, BOND_COLUMNS.index(column)], state.bonds.table[row, p])
    np.testing.assert_allclose(gap, -state.bonds.table[Bond.REF_OVERLAP, p], rtol=0, atol=1e-18)


CAMPAIGN_3D = """
[rock]
name = "granite 3D"
density_kg_m3 = 2630
[targets.ucs]
E_GPa = 41.5
[specimen]
dimensions = 3
rmin_mm = 0.75
width_mm = 12
height_mm = 24
seed = 7
install_gap = 0.4
pressure_mpa = 0.2
[search]
bounds = { E_c = [10, 30] }
"""

def test_a_finished_3d_campaign_exports_both_files_with_its_own_values(tmp_path, cli, save_finished):
    from rockcal.campaign.outputs.export import calibration_in
    from rockcal.pfc.parameters import pfc_parameters
    from rockcal.pfc.vessel_file import vessel_values

    out = save_finished(tmp_path / "campaign", CAMPAIGN_3D, PARAMS, {"E_c": 62.0})
    (tmp_path / "pfc").mkdir()
    run = cli("export", out, "--to", tmp_path / "pfc" / PARAMETER_FILE)
    assert run.returncode == 0, run.stderr
    calibrated = calibration_in(out)  # read back from the store as the export read it
    assert calibrated.specimen.dimensions == 3 and calibrated.specimen.seed == 7
    written = read_fish((tmp_path / "pfc" / PARAMETER_FILE).read_text())
    expected = pfc_parameters(calibrated)
    assert written.keys() == expected.keys() and written["pk_seed"] == 10007
    for name, value in expected.items():  # each float to the 15 digits written
        assert written[name] == (pytest.approx(value, rel=1e-14) if isinstance(value, float) else value), name
    assert written["pbm_emod"] == 62e9 and written["pbm_igap"] == pytest.approx(0.4 * 0.75e-3, rel=1e-14)
    vessel = read_fish((tmp_path / "pfc" / VESSEL_FILE).read_text())
    assert vessel == pytest.approx(vessel_values(calibrated.specimen), rel=1e-14)
    assert (vessel["mv_H"], vessel["mv_W"]) == (24e-3, 12e-3)
    # the parameter file cannot take the vessel file's name: one line, exit 2, nothing overwritten
    clash = cli("export", out, "--to", tmp_path / "pfc" / VESSEL_FILE)
    assert clash.returncode == 2 and len(clash.stderr.strip().splitlines()) == 1 and "--to" in clash.stderr
    assert read_fish((tmp_path / "pfc" / VESSEL_FILE).read_text()) == vessel


# the flat-jointed material group's names in FISHTank's ft.fis (PFC 5's and PFC 6's alike:
# `_mpAssignFJProps`, `_mpCheckAllParams`): fjm_Nal, its elements per ring, in PFC3D only
FISHTANK_FLAT_JOINT_3D = {"fjm_igap", "fjm_B_frac", "fjm_G_frac", "fjm_G_m", "fjm_G_sd", "fjm_Nr",
                          "fjm_Nal", "fjm_rmulCode", "fjm_rmulVal", "fjm_emod", "fjm_krat",
                          "fjm_fric", "fjm_ten_m", "fjm_ten_sd", "fjm_coh_m", "fjm_coh_sd", "fjm_fa",
                          "fjm_trackMS", "lnm_emod", "lnm_krat", "lnm_fric"}


@pytest.mark.parametrize("fishtank", [5, 6, 7])
def test_the_flat_jointed_parameter_file_reads_back_in_SI_with_its_elements_per_ring(fishtank):
    from rockcal.materials.flat_joint import make_flatjoint_params

    params = make_flatjoint_params({"fj_emod": 38.0, "fj_kratio": 1.9, "fj_ten": 48.4,
                                    "fj_coh": 120.0, "fj_nr": 3, "fj_nal": 5, "fj_fa": 20.0,
                                    "fjm_B_frac": 0.8, "fjm_G_frac": 0.1, "fjm_G_m": 0.002})
    text = to_fish_3d(params, SETTINGS, fishtank=fishtank)
    values = read_fish(text)
    assert values["cm_matType"] == MATERIAL_TYPES[fishtank]["flat-jointed"]
    assert {name for name in values if name.startswith(("fjm_", "lnm_"))} == \
        FISHTANK_FLAT_JOINT_3D - {"fjm_trackMS"}  # a boolean, which `read_fish` skips
    assert "  fjm_trackMS = false" in text.splitlines()
    expected = {"fjm_Nr": 3, "fjm_Nal": 5, "fjm_emod": 38e9, "fjm_krat": 1.9, "fjm_ten_m": 48.4e6,
                "fjm_coh_m": 120e6, "fjm_fa": 20.0, "fjm_B_frac": 0.8, "fjm_G_frac": 0.1,
                "fjm_G_m": 2e-6, "fjm_igap": 0.4 * 0.75e-3, "lnm_emod": 38e9}
    for name, value in expected.items():
        assert values[name] == pytest.approx(value, rel=1e-14), name
    assert "def mpSetFJParams" in text and "fjm_Nr: the disk's rings" in text and "pbm_" not in text
    two_d = pfc_parameters(Calibrated(params, SETTINGS.model_copy(update={"dimensions": 2}), {}, fishtank))
    assert "fjm_Nal" not in two_d and two_d["fjm_Nr"] == 3
