"""The genesis time of clumped specimens against the balls': the same cloud (size, R_min, ratio,
seed) packed as balls (`packing.pack_box`) and as clumps of each template asked for
(`clump_genesis.pack_clumps`), each timed by its own clock on one thread, in one run; for the
clumps the rounds of the pressure-and-floater loop (those with floaters), and of each packing
its porosity, contacts per grain and floaters left. Nothing is cached: every packing is made.

Run by hand: `python benchmarks/clump_genesis.py [--width-mm 25] [--rmin-mm 0.25] [--seed 1]
[--shapes two-pebble three-pebble]`.
"""

import argparse
import json
import logging
import re
import time

import numba
import numpy as np

from rockcal.specimens import clump_genesis, packing
from rockcal.materials.clump_templates import template
from rockcal.specimens.genesis import floaters
from rockcal.specimens.specimen import Specimen


class Rounds(logging.Handler):
    """The last clumped genesis' summary line (`clump_genesis._pack`)."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.rounds = self.floater_rounds = None

    def emit(self, record):
        found = re.search(r"(\d+) rounds, (\d+) of them floater rounds", record.getMessage())
        if found:
            self.rounds, self.floater_rounds = int(found[1]), int(found[2])


def described(pos, radius, clump_of, width, height, pressure) -> dict:
    """A packing's grains, pressure, porosity, contacts per grain and floaters left (balls' by
    `genesis.floaters`, clumps' by `clump_genesis.floating_clumps`)."""
    spec = Specimen(pos, radius, np.empty((0, 2), np.int64), width, height, "", clump_of=clump_of)
    left = floaters(pos, radius, width, height) if clump_of is None else \
        clump_genesis.floating_clumps(pos, radius, clump_of, width, height)
    return {"grains": spec.n_grains, "pressure_mpa": round(pressure, 4),
            "porosity": round(spec.porosity, 4), "contacts_per_grain": round(spec.coordination(), 2),
            "floaters": int(np.count_nonzero(left))}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width-mm", type=float, default=25.0)
    parser.add_argument("--rmin-mm", type=float, default=0.25)
    parser.add_argument("--ratio", type=float, default=1.65)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--shapes", nargs="+", default=["two-pebble", "three-pebble"])
    args = parser.parse_args()
    numba.set_num_threads(1)
    width, height = 1e-3 * args.width_mm, 2e-3 * args.width_mm
    box = (width, height, 1e-3 * args.rmin_mm, args.ratio, args.seed, 0.09, 0.1)
    small = (4e-3, 8e-3, 0.5e-3, 1.25, 1, 0.09, 0.1)
    rounds = Rounds()
    log = logging.getLogger("rockcal.specimens.clump_genesis")
    log.setLevel(logging.INFO)
    log.addHandler(rounds)

    packing.pack_box(*small)  # compile
    started = time.perf_counter()
    pos, radius, pressure = packing.pack_box(*box)
    ball_s = time.perf_counter() - started
    rows = {"ball": {"s": round(ball_s, 1), **described(pos, radius, None, width, height, pressure)}}
    for shape in args.shapes:
        clump_genesis.pack_clumps(template(shape), *small)  # compile
        started = time.perf_counter()
        pos, radius, pressure, clump_of = clump_genesis.pack_clumps(template(shape), *box)
        seconds = time.perf_counter() - started
        rows[shape] = {"s": round(seconds, 1), "over_ball": round(seconds / ball_s, 2),
                       "rounds": rounds.rounds, "floater_rounds": rounds.floater_rounds,
                       **described(pos, radius, clump_of, width, height, pressure)}
    print(json.dumps({"width_mm": args.width_mm, "height_mm": 2 * args.width_mm,
                      "rmin_mm": args.rmin_mm, "ratio": args.ratio, "seed": args.seed, **rows},
                     indent=2))


if __name__ == "__main__":
    main()
