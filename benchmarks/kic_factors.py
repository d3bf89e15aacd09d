"""What moves the notched beam's K_IC and the UCS apart: PFC bond settings at the source's
identified point.

Run by hand: `python benchmarks/kic_factors.py [--store runs/kic-factors] [--rmin-mm 0.25]
[--seeds 3] [--workers 2] [--only cv0,cv023] [--contact-stiffness pfc5]`. Each factor is a set of micro-parameters on top
of the source's identified point (E_c 21.65 GPa, kn/ks 1.9, sigma_c 36.55 MPa, tau_c 90 MPa,
mu 0.5), on the granite campaign's specimens or with some of their settings changed
(installation gap, notch); per factor: K_IC and P_max of the full-size
notched beam over `--seeds` packings, E, nu and UCS of the UCS specimen (seed 1), and UCS / K_IC
(the lab granite: 131 m^-0.5). Runs go through a run store (resumable, never run twice).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import load_campaign
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore
from rockcal.dem.simulate import CONTACT_STIFFNESS

LAB = {"K_IC_MPa_sqrt_m": 1.057, "ucs_MPa": 138.8}
SPREAD = {"sigma_c_cv": 0.23, "tau_c_cv": 0.23}  # the granite default (Potyondy & Cundall's)
FACTORS = {  # name: (micro-parameters on top of the source's point, specimen settings changed)
    "cv023": (SPREAD, {}),
    "cv0": ({}, {}),
    "cv046": ({"sigma_c_cv": 0.46, "tau_c_cv": 0.46}, {}),
    "ten_cv023": ({"sigma_c_cv": 0.23}, {}),
    "cv023_phi30": (SPREAD | {"phi_b": 30.0}, {}),
    "cv023_lambda07": (SPREAD | {"lambda": 0.7}, {}),
    "cv023_mcf05": (SPREAD | {"mcf": 0.5}, {}),
    "cv023_mcf0": (SPREAD | {"mcf": 0.0}, {}),
    "cv023_gap03": (SPREAD, {"install_gap": 0.3}),
    "cv023_gap09": (SPREAD, {"install_gap": 0.9}),
    "cv023_cut": (SPREAD, {"notch_width_mm": 0.0}),
    "cv023_w05": (SPREAD, {"notch_width_mm": 0.5}),  # notch-tip radius 0.25 mm
    "cv023_w1": (SPREAD, {"notch_width_mm": 1.0}),
    "cv0_gap09_cut": ({}, {"install_gap": 0.9, "notch_width_mm": 0.0}),  # the three best together
}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--store", type=Path, default=Path("runs/kic-factors"))
    parser.add_argument("--rmin-mm", type=float, default=None)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--only", default="", help="comma-separated factor names (default: all)")
    parser.add_argument("--contact-stiffness", default=None, choices=CONTACT_STIFFNESS,
                        help="default: the granite campaign's")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()

    granite, _ = load_campaign(None)
    specimen = granite.specimen
    if args.rmin_mm is not None:
        specimen = specimen.model_copy(update={"rmin_mm": args.rmin_mm})
    if args.contact_stiffness is not None:
        specimen = specimen.model_copy(update={"contact_stiffness": args.contact_stiffness})
    names = [n for n in args.only.split(",") if n] or list(FACTORS)
    unknown = sorted(set(names) - set(FACTORS))
    if unknown:
        parser.error(f"unknown factor {unknown[0]!r}; known: {', '.join(FACTORS)}")
    base = {"density": granite.rock.density_kg_m3}  # the MicroParams defaults: the source's point
    specs = {}
    for name in names:
        changes, settings = FACTORS[name]
        params, own = base | changes, specimen.model_copy(update=settings)
        specs[name] = ([run_spec("bending", own.model_copy(update={"seed": own.seed + k}), params)
                        for k in range(args.seeds)],
                       run_spec("ucs", own, params))
    everything = [s for beams, ucs in specs.values() for s in (*beams, ucs)]
    started = time.perf_counter()
    store = RunStore(args.store)
    executor = Executor(store, args.workers)
    try:
        results = dict(zip((s.key for s in everything), executor.run(everything)))
    finally:
        executor.close()
    elapsed = time.perf_counter() - started

    rows = []
    print(f"{'factor':<16} {'K_IC':>13} {'P_max':>7} | {'E':>6} {'nu':>6} {'UCS':>6} | {'UCS/K_IC':>8}")
    for name, (beams, ucs) in specs.items():
        k = [results[s.key].responses.get("K_IC_MPa_sqrt_m", np.nan) for s in beams]
        p = [results[s.key].responses.get("P_max_kN_per_m", np.nan) for s in beams]
        u = results[ucs.key].responses
        row = {"factor": name, "params": FACTORS[name][0], "specimen": FACTORS[name][1],
               "K_IC": float(np.mean(k)),
               "K_IC_sd": float(np.std(k, ddof=1)) if len(k) > 1 else 0.0, "K_IC_per_seed": k,
               "P_max_kN_per_m": float(np.mean(p)), "E_GPa": u.get("E_GPa"), "nu": u.get("nu"),
               "ucs_MPa": u.get("ucs_MPa")}
        row["ucs_over_kic"] = row["ucs_MPa"] / row["K_IC"] if row["ucs_MPa"] else np.nan
        rows.append(row)
        print(f"{name:<16} {row['K_IC']:6.3f} ± {row['K_IC_sd']:4.2f} {row['P_max_kN_per_m']:7.1f} | "
              f"{row['E_GPa']:6.2f} {row['nu']:6.3f} {row['ucs_MPa']:6.1f} | {row['ucs_over_kic']:8.1f}")
    print(f"lab: K_IC {LAB['K_IC_MPa_sqrt_m']}, UCS {LAB['ucs_MPa']}, UCS/K_IC "
          f"{LAB['ucs_MPa'] / LAB['K_IC_MPa_sqrt_m']:.0f}; {executor.executed} runs done now in "
          f"{elapsed:.0f} s on {args.workers} processes")
    if args.json:
        args.json.write_text(json.dumps({"rmin_mm": specimen.rmin_mm, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
