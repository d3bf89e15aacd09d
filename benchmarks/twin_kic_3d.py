"""A 3D twin of all four lab values: E, nu, UCS and K_IC made by the 3D engine at known E_c,
kn/ks, sigma_c and installation gap (on a 15 x 30 mm cylinder and a 0.3-scale notched beam,
66 x 15 mm at its default thickness, both at R_min 0.75 mm), then a campaign searching those
four on them, multi-fidelity as `docs/campaigns/granite-3d-all-targets.toml` (coarse runs at
R_min 1.125 mm); how close it comes to the parameters that made them, and which of them its
lab sheet pins (the identifiability stage).

Run by hand: `python benchmarks/twin_kic_3d.py [--out runs/twin-kic-3d] [--workers 2]
[--tolerance 0.05] [--set E_c=28 --set kn_ks=3.2 --set sigma_c=45 --set install_gap=0.8]`
(about half an hour on 2 busy cores at a 5 % tolerance; a second run reuses the folder's store).
"""

import os
import time
from pathlib import Path

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.store import RunStore
from rockcal.params import parse_assignments
from twin_3d import lab_values, report, twin_arguments

TRUE = {"E_c": 28.0, "kn_ks": 3.2, "sigma_c": 45.0, "install_gap": 0.8}
TARGETS = {"ucs": ("E_GPa", "nu", "ucs_MPa"), "bending": ("K_IC_MPa_sqrt_m",)}
CAMPAIGN = """
[rock]
name = "twin-kic-3d"
density_kg_m3 = 2622

[targets.ucs]
E_GPa = {E_GPa!r}
nu = {nu!r}
ucs_MPa = {ucs_MPa!r}

[targets.bending]
K_IC_MPa_sqrt_m = {K_IC_MPa_sqrt_m!r}

[validation]
tests = []

[specimen]
dimensions = 3
width_mm = 15
height_mm = 30
rmin_mm = 0.75
beam_length_mm = 66
beam_height_mm = 15
notch_mm = 5.4
notch_width_mm = 0.0
span_mm = 48
stop_fraction = 0.9
install_gap = {install_gap!r}

[search]
bounds = {{ E_c = [18, 40], kn_ks = [1.5, 5], sigma_c = [20, 90], install_gap = [0.4, 1.2] }}
fixed = {{ tau_c = 90, mu = 0.5 }}

[surrogate]
coarse_samples = 16
coarse_factor = 1.5
samples = 4
samples_every_test = 2
checks = 1

[acceptance]
tolerance = {tolerance!r}
max_dem_runs = 40
candidates = 1
"""


def main() -> None:
    args = twin_arguments("runs/twin-kic-3d", workers=2, tolerance=0.02).parse_args()
    true = TRUE | parse_assignments(args.set)
    started = time.perf_counter()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    stand_in = planned(parse_campaign(CAMPAIGN.format(E_GPa=1.0, nu=0.2, ucs_MPa=1.0, K_IC_MPa_sqrt_m=1.0,
                                                      install_gap=true["install_gap"], tolerance=args.tolerance),
                                      Path.cwd()))
    params = stand_in.fixed_params() | {k: v for k, v in true.items() if k != "install_gap"}
    targets, runs = lab_values(stand_in.specimen, params, TARGETS)
    for test, names in TARGETS.items():
        print(f"twin's {test}: " + ", ".join(f"{k} {targets[k]:.4g}" for k in names) +
              f" ({runs[test].responses['n_particles']:.0f} spheres)", flush=True)
    text = CAMPAIGN.format(**targets, install_gap=0.6, tolerance=args.tolerance)
    campaign = planned(parse_campaign(text, Path.cwd()))
    record = calibrate(campaign, Executor(RunStore(args.out), workers=args.workers))
    report(record, true, started)
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
