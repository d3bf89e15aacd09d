"""3D in campaigns and `rockcal simulate` (`[specimen] dimensions = 3`, `--dimensions 3`): a 3D
run is keyed apart and every 2D run keeps the key it had before; the UCS kind runs the 3D test
on a cylinder of the specimen's width and height and reads it as the 2D test's result; a
campaign of UCS targets runs the whole procedure on a tiny cylinder, and a twin recovers its
micro-parameters; a campaign of the flat-jointed material runs in 3D.

The cylinder is 7 x 14 mm at R_min 0.5 mm: about 300 spheres, under a second a run."""

import json

import numpy as np
import pytest

from rockcal.campaign.input.config import SpecimenSettings, parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.pool import Executor, execute
from rockcal.campaign.runs.spec import ENGINE, RunResult, RunSpec, run_spec
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens3d.specimen import Specimen3D
from rockcal.labtests.ucs import simulate_ucs
from rockcal.labtests.kind import LATER_SETTINGS, all_settings
from rockcal.labtests.settings import specimen_settings
from rockcal.labtests.ucs import TEST as UCS
from rockcal.materials import as_params

CYLINDER = {"dimensions": 3, "width_mm": 7.0, "height_mm": 14.0, "rmin_mm": 0.5}
PARAMS = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0, "tau_c": 60.0}
CAMPAIGN = """
[targets.ucs]
E_GPa = {E_GPa!r}
nu = {nu!r}
ucs_MPa = {ucs_MPa!r}
[specimen]
dimensions = 3
width_mm = 7
height_mm = 14
rmin_mm = 0.5
{sensitivity}
[search]
bounds = {{ E_c = [15, 25], kn_ks = [1.5, 2.5], sigma_c = [30, 50] }}
fixed = {{ tau_c = 60, mu = 0.5 }}
[surrogate]
samples = {samples}
checks = {checks}
[optimizer]
iterations = 30
[acceptance]
tolerance = {tolerance}
max_dem_runs = {budget}
"""
SENSITIVITY = """[sensitivity]
array = "L4(2^3)"
levels = { E_c = [15, 25], kn_ks = [1.5, 2.5], sigma_c = [30, 50] }"""


def test_a_2d_run_keeps_the_key_it_had_before_3d():
    settings = SpecimenSettings()
    before = [name for name in UCS.settings if name != "dimensions"]
    old_key = {name: getattr(settings, name) for name in before
               if not (name in LATER_SETTINGS and getattr(settings, name) == LATER_SETTINGS[name])}
    spec = run_spec("ucs", settings, {})
    assert dict(spec.specimen) == old_key
    assert spec.key == RunSpec("ucs", tuple(old_key.items()), spec.params, spec.engine).key
    assert spec.engine == f"{ENGINE}, ucs test revision {UCS.revision}"
    assert all_settings(dict(spec.specimen))["dimensions"] == 2
    assert "dimensions" not in settings.model_dump()  # left out of a record at its default


def test_a_3d_run_is_keyed_by_its_dimensions_engine_and_generator():
    in_3d = SpecimenSettings(**CYLINDER)
    spec = run_spec("ucs", in_3d, PARAMS)
    assert dict(spec.specimen)["dimensions"] == 3
    assert "3D engine" in spec.engine and "3D specimen generator" in spec.engine
    # the same settings in 2D (the 3D defaults given) are another run
    same_in_2d = in_3d.model_copy(update={"dimensions": 2})
    assert run_spec("ucs", same_in_2d, PARAMS).key != spec.key
    assert in_3d.model_dump()["dimensions"] == 3


@pytest.fixture(scope="module")
def cylinder_settings():
    return specimen_settings(UCS, CYLINDER)


@pytest.mark.slow  # a genesis of a few seconds
def test_the_ucs_kind_runs_the_3d_test_on_a_cylinder(cylinder_settings):
    s = cylinder_settings
    specimen = UCS.make(s)
    assert isinstance(specimen, Specimen3D) and specimen.shape == "cylinder"
    assert specimen.size_m == pytest.approx((7e-3, 7e-3, 14e-3))
    axis = np.hypot(*(specimen.pos[:, :2] - 3.5e-3).T)
    assert axis.max() <= 3.5e-3  # centres inside the cylinder of the width as diameter
    assert 200 < specimen.n_particles < 400
    result = UCS.run(as_params(PARAMS), specimen, s, lambda x, y: None)
    direct = simulate_ucs(PARAMS, specimen)
    assert (result.E_GPa, result.nu, result.ucs_MPa) == (direct.E_GPa, direct.nu, direct.ucs_MPa)
    assert result.n_particles == specimen.n_particles
    # spheres and cracks in 3D, as the engine gave them
    assert np.array_equal(result.positions, direct.positions)
    broken = {mode: len(xyz) for mode, xyz in result.cracks.items()}
    assert broken == {"tension": result.n_broken_tension, "shear": result.n_broken_shear}
    assert all(xyz.shape[1] == 3 for xyz in result.cracks.values())
    # CD at the reversal of the cylinder's volumetric strain, axial - 2 lateral, before the peak
    axial, lateral, stress, _ = result.curve.T
    peak = int(np.argmax(stress))
    volumetric = axial[:peak + 1] - 2 * lateral[:peak + 1]
    assert result.cd_MPa == stress[int(np.argmax(volumetric))]


def drawn_by(monkeypatch, name: str) -> list:
    """The calls (arguments) of `rockcal.plots.<name>` from now on, each still drawn."""
    from rockcal import plots

    calls, draw = [], getattr(plots, name)
    monkeypatch.setattr(plots, name, lambda *args, **kwargs: calls.append(args) or draw(*args, **kwargs))
    return calls


def read_by_figures(monkeypatch) -> list:
    """What `rockcal.labtests.damage.crack_stresses` gives the figures from now on (the CI and
    CD they mark)."""
    from rockcal import plots

    found, read = [], plots.crack_stresses
    monkeypatch.setattr(plots, "crack_stresses", lambda *args: found.append(read(*args)) or found[-1])
    return found


def crack_stresses_of(responses: dict) -> tuple:
    return responses["ci_MPa"], responses["ci_strain_MPa"], responses["cd_MPa"]


@pytest.mark.slow  # a genesis (cached) and one run through the command
def test_simulate_ucs_in_3d_runs_the_cylinder(cli, tmp_path, cylinder_settings, monkeypatch):
    planes = drawn_by(monkeypatch, "crack_planes")
    marked = read_by_figures(monkeypatch)
    run = cli("simulate", "ucs", "--dimensions", "3", "--width-mm", "7", "--height-mm", "14",
              "--rmin-mm", "0.5", *[f"--set={k}={v}" for k, v in PARAMS.items()], "--json",
              "--out", tmp_path)
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    specimen = UCS.make(cylinder_settings)
    assert summary["n_particles"] == specimen.n_particles
    assert summary["contact_stiffness"] == "pfc5" and summary["specimen"].startswith("cylinder 7x14 mm")
    assert summary["ucs_MPa"] == pytest.approx(simulate_ucs(PARAMS, specimen).ucs_MPa, rel=1e-12)
    assert (tmp_path / "ucs_cracks.png").stat().st_size > 0
    # its crack picture: the cylinder's cracks in 3D on three planes
    (cracks, shape, size_m, path, _), = planes
    assert (shape, path.name) == ("cylinder", "ucs_cracks.png") and size_m == specimen.size_m
    assert sum(len(xyz) for xyz in cracks.values()) == summary["n_broken_tension"] + summary["n_broken_shear"]
    assert all(xyz.shape[1] == 3 for xyz in cracks.values())
    # its curve's CI and CD: the summary's, read over the cylinder's two lateral strains
    assert [crack_stresses_of(vars(found)) for found in marked] == [crack_stresses_of(summary)]


@pytest.mark.slow  # a campaign of at most 18 small 3D runs: about 10 s
def test_a_3d_campaign_of_ucs_targets_runs_the_whole_procedure(tmp_path):
    # targets 5 % off the cylinder's own at the box's centre: within reach whatever its packing
    centre = simulate_ucs(PARAMS, UCS.make(specimen_settings(UCS, CYLINDER)))
    text = CAMPAIGN.format(E_GPa=1.05 * centre.E_GPa, nu=0.95 * centre.nu, ucs_MPa=1.05 * centre.ucs_MPa,
                           sensitivity=SENSITIVITY, samples=8, checks=1, tolerance=0.05, budget=18)
    store = RunStore(tmp_path)
    record = calibrate(planned(parse_campaign(text, tmp_path)), Executor(store, workers=1))
    # the source study's finding holds in 3D: E_c drives E, kn/ks drives nu, sigma_c drives UCS
    ranking = record.sensitivity.ranking
    assert (ranking["E_GPa"][0], ranking["nu"][0], ranking["ucs_MPa"][0]) == ("E_c", "kn_ks", "sigma_c")
    assert record.surrogate_check.trusted
    assert record.accepted and record.dem_runs <= 18
    assert all(abs(e) <= 0.05 for e in record.errors.values())
    final = store.run(record.final_ucs_run_key)
    assert final.specimen["dimensions"] == 3
    assert final.responses["n_particles"] == UCS.make(specimen_settings(UCS, CYLINDER)).n_particles
    store.close()


TRUE = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0}
RECOVERED_WITHIN = {"E_c": 0.05, "kn_ks": 0.05, "sigma_c": 0.10}  # see the twin's docstring


@pytest.mark.slow  # a genesis and a campaign of up to 30 small 3D runs: 25 s
def test_a_3d_twin_recovers_its_modulus_stiffness_ratio_and_strength(tmp_path):
    """UCS targets made by the 3D engine at known E_c, kn/ks and sigma_c, then a campaign on the
    same cylinder that searches all three recovers E_c and kn/ks within 5 %, sigma_c within
    10 %. The cylinder is 8 x 16 mm (about 450 spheres): on the 7 x 14 mm one nu leaves kn/ks 6 %
    off with every target met within 1 %. The shear strength is fixed well above sigma_c (tau_c
    2.5 sigma_c) so that the UCS follows sigma_c at all (at 1.5 sigma_c it moved by less than
    its roughness between sigma_c 36 and 44); even so this few spheres' UCS is rough (at the
    true E_c and kn/ks it is 166.7, 165.2 and 168.1 MPa at sigma_c 40, 42 and 44), so the
    campaign meets its targets within 1 %: within 3 % it stopped at sigma_c 45.7."""
    options = dict(sensitivity="", samples=12, checks=2, tolerance=0.01, budget=30)
    twin = CAMPAIGN.replace("width_mm = 7\nheight_mm = 14", "width_mm = 8\nheight_mm = 16").replace(
        "tau_c = 60", "tau_c = 100")
    assert twin != CAMPAIGN
    stand_in = planned(parse_campaign(twin.format(E_GPa=30.0, nu=0.2, ucs_MPa=100.0, **options), tmp_path))
    lab = execute(run_spec("ucs", stand_in.specimen, stand_in.fixed_params() | TRUE))
    assert lab.status == "ok", lab.message
    targets = {name: float(lab.responses[name]) for name in ("E_GPa", "nu", "ucs_MPa")}
    campaign = planned(parse_campaign(twin.format(**targets, **options), tmp_path))
    record = calibrate(campaign, Executor(RunStore(tmp_path / "out"), workers=1))
    assert record.accepted
    for name in TRUE:
        assert record.identified[name] == pytest.approx(TRUE[name], rel=RECOVERED_WITHIN[name]), name


@pytest.mark.slow  # a command-line campaign of 14 small 3D runs and its exports: about 20 s
def test_a_3d_calibration_exports_pfc3ds_parameter_file_and_its_spheres(cli, tmp_path, monkeypatch):
    """`rockcal export` of a 3D calibration writes PFC3D's mpParams.p3dat (the identified
    parameters read back), a PFC Python script is refused in one line, and `export-specimen`
    lists the cylinder's spheres with their z and its bonds. Its report says 3D, names the
    cylinder and no beam, shows the UCS run's cracks at the identified point on three planes,
    and its figures mark the run's CI and CD as its record has them."""
    planes = drawn_by(monkeypatch, "crack_planes")
    marked = read_by_figures(monkeypatch)
    text = CAMPAIGN.format(E_GPa=30.0, nu=0.16, ucs_MPa=110.0, sensitivity=SENSITIVITY, samples=8,
                           checks=1, tolerance=0.05, budget=18) + "[uncertainty]\ndraws = 10\n"
    (tmp_path / "rock.toml").write_text(text)
    done = cli("calibrate", tmp_path / "rock.toml", "--out", tmp_path / "out", "--workers", "1", "--json")
    assert done.returncode == 0, done.stderr
    identified = json.loads(done.stdout)["identified"]
    (cracks, shape, _, path, _), = planes
    assert shape == "cylinder" and path == tmp_path / "out" / "cracks_ucs.png"
    assert all(xyz.shape[1] == 3 for xyz in cracks.values())
    report = (tmp_path / "out" / "report.html").read_text()
    assert "<h2>Crack pattern, UCS</h2><figure><img" in report
    assert "(3D)</h1>" in report and "PFC3D" in report and "UCS cylinder Ø7 x 14 mm" in report
    assert "notched-beam bending" not in report and "cracks_bending" not in report  # no beam section
    record = json.loads((tmp_path / "out" / "record.json").read_text())
    final = RunStore(tmp_path / "out", readonly=True).run(record["final_ucs_run_key"])
    assert len(marked) == 2  # the stress-strain curve and the CI / CD figure
    assert all(crack_stresses_of(vars(found)) == crack_stresses_of(final.responses) for found in marked)

    fish = cli("export", tmp_path / "out")
    assert fish.returncode == 0, fish.stderr
    assert "PFC3D" in fish.stdout
    emod = [line for line in fish.stdout.splitlines() if line.strip().startswith("pbm_emod")]
    assert len(emod) == 1 and float(emod[0].split("=")[1].split(";")[0]) == \
        pytest.approx(identified["E_c"] * 1e9, rel=1e-12)
    refused = cli("export", tmp_path / "out", "--format", "pfc-python")
    assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
    assert "--format" in refused.stderr

    listed = cli("export-specimen", tmp_path / "out", "--to", tmp_path / "spheres")
    assert listed.returncode == 0, listed.stderr
    balls = np.genfromtxt(tmp_path / "spheres" / "balls.csv", delimiter=",", names=True)
    assert balls.dtype.names[:5] == ("id", "x_m", "y_m", "z_m", "radius_m")
    assert len(balls) == UCS.make(specimen_settings(UCS, CYLINDER)).n_particles


@pytest.mark.slow  # a genesis of a few seconds
def test_the_first_screen_counts_the_cylinders_spheres(cylinder_settings):
    """The plan's grain count of a 3D cylinder is its packing's cloud less the corners carved
    off (pi/4 of it): within 15 % of the spheres the genesis makes, whose carving by the
    spheres' centres keeps a little more (302 against 271 on this 14-sphere-tall cylinder)."""
    from rockcal.campaign.plan.cost import specimen_size

    planned = specimen_size("ucs", SpecimenSettings(**CYLINDER))[1]
    made = UCS.make(cylinder_settings).n_particles
    assert planned == pytest.approx(made, rel=0.15)


DISK = {"dimensions": 3, "disk_diameter_mm": 14.0, "rmin_mm": 0.5, "brazilian_loading": "strips"}


@pytest.mark.slow  # a genesis and a small 3D Brazilian run: about 10 s
def test_the_brazilian_kind_runs_the_3d_test_on_a_disk():
    """The Brazilian kind in 3D is `simulate_brazilian` on a disk D x D/2: sigma_t = 2 P /
    (pi D t) with its load in kN, the spheres and cracks in 3D; a 3D run
    is keyed by its dimensions."""
    from rockcal.labtests.brazilian import TEST as BRAZILIAN
    from rockcal.labtests.brazilian import simulate_brazilian

    s = specimen_settings(BRAZILIAN, DISK)
    disk = BRAZILIAN.make(s)
    assert disk.shape == "disk" and disk.size_m[1] == pytest.approx(disk.size_m[0] / 2)
    result = BRAZILIAN.run(as_params(PARAMS), disk, s, None)
    alone = simulate_brazilian(as_params(PARAMS), disk, loading="strips")
    assert result.sigma_t_MPa == alone.sigma_t_MPa and result.split == alone.split
    assert result.sigma_t_MPa == pytest.approx(2e-3 * result.P_max_kN / (np.pi * disk.size_m[0] * disk.size_m[1]),
                                               rel=1e-12)
    assert result.positions.shape == (disk.n_particles, 3)
    assert sum(len(c) for c in result.cracks.values()) == result.n_broken_tension + result.n_broken_shear
    assert dict(run_spec("brazilian", SpecimenSettings(**DISK), PARAMS).specimen)["dimensions"] == 3


FLAT_JOINTED = """
[targets.ucs]
E_GPa = 20.0
ucs_MPa = 40.0
[specimen]
dimensions = 3
width_mm = 7
height_mm = 14
rmin_mm = 0.5
[material]
model = "flatjoint"
[search]
bounds = { fj_emod = [10, 30], fj_ten = [5, 15] }
fixed = { fj_coh = 20, fj_nal = 3 }
[surrogate]
samples = 6
checks = 1
[optimizer]
iterations = 20
[acceptance]
max_dem_runs = 9
"""


@pytest.mark.slow  # one small 3D flat-jointed run: about 4 s
def test_a_3d_flat_jointed_campaign_runs_and_its_runs_are_3d_flat_joints(tmp_path):
    """A campaign of the flat-jointed material in 3D on a stand-in forward model (E = fj_emod,
    UCS = 4 fj_ten) identifies its point; the run at it, on the DEM, is the 3D flat-jointed
    cylinder's: elements break, and the peak is reached."""
    specs = []

    class StandIn:
        class store:
            @staticmethod
            def get(spec):
                return None

        def run(self, batch, progress=None):
            specs.extend(batch)
            return [RunResult("ok", {"E_GPa": dict(s.params)["fj_emod"], "nu": 0.2,
                                     "ucs_MPa": 4 * dict(s.params)["fj_ten"], "n_particles": 300},
                              None, 0.0) for s in batch]

    record = calibrate(planned(parse_campaign(FLAT_JOINTED, tmp_path)), StandIn())
    assert record.accepted
    assert record.identified["fj_emod"] == pytest.approx(20.0, rel=0.02)
    assert all(dict(s.specimen)["dimensions"] == 3 and dict(s.params)["fj_nal"] == 3 for s in specs)
    lab = execute(specs[-1])
    assert lab.status == "ok", lab.message
    assert lab.responses["dimensions"] == 3
    assert lab.responses["n_broken_tension"] + lab.responses["n_broken_shear"] > 0
    assert lab.responses["ucs_MPa"] > 0 and lab.cracks.shape[1] == 4
