"""Is the 3D Lac du Bonnet campaign's resolution stable? Its whole sheet (E, nu, UCS, the
Brazilian and direct tensile strengths, m_i of the confined series) at one flat-joint point, on
several packings at the campaign's R_min and at finer ones, each run as the campaign runs it
(docs/campaigns/ldb-3d.toml's specimens, only R_min and the seed changed).

The point: the 2D campaign's closest verified point (docs/validation/lac-du-bonnet.md);
`--set NAME=VALUE` replaces one value. Runs go to a store (`--store`), so a second call reuses them.

Run by hand: `python benchmarks/ldb_3d_resolution.py [--rmin-mm 0.5 0.4] [--seeds 1 2]
[--store ldb-3d-resolution] [--workers 2]`.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import load_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.points import responses_of_test, runs_of
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore
from rockcal.params import parse_assignments

CAMPAIGN = Path(__file__).parents[1] / "docs" / "campaigns" / "ldb-3d.toml"
POINT_2D = {"fj_emod": 62.11, "fj_kratio": 1.277, "fj_ten": 20.94, "fj_coh": 132.3, "fjm_B_frac": 0.73,
            "fj_fa": 0.0, "fj_cohres": 46.3}
TESTS = ("ucs", "brazilian", "direct_tension", "biaxial")
SHOWN = {"n_particles": "spheres", "E_GPa": "E GPa", "nu": "nu", "ucs_MPa": "UCS MPa",
         "sigma_t_MPa": "Brazilian MPa", "sigma_t_direct_MPa": "direct MPa", "m_i": "m_i",
         "phi_deg": "phi deg"}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rmin-mm", type=float, nargs="+", default=[0.5, 0.4])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--store", type=Path, default=Path("ldb-3d-resolution"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    campaign = planned(load_campaign(str(CAMPAIGN))[0])
    params = campaign.fixed_params() | POINT_2D | parse_assignments(args.set)
    executor = Executor(RunStore(args.store), workers=args.workers)
    print(f"load average {os.getloadavg()[0]:.2f}; point {params}", flush=True)
    print("R_min mm | seed | " + " | ".join(SHOWN.values()) + " | UCS/Brazilian | wall s")
    for rmin in args.rmin_mm:
        rows = []
        for seed in args.seeds:
            started = time.perf_counter()
            settings = campaign.specimen.model_copy(update={"rmin_mm": rmin, "seed": seed})
            found = {}
            for test in TESTS:
                specs = [run_spec(test, settings, params, "flatjoint", own) for own in runs_of(campaign, test)]
                results = executor.run(specs)
                bad = [r.message for r in results if r.status != "ok"]
                if bad:
                    raise SystemExit(f"{test} at R_min {rmin}, seed {seed}: {bad[0]}")
                found |= {k: v for k, v in responses_of_test(campaign, test, [r.responses for r in results]).items()
                          if k not in found}
            row = [found[k] for k in SHOWN] + [found["ucs_MPa"] / found["sigma_t_MPa"]]
            rows.append(row)
            print(f"{rmin:g} | {seed} | " + " | ".join(f"{v:.4g}" for v in row)
                  + f" | {time.perf_counter() - started:.0f} (load {os.getloadavg()[0]:.2f})", flush=True)
        print(f"{rmin:g} | mean | " + " | ".join(f"{v:.4g}" for v in np.mean(rows, axis=0)), flush=True)
    executor.close()


if __name__ == "__main__":
    main()
