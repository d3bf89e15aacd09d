"""A 2D twin whose lab sheet does not pin every parameter: E, nu and UCS made by rockcal's
engine at a known point of E_c, kn/ks, sigma_c and the installation gap (four parameters,
three targets), then calibrated on them; the identifiability stage marks the parameter the
sheet does not see not pinned, with a range read in the DEM, and names a lab test. The named
test's value at the same point is then added to the targets and the campaign resumed from its
store, as a user would (`rockcal calibrate CAMPAIGN --out OUT --resume`): how close each phase
comes to the point that made the targets, and which parameters it pins.

Small specimens keep it cheap: an 18 x 36 mm UCS prism (about 1,670 grains), a 16 mm Brazilian
disk and a 44 x 10 mm notched beam, R_min 0.25 mm, each target the mean over `--packings`
packings (default 1). Between nearby points their UCS and K_IC scatter by a few %, about the
3 % tolerance, the installation gap's steps most.
tau_c is held at 60 MPa, not the granite's 90: at 90 these specimens' UCS and Brazilian strength
jump between nearby points (a Brazilian disk that does not split), too rough for targets met
within 3 %.

Run by hand: `python benchmarks/twin_identifiability_2d.py [--out runs/twin-identifiability-2d]
[--workers 2] [--set install_gap=0.7] [--tolerance 0.03] [--packings 1]` (minutes on 2 cores; the
folder must not hold a store, or pass --resume to reuse it).
"""

import time
from pathlib import Path

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.job import run_in_folder
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.pool import execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.inverse.identifiability import largest_error
from rockcal.labtests.seeds import mean_over_seeds, seed_list
from rockcal.params import parse_assignments
from twin_3d import twin_arguments

# the secret point: the granite's box, each value a few % to 20 % off its middle or its fixed gap (0.6)
TRUE = {"E_c": 23.0, "kn_ks": 2.3, "sigma_c": 36.0, "install_gap": 0.7}
FIXED = {"tau_c": 60.0, "mu": 0.5}
BOUNDS = {"E_c": (20, 30), "kn_ks": (1, 3), "sigma_c": (30, 50), "install_gap": (0.4, 1.2)}
SHEET = ("E_GPa", "nu", "ucs_MPa")  # the lab sheet: UCS tests only
RANKED = ("brazilian", "bending")  # the lab tests the stage may name
RESPONSE = {"brazilian": "sigma_t_MPa", "bending": "K_IC_MPa_sqrt_m"}
SPECIMEN = {"rmin_mm": 0.25, "width_mm": 18, "height_mm": 36, "seed": 1, "disk_diameter_mm": 16,
            "beam_length_mm": 44, "beam_height_mm": 10, "notch_mm": 3.6, "notch_width_mm": 0.8, "span_mm": 32}


def campaign_text(targets: dict, tolerance: float, extra: dict, packings: int) -> str:
    """The twin's campaign: the UCS targets, and `extra` ({test: {response: value}}) beside them,
    each the mean over `packings` packings."""
    sections = "".join(f"[targets.{test}]\npackings = {packings}\n" + "".join(f"{r} = {v!r}\n" for r, v in values.items())
                       for test, values in ({"ucs": targets} | extra).items())
    lines = lambda d: "\n".join(f"{k} = {v!r}" for k, v in d.items())  # noqa: E731
    bounds = ", ".join(f"{k} = [{lo!r}, {hi!r}]" for k, (lo, hi) in BOUNDS.items())
    fixed = ", ".join(f"{k} = {v!r}" for k, v in FIXED.items())
    return f"""[rock]
name = "twin-2d"
{sections}
[validation]
tests = []
[specimen]
{lines(SPECIMEN)}
[search]
bounds = {{ {bounds} }}
fixed = {{ {fixed} }}
[surrogate]
samples = 16
checks = 2
[acceptance]
tolerance = {tolerance!r}
max_dem_runs = 60
[identifiability]
tests = {list(RANKED)!r}
""".replace("'", '"')


def lab_values(true: dict, tolerance: float, packings: int) -> dict:
    """The twin's lab values: each test's mean over its packings at `true`, as the campaign runs it."""
    text = campaign_text({"E_GPa": 40.0, "nu": 0.25, "ucs_MPa": 130.0}, tolerance, {}, packings)
    stand_in = planned(parse_campaign(text, Path(".")))
    params = stand_in.fixed_params() | {k: v for k, v in true.items() if k != "install_gap"}
    values = {}
    for test, names in (("ucs", SHEET), *((t, (RESPONSE[t],)) for t in RANKED)):
        runs = [execute(run_spec(test, stand_in.specimen.model_copy(update={"install_gap": true["install_gap"],
                                                                            "seed": seed}), params))
                for seed in seed_list(stand_in.specimen.seed, packings)]
        assert all(run.status == "ok" for run in runs), [run.message for run in runs]
        mean = mean_over_seeds([run.responses for run in runs])
        values |= {name: float(mean[name]) for name in names}
    return values


def phase(title: str, text: str, out: Path, resume: bool, workers: int, true: dict):
    """One `rockcal calibrate` of the campaign `text` in `out`, and what it found against the truth."""
    started = time.perf_counter()
    record, _ = run_in_folder(planned(parse_campaign(text, out.parent)), text, out, resume=resume,
                              how=dict(workers=workers))
    print(f"\n== {title}: accepted {record.accepted}, {record.executed_runs} DEM runs executed "
          f"({record.dem_runs} parameter sets in the calibration's budget), {time.perf_counter() - started:.0f} s")
    print("errors at the identified point:", ", ".join(f"{k} {100 * v:+.2f} %" for k, v in record.errors.items()))
    found = record.identifiability
    print(f"{'parameter':12s} {'truth':>7s} {'found':>7s} {'error':>8s}  verdict, range (its largest error, share of its box, read by)")
    for name, truth in true.items():
        value, r = record.identified[name], found.ranges[name]
        holds = "holds" if r.low <= truth <= r.high else "MISSES"
        read = "surrogate" if r.verified_ends is None else f"DEM, ends met: {', '.join(r.verified_ends) or 'none'}" + (
            "" if r.met_low is None else f", met over {r.met_low:.4g}-{r.met_high:.4g}")
        print(f"{name:12s} {truth:7.4g} {value:7.4g} {100 * (value / truth - 1):+7.2f} %  "
              f"{'pinned' if r.pinned else 'NOT pinned'}, {r.low:.4g}-{r.high:.4g} (±{100 * largest_error(r.low, r.high, value):.1f} "
              f"% of the value found, {100 * r.share:.0f} % of the box, {read}), "
              f"{holds} the truth")
    for run in found.end_runs:  # in the order they ran, each range read in turn
        errors = "failed" if run.errors is None else ", ".join(f"{k} {100 * v:+.1f} %" for k, v in run.errors.items())
        print(f"  {run.parameter} {run.side:4s} end {', '.join(f'{k} {v:.4g}' for k, v in run.point.items())}: {errors}, "
              f"{'met' if run.met else 'missed'}")
    for t in found.tests:
        print(f"  test {t.test} ({t.response}): {', '.join('-' if v is None else f'{v:.4g}' for v in t.values)} "
              f"at the ends, spread {100 * t.spread:.1f} %, score {t.score:.3f}")
    print(f"identifiability ({found.runs} runs): {found.text}")
    return record


def main() -> None:
    parser = twin_arguments("runs/twin-identifiability-2d", workers=2, tolerance=0.03)
    parser.add_argument("--packings", type=int, default=1)
    parser.add_argument("--resume", action="store_true", help="reuse the runs in --out")
    args = parser.parse_args()
    true = TRUE | parse_assignments(args.set)
    started = time.perf_counter()
    lab = lab_values(true, args.tolerance, args.packings)
    print("twin's lab values:", ", ".join(f"{k} {v:.4g}" for k, v in lab.items()),
          f"({time.perf_counter() - started:.0f} s)")
    sheet = {r: lab[r] for r in SHEET}
    first = phase("the UCS sheet", campaign_text(sheet, args.tolerance, {}, args.packings), args.out, args.resume,
                  args.workers, true)
    useful = [t for t in first.identifiability.tests if t.spread > 2 * args.tolerance]
    if not useful:
        print("no test named: nothing to add")
        return
    named = useful[0]
    extra = {named.test: {named.response: lab[named.response]}}
    phase(f"with the named {named.test} test's {named.response} {lab[named.response]:.4g} added, resumed",
          campaign_text(sheet, args.tolerance, extra, args.packings), args.out, True, args.workers, true)
    print(f"\ntotal {(time.perf_counter() - started) / 60:.1f} min")


if __name__ == "__main__":
    main()
