"""Lac du Bonnet's flat joint over the installation gap: E, UCS and Brazilian strength on three
packings at one point of the `ldb` campaign, only the gap changed. Does a wider gap (more
joints, a higher coordination) lift UCS / Brazilian toward the lab's 23?

Run by hand: `python benchmarks/ldb_install_gap.py --store runs/ldb-gap [--gaps 0.3 0.6 1.0 1.4]
[--packings 3] [--workers 2] [--set fj_emod=61.17 ...]`. The point defaults to one of the flat
joint without residual strength (`fj_resmode` 0, `fj_fa` 0), the disk between bare flat
platens (`BARE_PLATENS`); the specimens and the other fixed parameters are the `ldb`
campaign's. Every run goes through the run store (a stopped table resumes). Prints a
Markdown table: per gap, the means over the packings and UCS / Brazilian of those means.
About 4 min on 2 cores once the specimens are made.
"""

import argparse
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import load_campaign
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore
from rockcal.labtests.brazilian import STRIP_MODULUS_GPA
from rockcal.params import parse_assignments

POINT = {"fj_emod": 61.17, "fj_kratio": 1.313, "fj_ten": 52.69, "fj_coh": 133.7, "fjm_B_frac": 0.5024,
         "fj_fa": 0.0, "fj_resmode": 0}
# the campaign loads its disk between strips; this table is of bare platens (the default
# strip modulus, which they do not use)
BARE_PLATENS = {"brazilian_loading": "flat", "strip_modulus_gpa": STRIP_MODULUS_GPA}
TESTS = {"ucs": ("E_GPa", "ucs_MPa"), "brazilian": ("sigma_t_MPa",)}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--store", type=Path, required=True, help="folder of the run store (made if new)")
    parser.add_argument("--gaps", type=float, nargs="+", default=[0.3, 0.6, 1.0, 1.4],
                        help="installation gaps, fractions of R_min (the campaign's is 0.6)")
    parser.add_argument("--packings", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    campaign, _ = load_campaign("ldb")
    point = POINT | parse_assignments(args.set)
    params = campaign.fixed_params() | point
    seeds = range(campaign.specimen.seed, campaign.specimen.seed + args.packings)
    cases = [(gap, seed, test) for gap in args.gaps for seed in seeds for test in TESTS]
    specs = [run_spec(test, campaign.specimen.model_copy(update={"install_gap": gap, "seed": seed} | BARE_PLATENS),
                      params, campaign.material.model) for gap, seed, test in cases]
    args.store.mkdir(parents=True, exist_ok=True)
    executor = Executor(RunStore(args.store), workers=args.workers)
    try:
        results = executor.run(specs)
    finally:
        executor.close()
    found = {}
    for (gap, _, test), result in zip(cases, results):
        for name in TESTS[test]:
            value = result.responses[name] if result.status == "ok" else np.nan
            found.setdefault(gap, {}).setdefault(name, []).append(value)
    print(f"{', '.join(f'{k} {v:g}' for k, v in point.items())}; packings {seeds.start}-{seeds.stop - 1}\n")
    print("| gap (R_min) | E (GPa) | UCS (MPa) | Brazilian σ_t (MPa), per packing | UCS / Brazilian |")
    print("|---|---|---|---|---|")
    for gap, v in found.items():
        e, ucs, bts = (np.mean(v[n]) for n in ("E_GPa", "ucs_MPa", "sigma_t_MPa"))
        per = ", ".join(f"{x:.1f}" for x in v["sigma_t_MPa"])
        print(f"| {gap:g} | {e:.1f} | {ucs:.1f} | {bts:.1f} ({per}) | {ucs / bts:.1f} |")


if __name__ == "__main__":
    main()
