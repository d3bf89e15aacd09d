"""Which of PFC's parallel-bond knobs moves the 3D granite's ν apart from its UCS / K_IC? At a
point of `docs/campaigns/granite-3d-all-targets.toml`'s search (E_c, kn_ks, sigma_c and the
installation gap), one knob at a time that the campaign holds fixed or tied (mu, the bond's own
stiffness ratio knbar_ksbar, mcf, tau_c, lambda, Ebar_c apart from E_c): each row's E, ν, UCS
(the means over the packings), K_IC (the beam on the first packing), UCS / K_IC and its runs'
wall and processor time, on the campaign's specimens (coarse: R_min x its coarse_factor).

Run by hand: `python benchmarks/granite_3d_knobs.py [--full] [--packings 3] [--point nearest]
[--only base mu=0.8 ...]` (one process; numba's threads as NUMBA_NUM_THREADS says).
"""

import argparse
import os
import time
from pathlib import Path

import numba
import numpy as np

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.pool import execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.labtests.seeds import seed_list

CAMPAIGN = Path(__file__).resolve().parents[1] / "docs" / "campaigns" / "granite-3d-all-targets.toml"
LAB = {"E_GPa": 41.5, "nu": 0.23, "ucs_MPa": 138.8, "K_IC_MPa_sqrt_m": 1.057}
# verified points of Fracture toughness, the granite's four lab values in 3D: the search with
# the full moment and tau_c 90 MPa
POINTS = {
    "nearest": {"E_c": 19.75, "kn_ks": 2.842, "sigma_c": 16.76, "install_gap": 1.309, "mcf": 1.0, "tau_c": 90.0},
    "nu": {"E_c": 28.43, "kn_ks": 3.540, "sigma_c": 22.91, "install_gap": 0.872, "mcf": 1.0, "tau_c": 90.0},
    # the search without moment, tau_c 90 MPa: its nearest (K_IC -4 %, UCS +45 %)
    "no-moment": {"E_c": 28.64, "kn_ks": 1.902, "sigma_c": 9.25, "install_gap": 0.6, "mcf": 0.0, "tau_c": 90.0},
    # and with a lower cohesion, E_c, kn_ks and sigma_c moved by hand: within 6.4 % of all four
    "four": {"E_c": 27.5, "kn_ks": 2.3, "sigma_c": 9.8, "install_gap": 0.6, "mcf": 0.0, "tau_c": 60.0},
}


def knobs(point: dict) -> dict[str, dict]:
    """Each row's change to the point, by its label: one PFC knob at a time."""
    s, e, k = point["sigma_c"], point["E_c"], point["kn_ks"]
    return {
        "base": {},
        "mu=0.8": {"mu": 0.8}, "mu=1.0": {"mu": 1.0},
        "knbar_ksbar=4.5": {"knbar_ksbar": 4.5}, "knbar_ksbar=2.0": {"knbar_ksbar": 2.0},
        "kn_ks=4.5 (bond's held)": {"kn_ks": 4.5, "knbar_ksbar": k},
        "mcf=0.5": {"mcf": 0.5}, "mcf=0": {"mcf": 0.0},
        "tau_c=2 sigma_c": {"tau_c": 2 * s}, "tau_c=sigma_c": {"tau_c": s}, "tau_c=0.5 sigma_c": {"tau_c": 0.5 * s},
        "lambda=0.7": {"lambda": 0.7}, "lambda=0.5": {"lambda": 0.5},
        "Ebar_c=0.5 E_c": {"Ebar_c": 0.5 * e}, "Ebar_c=2 E_c": {"Ebar_c": 2 * e},
    }


def row(campaign, point: dict, change: dict, full: bool, packings: int) -> dict:
    """One row: the tests' responses at the point with `change`, and their runs' times."""
    params = campaign.fixed_params() | point | change
    gap = {"install_gap": params.pop("install_gap")}
    settings = (campaign.specimen if full else campaign.coarse_specimen()).model_copy(update=gap)
    wall = cpu = 0.0
    ucs = []
    for test, seeds in (("ucs", seed_list(settings.seed, packings)), ("bending", [settings.seed])):
        for seed in seeds:
            started = time.process_time()
            r = execute(run_spec(test, settings.model_copy(update={"seed": seed}), params))
            cpu += time.process_time() - started
            wall += r.wall_s
            assert r.status == "ok", r.message
            if test == "ucs":
                ucs.append(r.responses)
            else:
                k_ic = r.responses["K_IC_MPa_sqrt_m"]
    means = {name: float(np.mean([u[name] for u in ucs])) for name in ("E_GPa", "nu", "ucs_MPa")}
    return means | {"K_IC_MPa_sqrt_m": k_ic, "wall_s": wall, "cpu_s": cpu,
                    "spheres": ucs[0]["n_particles"], "shear": np.mean([u["n_broken_shear"] for u in ucs]),
                    "tension": np.mean([u["n_broken_tension"] for u in ucs])}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--full", action="store_true", help="the campaign's R_min, not its coarse runs'")
    parser.add_argument("--packings", type=int, default=3)
    parser.add_argument("--point", choices=POINTS, action="append", help="default: nearest and nu")
    parser.add_argument("--only", nargs="+", help="the rows of these labels (default: every knob)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a knob of the rows' own: a row `NAME=VALUE` of it")
    args = parser.parse_args()
    campaign = planned(parse_campaign(CAMPAIGN.read_text(), CAMPAIGN.parent))
    rmin = campaign.specimen.rmin_mm * (1 if args.full else campaign.surrogate.coarse_factor)
    print(f"R_min {rmin:g} mm, UCS over {args.packings} packings, the beam on packing 1; threads "
          f"{numba.get_num_threads()}, load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores", flush=True)
    print("| point | knob | E GPa | ν | UCS MPa | K_IC MPa·m^0.5 | UCS / K_IC m^-0.5 | E | ν | UCS | K_IC "
          "| bonds broken in shear | wall s | processor s |")
    print("|" + "---|" * 14)
    for name in args.point or ["nearest", "nu"]:
        point = POINTS[name]
        rows = knobs(point) | {a: {a.split("=")[0]: float(a.split("=")[1])} for a in args.set}
        for label, change in rows.items():
            if args.only and label not in args.only:
                continue
            r = row(campaign, point, change, args.full, args.packings)
            errors = " | ".join(f"{100 * (r[k] / v - 1):+.1f} %" for k, v in LAB.items())
            broken = r["shear"] / max(1.0, r["shear"] + r["tension"])
            print(f"| {name} | {label} | {r['E_GPa']:.1f} | {r['nu']:.3f} | {r['ucs_MPa']:.1f} | "
                  f"{r['K_IC_MPa_sqrt_m']:.3f} | {r['ucs_MPa'] / r['K_IC_MPa_sqrt_m']:.0f} | {errors} | "
                  f"{100 * broken:.0f} % | {r['wall_s']:.0f} | {r['cpu_s']:.0f} |", flush=True)
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
