"""UCS, Brazilian and direct tensile strength of the flat-jointed material over slit fraction
and N_r, beside the parallel bond's on the same grains, both at the parallel bond's granite
defaults (E_c = E* = 21.65 GPa, kn/ks = kappa* = 1.9, sigma_c = fj_ten 36.55 MPa,
tau_c = fj_coh 90 MPa, mu 0.5, constant strengths).

Every run goes through a run store, as a campaign's do: a table stopped part-way resumes where it
stopped, and `--workers` runs it in parallel. The specimens are the source's: the UCS prism
50 x 100 mm (the direct-tension prism too) and the Brazilian disk D 50 mm, on packings 1 to
`--packings`.

Run by hand:
    python benchmarks/fjm_table.py --store runs/fjm-table-half --rmin-mm 0.5   # about 20 min on one core
    python benchmarks/fjm_table.py --store runs/fjm-table --rmin-mm 0.25       # full size: 16 x the work
    python benchmarks/fjm_table.py --store runs/fjm-table --rmin-mm 0.25 --rows cross --workers 2  # 5 of its 9 flat-joint rows
Prints one markdown row per material: mean +- sd over the packings of E, UCS, Brazilian and
direct sigma_t, and UCS over each (the range over packings in brackets).
"""

import argparse
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore

GRANITE = {"fj_emod": 21.65, "fj_kratio": 1.9, "fj_ten": 36.55, "fj_coh": 90.0, "fj_fric": 0.5}
TESTS = {"ucs": ("E_GPa", "ucs_MPa"), "brazilian": ("sigma_t_MPa",), "direct_tension": ("sigma_t_direct_MPa",)}


SLITS, NRS = (0.0, 0.3, 0.6), (1, 2, 3)


def materials(rows: str) -> list[tuple[str, str, dict]]:
    """(row name, material, parameters): the parallel bond, then the flat joint at each slit
    fraction and N_r ("grid"), or N_r 2 at each slit fraction and slit 0.3 at each N_r ("cross")."""
    pairs = [(slit, nr) for slit in SLITS for nr in NRS if rows == "grid" or nr == 2 or slit == 0.3]
    return [("parallel bond", "parallel_bond", {})] + [
        (f"flat joint, slit {slit:g}, N_r {nr}", "flatjoint", GRANITE | {"fj_nr": nr, "fjm_B_frac": 1.0 - slit})
        for slit, nr in pairs]


def _spread(values: np.ndarray, digits: int) -> str:
    sd = values.std(ddof=1) if len(values) > 1 else 0.0
    return f"{values.mean():.{digits}f} ± {sd:.{digits}f}"


def _ratio(ucs: np.ndarray, strength: np.ndarray) -> str:
    r = ucs / strength
    return f"{ucs.mean() / strength.mean():.1f} ({r.min():.1f}–{r.max():.1f})"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--store", type=Path, required=True, help="folder of the run store (made if new)")
    parser.add_argument("--rmin-mm", type=float, default=0.25)
    parser.add_argument("--packings", type=int, default=3)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--rows", choices=("grid", "cross"), default="grid",
                        help="grid: every slit fraction with every N_r; cross: N_r 2 over the slit "
                             "fractions and slit 0.3 over N_r (5 of the 9 flat-joint rows)")
    args = parser.parse_args()
    args.store.mkdir(parents=True, exist_ok=True)
    rows = materials(args.rows)
    seeds = range(1, args.packings + 1)
    specs = [run_spec(test, SpecimenSettings(rmin_mm=args.rmin_mm, seed=seed), params, model)
             for _, model, params in rows for seed in seeds for test in TESTS]
    results = iter(Executor(RunStore(args.store), workers=args.workers).run(specs))
    print(f"R_min {args.rmin_mm:g} mm, packings 1-{args.packings}\n")
    print("| material | E (GPa) | UCS (MPa) | Brazilian σ_t (MPa) | direct σ_t (MPa) | UCS / Brazilian | UCS / direct |")
    print("|---|---|---|---|---|---|---|")
    for name, _, _ in rows:
        found = {r: [] for names in TESTS.values() for r in names}
        for _ in seeds:
            for test, names in TESTS.items():
                result = next(results)
                for r in names:
                    found[r].append(result.responses[r] if result.status == "ok" else np.nan)
        v = {r: np.array(x) for r, x in found.items()}
        print(f"| {name} | {_spread(v['E_GPa'], 1)} | {_spread(v['ucs_MPa'], 1)} | {_spread(v['sigma_t_MPa'], 1)} "
              f"| {_spread(v['sigma_t_direct_MPa'], 1)} | {_ratio(v['ucs_MPa'], v['sigma_t_MPa'])} "
              f"| {_ratio(v['ucs_MPa'], v['sigma_t_direct_MPa'])} |")


if __name__ == "__main__":
    main()
