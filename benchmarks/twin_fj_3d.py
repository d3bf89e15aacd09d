"""A 3D twin of the flat-jointed material: UCS and Brazilian targets made by the 3D engine at
known fj_emod, fj_kratio, fj_ten and fj_coh on a small cylinder and disk, then a campaign that
searches those four run on them; how close it comes to the parameters that made them, and the
identifiability stage's verdict on each (pinned, or not pinned with the range that meets the
sheet, and whether that range holds the truth).

E reads fj_emod, ν fj_kratio, the Brazilian strength fj_ten and the UCS fj_coh with fj_ten.
The specimens are small (a 10 x 20 mm cylinder and a 20 mm disk at R_min 0.6 mm) so that a run
takes seconds; their responses are rough, which the tolerance allows for.

Run by hand: `python benchmarks/twin_fj_3d.py [--out twin-fj-3d] [--workers 1]
[--set fj_emod=27 ...] [--tolerance 0.03]` (a second run reuses the folder's store).
"""

import time
from pathlib import Path

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.store import RunStore
from rockcal.params import parse_assignments
from twin_3d import lab_values, report, twin_arguments

TRUE = {"fj_emod": 27.0, "fj_kratio": 2.3, "fj_ten": 14.0, "fj_coh": 33.0}
BOUNDS = {"fj_emod": (15, 45), "fj_kratio": (1.2, 4.0), "fj_ten": (6, 25), "fj_coh": (15, 60)}
FIXED = {"fj_fric": 0.5, "fj_fa": 0, "fj_nr": 2, "fjm_B_frac": 0.9, "fj_ten_cv": 0.1,
         "fj_coh_cv": 0.1}
TARGETS = {"ucs": ("E_GPa", "nu", "ucs_MPa"), "brazilian": ("sigma_t_MPa",)}
CAMPAIGN = """
[material]
model = "flatjoint"
[targets.ucs]
E_GPa = {E_GPa!r}
nu = {nu!r}
ucs_MPa = {ucs_MPa!r}
[targets.brazilian]
sigma_t_MPa = {sigma_t_MPa!r}
[validation]
tests = []
[specimen]
dimensions = 3
width_mm = 10
height_mm = 20
rmin_mm = 0.6
disk_diameter_mm = 20
[search]
bounds = {{ {bounds} }}
fixed = {{ {fixed} }}
[surrogate]
samples = 16
checks = 2
[acceptance]
tolerance = {tolerance!r}
max_dem_runs = 36
"""


def campaign_text(targets: dict, tolerance: float) -> str:
    bounds = ", ".join(f"{k} = [{lo}, {hi}]" for k, (lo, hi) in BOUNDS.items())
    fixed = ", ".join(f"{k} = {v!r}" for k, v in FIXED.items())
    return CAMPAIGN.format(**targets, bounds=bounds, fixed=fixed, tolerance=tolerance)


def main() -> None:
    args = twin_arguments("twin-fj-3d", workers=1, tolerance=0.03).parse_args()
    true = TRUE | parse_assignments(args.set)
    started = time.perf_counter()
    stand_in = {"E_GPa": 30.0, "nu": 0.2, "ucs_MPa": 100.0, "sigma_t_MPa": 10.0}
    stand_in_campaign = planned(parse_campaign(campaign_text(stand_in, args.tolerance), Path.cwd()))
    targets, _ = lab_values(stand_in_campaign.specimen, stand_in_campaign.fixed_params() | true, TARGETS,
                            "flatjoint")
    print("twin's lab values:", ", ".join(f"{k} {v:.4g}" for k, v in targets.items()))
    campaign = planned(parse_campaign(campaign_text(targets, args.tolerance), Path.cwd()))
    record = calibrate(campaign, Executor(RunStore(args.out), workers=args.workers))
    report(record, true, started)


if __name__ == "__main__":
    main()
