"""The packings rockcal ships (`rockcal.specimens.specimen.SHIPPED_DIR`): those of the embedded granite
campaign and of its quick look, so that a first `rockcal calibrate` need not make them.

Run by hand: `python benchmarks/shipped_specimens.py` makes each (from the cache, or by genesis)
and copies it into src/rockcal/dem/specimens/; `--check` makes each anew by genesis, without
any cache, and compares it to the shipped file bit for bit (hours for the full-size beams: pick
some with `--only`, e.g. `--only 0 2`). After a change of the generator (GENERATOR_VERSION) the
test suite says they are missing: run this once.
"""

import argparse
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import load_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.quick_look import quick_look
from rockcal.campaign.plan.screen import specimens
from rockcal.specimens.specimen import cache_dir, packing_name, random_packing
from rockcal.labtests.registry import lab_test

SHIPPED = Path(__file__).parents[1] / "src" / "rockcal" / "dem" / "specimens"


def packings() -> list[dict]:
    """`random_packing`'s arguments for every packing of the embedded campaigns, once each."""
    granite = planned(load_campaign(None)[0])
    found = {}
    for campaign in (granite, quick_look(granite)):
        for test, settings in specimens(campaign):
            args = lab_test(test).packing(settings)
            found[packing_name(**args)] = args
    return list(found.values())


def describe(args: dict) -> str:
    return (f"{args['width_mm']:g} x {args['height_mm']:g} mm, R_min {args['rmin_mm']:g} mm, "
            f"seed {args['seed']}")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--check", action="store_true", help="make each anew and compare")
    parser.add_argument("--only", type=int, nargs="*", help="the packings' indices (as listed)")
    args = parser.parse_args()
    todo = list(enumerate(packings()))
    if args.only:
        todo = [todo[i] for i in args.only]
    failed = 0
    for i, p in todo:
        name = packing_name(**p)
        started = time.perf_counter()
        if args.check:
            made = random_packing(**p, cache=False)
            shipped = np.load(SHIPPED / name)
            same = np.array_equal(made.pos, shipped["pos"]) and np.array_equal(made.radius, shipped["radius"])
            failed += not same
            verdict = "the same, bit for bit" if same else "DIFFERENT"
        else:
            random_packing(**p)  # from the cache or the shipped folder, else made and cached
            SHIPPED.mkdir(exist_ok=True)
            if not (SHIPPED / name).exists():
                shutil.copyfile(cache_dir() / name, SHIPPED / name)
            verdict = "shipped"
        print(f"[{i}] {describe(p)} {name}: {verdict} ({time.perf_counter() - started:.0f} s)", flush=True)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
