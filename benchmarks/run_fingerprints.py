"""A fingerprint of every registered lab test's run on both materials, in 2D (balls and
two-pebble clumps) and 3D, on small specimens: the run's key and a SHA-256 of its responses,
curve and cracks, or the message of a combination the tool refuses. A change that must not move
the engine's numbers (a refactor) prints the same lines before and after; a different processor
of the same kind prints the same lines too (`docs/concepts/reproducibility.md`).

    python benchmarks/run_fingerprints.py            # about 2 min on one core, specimens cached
"""

import hashlib
import json

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.pool import execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.errors import InputError
from rockcal.labtests.registry import LAB_TESTS

SIZES = dict(rmin_mm=0.4, width_mm=8, height_mm=16, disk_diameter_mm=10, beam_length_mm=44, beam_height_mm=10,
             notch_mm=3.6, notch_width_mm=0.8, span_mm=32)
VARIANTS = {  # name: the specimen settings beyond SIZES, and the tests it runs (None: all)
    "2D balls": ({}, None),
    "2D clumps": ({"grain_shape": "two-pebble"}, None),
    "2D jaws": ({"brazilian_loading": "isrm"}, ("brazilian",)),
    "2D strips": ({"brazilian_loading": "strips"}, ("brazilian",)),
    "3D spheres": ({"dimensions": 3, "disk_diameter_mm": 16}, None),  # a disk D/2 thick: 4 spheres across
    "3D strips": ({"dimensions": 3, "disk_diameter_mm": 16, "brazilian_loading": "strips"}, ("brazilian",)),
}
OWN = {"biaxial": {"confinement_mpa": 5.0}}  # its servo-controlled side walls at work
MATERIALS = {
    "parallel_bond": {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0, "tau_c": 60.0, "sigma_c_cv": 0.2,
                      "tau_c_cv": 0.2, "phi_b": 20.0},
    "flatjoint": {"fj_emod": 30.0, "fj_kratio": 2.0, "fj_ten": 20.0, "fj_ten_cv": 0.2, "fj_coh": 60.0,
                  "fj_coh_cv": 0.2, "fj_fa": 30.0, "fj_nr": 2, "fjm_B_frac": 0.8},
}


def fingerprint(result) -> str:
    digest = hashlib.sha256(json.dumps(result.responses, sort_keys=True).encode())
    for array in (result.curve, result.cracks):
        if array is not None:
            digest.update(array.tobytes())
    return digest.hexdigest()[:16]


def main() -> None:
    for variant, (extra, tests) in VARIANTS.items():
        settings = SpecimenSettings(**SIZES | extra)
        for model, params in MATERIALS.items():
            for test in tests or LAB_TESTS:
                line = f"{variant:10s} {model:13s} {test:15s}"
                try:
                    LAB_TESTS[test].check_dimensions(settings.dimensions, model)
                    spec = run_spec(test, settings, params, model, OWN.get(test))
                except InputError as error:
                    print(f"{line} refused: {error}", flush=True)
                    continue
                result = execute(spec)
                print(f"{line} key {spec.key}  {result.status:6s} {fingerprint(result)}  {result.message}",
                      flush=True)


if __name__ == "__main__":
    main()
