"""Potyondy & Cundall's (2004) PFC2D Lac du Bonnet granite, with its own genesis settings.

Run by hand: `python benchmarks/pc2004_granite.py [--seeds 3] [--strain gauge|platen]
[--contact-stiffness pfc4|pfc5]` (pfc4: their PFC2D 3.x's contacts, kn = t E_c). Specimen
31.7 x 63.4 mm, R_min 0.27 mm, ratio 1.66, touching pairs bonded (installation gap 0), cloud
porosity 0.08; E_c = Ebar_c = 62 GPa, kn/ks 2.5, sigma_c = tau_c = 157 +- 36 MPa, mu 0.5
(Potyondy & Cundall 2004, IJRMMS 41:1329, Lac du Bonnet granite). Prints E and q_u per packing and their means beside
PFC2D's 70.9 GPa and 199.1 MPa.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from rockcal.specimens.genesis import Genesis
from rockcal.dem.simulate import CONTACT_STIFFNESS
from rockcal.specimens.specimen import random_packing
from rockcal.labtests.ucs import simulate_ucs

PARAMS = {"E_c": 62.0, "kn_ks": 2.5, "sigma_c": 157.0, "sigma_c_sd": 36.0, "tau_c": 157.0,
          "tau_c_sd": 36.0, "mu": 0.5, "lambda": 1.0, "density": 2630.0}
GENESIS = Genesis(install_gap=0.0, cloud_porosity=0.08, pressure_mpa=0.1)
PFC2D = {"E_GPa": 70.9, "ucs_MPa": 199.1}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--strain", default="platen", choices=("gauge", "platen"))
    parser.add_argument("--contact-stiffness", default="pfc4", choices=CONTACT_STIFFNESS)
    args = parser.parse_args()
    rows = []
    for seed in range(1, args.seeds + 1):
        spec = random_packing(31.7, 63.4, 0.27, 1.66, seed, GENESIS)
        r = simulate_ucs(PARAMS, spec, strain=args.strain, contact_stiffness=args.contact_stiffness)
        rows.append({"seed": seed, "E_GPa": r.E_GPa, "nu": r.nu, "ucs_MPa": r.ucs_MPa,
                     "wall_s": r.wall_s} | spec.description())
        print(json.dumps(rows[-1]))
    for key in ("E_GPa", "ucs_MPa"):
        values = np.array([row[key] for row in rows])
        spread = values.std(ddof=1) if len(values) > 1 else 0.0
        print(f"{key}: {values.mean():.1f} ± {spread:.1f} (PFC2D {PFC2D[key]}, "
              f"{100 * (values.mean() / PFC2D[key] - 1):+.1f} %), strain read from the {args.strain}, "
              f"contacts {args.contact_stiffness}")


if __name__ == "__main__":
    main()
