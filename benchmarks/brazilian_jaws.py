"""Brazilian test between flat platens, between flat platens with bearing strips and between
ISRM's curved jaws, at full size: the embedded granite's specimen and fixed parameters at the
point its calibration identifies (E_c 21.65 GPa, kn/ks 1.985, sigma_c 35.61 MPa), a 50 mm disk
on packings 1, 2, 3.

Run by hand: `python benchmarks/brazilian_jaws.py [--diameters-mm 50] [--seeds 1,2,3]
[--loadings flat,isrm,strips] [--strip-modulus-gpa 1.0] [--out DIR] [--json FILE]`, one run at a
time on one thread. Another material's point: `--campaign FILE` (its specimen, material and fixed
parameters) and `--set NAME=VALUE` for each searched parameter, e.g. the flat-jointed granite's
identified point: `--campaign docs/campaigns/granite-flatjoint.toml --set fj_emod=38.03
--set fj_kratio=1.922 --set fj_ten=48.4`.
Prints a table: sigma_t, whether the disk split through its centre, where the loading first
touched it (degrees from the loaded diameter, top and bottom), the closure at the peak, how far
the disk turned and shifted as a whole by the end, the bonds broken by just after the peak,
steps and wall time; then sigma_t's mean and spread per loading and diameter. With --json the
rows are written as each run ends; with --out, each run's crack pattern at the peak and its
curve (PNG, CSV) and the bonds broken by just after the peak (NPZ).
"""

import argparse
import json
import time
from pathlib import Path

import numba
import numpy as np

from rockcal.campaign.input.config import load_campaign
from rockcal.labtests.brazilian import STRIP_MODULUS_GPA, simulate_brazilian
from rockcal.labtests.rig.platens import disk_of
from rockcal.labtests.registry import lab_test
from rockcal.labtests.rig.jaws import JAW_RADIUS_PER_DISK_RADIUS, touching_jaw_centre_y
from rockcal.labtests.settings import specimen_settings
from rockcal.materials import material
from rockcal.params import parse_assignments

IDENTIFIED = {"E_c": 21.65, "kn_ks": 1.985, "sigma_c": 35.61}  # docs/validation/granite-calibration.md


def first_touch_deg(specimen, loading: str) -> tuple[float, float]:
    """Where the loading first touches the disk, top and bottom: the touching grain's angle from
    the loaded diameter seen from the disk's centre (degrees, clockwise positive)."""
    pos, radius = specimen.pos, specimen.radius
    cx, cy = disk_of(specimen).centre
    if loading != "isrm":  # flat platens, bare or with strips: the highest and the lowest grain
        top, bottom = np.argmax(pos[:, 1] + radius), np.argmin(pos[:, 1] - radius)
    else:  # the grain farthest from each jaw's centre of curvature
        diameter = (pos[:, 1] + radius).max() - (pos[:, 1] - radius).min()
        jaw = JAW_RADIUS_PER_DISK_RADIUS * 0.5 * diameter
        reach = [np.hypot(pos[:, 0] - cx, pos[:, 1] - touching_jaw_centre_y(pos, radius, cx, jaw, above))
                 + radius for above in (True, False)]
        top, bottom = (int(np.argmax(np.where(side, r, -np.inf)))
                       for r, side in zip(reach, (pos[:, 1] > cy, pos[:, 1] < cy)))
    return tuple(float(np.degrees(np.arctan2(pos[k, 0] - cx, abs(pos[k, 1] - cy)))) for k in (top, bottom))


def rigid_motion(before: np.ndarray, after: np.ndarray) -> tuple[float, float]:
    """The disk's rotation (degrees, anticlockwise) and sideways shift (mm) as a whole: least
    squares over its grains' displacements."""
    arm = before - before.mean(axis=0)
    moved = after - before
    turn = np.sum(arm[:, 0] * moved[:, 1] - arm[:, 1] * moved[:, 0]) / np.sum(arm**2)
    return float(np.degrees(turn)), float(1e3 * moved[:, 0].mean())


def run(test, params, campaign, diameter_mm: float, seed: int, loading: str, out: Path | None,
        strip_modulus_GPa: float = STRIP_MODULUS_GPA) -> dict:
    values = {k: getattr(campaign.specimen, k) for k in test.settings if hasattr(campaign.specimen, k)}
    settings = specimen_settings(test, values | {"disk_diameter_mm": diameter_mm, "seed": seed,
                                                 "brazilian_loading": loading})
    started = time.perf_counter()
    specimen = test.make(settings)
    made_s = time.perf_counter() - started
    if loading == "strips" and strip_modulus_GPa != STRIP_MODULUS_GPA:  # a strip of another material
        result = simulate_brazilian(params, specimen, loading=loading, strip_modulus_GPa=strip_modulus_GPa,
                                    contact_stiffness=settings["contact_stiffness"])
    else:  # as a campaign runs it
        result = test.run(params, specimen, settings, lambda x, y: None)
    turn, shift = rigid_motion(specimen.pos, result.positions)
    top, bottom = first_touch_deg(specimen, loading)
    row = {"D_mm": diameter_mm, "seed": seed, "loading": loading, "sigma_t_MPa": result.sigma_t_MPa,
           "strip_modulus_GPa": strip_modulus_GPa if loading == "strips" else None,
           "split": result.split, "touch_top_deg": top, "touch_bottom_deg": bottom,
           "closure_at_peak_mm": result.displacement_at_peak_mm,
           "turn_deg": turn, "shift_mm": shift,
           "broken_at_peak": sum(len(v) for v in result.peak_cracks.values()),
           "broken": result.n_broken_tension + result.n_broken_shear, "grains": result.n_particles,
           "steps": result.steps, "wall_s": result.wall_s, "genesis_s": made_s}
    if out is not None:
        from rockcal import plots

        out.mkdir(parents=True, exist_ok=True)
        name = f"brazilian_D{diameter_mm:g}_seed{seed}_{loading}"
        plots.crack_pattern(result.positions, result.radius, result.peak_cracks, out / f"{name}_cracks.png",
                            f"{loading}, packing {seed}: sigma_t {result.sigma_t_MPa:.2f} MPa, "
                            f"{'split' if result.split else 'no central split'} (bonds broken by just after the peak)")
        plots.load_displacement(result.curve, out / f"{name}_curve.png", f"Brazilian, {loading}, packing {seed}")
        np.savetxt(out / f"{name}_curve.csv", result.curve, delimiter=",", header="closure_mm,load_kN_per_m")
        np.savez(out / f"{name}_cracks.npz", centre=disk_of(specimen).centre, diameter_m=1e-3 * result.diameter_mm,
                 grain_m=2 * specimen.radius.mean(), **result.peak_cracks)  # to read the failure mode again
    return row


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--diameters-mm", default="50", help="comma-separated disk diameters, mm")
    parser.add_argument("--seeds", default="1,2,3", help="comma-separated packing seeds")
    parser.add_argument("--loadings", default="flat,isrm,strips")
    parser.add_argument("--strip-modulus-gpa", type=float, default=STRIP_MODULUS_GPA,
                        help="the bearing strips' Young's modulus through their thickness, GPa")
    parser.add_argument("--campaign", default=None, help="a campaign file: its specimen, material and fixed "
                        "parameters (default: the embedded granite at its identified point)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a parameter's value (with --campaign: each searched parameter)")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--out", type=Path, default=None, help="write crack patterns and curves here")
    parser.add_argument("--json", type=Path, default=None, help="write the rows as JSON here")
    args = parser.parse_args()
    numba.set_num_threads(args.threads)
    campaign = load_campaign(args.campaign)[0]
    chosen = parse_assignments(args.set)
    values = campaign.fixed_params() | (chosen if args.campaign else IDENTIFIED | chosen)
    params = material(campaign.material.model).make(values)
    test = lab_test("brazilian")

    rows = []
    print("| D mm | packing | loading | σ_t MPa | split | first touch top, bottom (°) | closure at peak mm "
          "| turn ° | shift mm | broken by peak | steps | s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for diameter in (float(d) for d in args.diameters_mm.split(",")):
        for seed in (int(s) for s in args.seeds.split(",")):
            for loading in args.loadings.split(","):
                r = run(test, params, campaign, diameter, seed, loading, args.out, args.strip_modulus_gpa)
                rows.append(r)
                print(f"| {r['D_mm']:g} | {seed} | {loading} | {r['sigma_t_MPa']:.2f} | "
                      f"{'split' if r['split'] else 'no'} | {r['touch_top_deg']:+.1f}, {r['touch_bottom_deg']:+.1f} | "
                      f"{r['closure_at_peak_mm']:.3f} | "
                      f"{r['turn_deg']:+.2f} | {r['shift_mm']:+.3f} | {r['broken_at_peak']} | {r['steps']} | "
                      f"{r['wall_s']:.0f} |", flush=True)
                if args.json is not None:
                    args.json.write_text(json.dumps(rows, indent=2))
    print()
    for diameter in sorted({r["D_mm"] for r in rows}):
        for loading in args.loadings.split(","):
            values = [r["sigma_t_MPa"] for r in rows if r["D_mm"] == diameter and r["loading"] == loading]
            splits = sum(r["split"] for r in rows if r["D_mm"] == diameter and r["loading"] == loading)
            if values:
                spread = np.std(values, ddof=1) if len(values) > 1 else 0.0
                print(f"D {diameter:g} mm, {loading}: sigma_t {np.mean(values):.2f} ± {spread:.2f} MPa "
                      f"(cv {spread / np.mean(values):.2f}) over {len(values)} packings, {splits:g} central splits")


if __name__ == "__main__":
    main()
