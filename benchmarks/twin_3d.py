"""A 3D twin at the 3D granite's size: UCS targets made by the 3D engine at known E_c, kn/ks and
σ_c on the cylinder of `docs/campaigns/granite-3d.toml` (25 x 50 mm, R_min 0.8 mm, about 3 150
spheres), then that campaign, its box and fixed parameters unchanged, run on them; how close
it comes to the parameters that made them.

The test suite's twin (`tests/dem3d/test_campaign_3d.py`) does the same on an 8 x 16 mm
cylinder of about 450 spheres, whose UCS is too rough to hold σ_c within 5 %; this one has
seven times the spheres.

Run by hand: `python benchmarks/twin_3d.py [--out runs/twin-3d] [--workers 2]
[--set E_c=28 --set kn_ks=3.2 --set sigma_c=45] [--tolerance 0.02]` (about 10 min on 2 cores;
a second run reuses the folder's store).
"""

import argparse
import re
import time
from pathlib import Path

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.pool import Executor, execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.materials import DEFAULT_MATERIAL
from rockcal.campaign.runs.store import RunStore
from rockcal.inverse.identifiability import largest_error
from rockcal.params import parse_assignments

CAMPAIGN = Path(__file__).resolve().parents[1] / "docs" / "campaigns" / "granite-3d.toml"
TRUE = {"E_c": 28.0, "kn_ks": 3.2, "sigma_c": 45.0}
TARGETS = ("E_GPa", "nu", "ucs_MPa")
RECOVERED = 0.05  # a parameter found within this share of its truth is recovered


def with_targets(text: str, targets: dict, tolerance: float) -> str:
    """The campaign file's text with its UCS targets and tolerance replaced."""
    for name, value in targets.items():
        text, count = re.subn(rf"^{name} = .*$", f"{name} = {value!r}", text, flags=re.MULTILINE)
        assert count == 1, name
    text, count = re.subn(r"^tolerance = .*$", f"tolerance = {tolerance!r}", text, flags=re.MULTILINE)
    assert count == 1
    return text


def twin_arguments(out: str, workers: int, tolerance: float) -> argparse.ArgumentParser:
    """The twins' common options: the store's folder, the workers, changes to the truth
    (`--set`) and the campaign's tolerance."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", type=Path, default=Path(out))
    parser.add_argument("--workers", type=int, default=workers)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--tolerance", type=float, default=tolerance)
    return parser


def lab_values(specimen, params: dict, targets: dict[str, tuple[str, ...]],
               model: str = DEFAULT_MATERIAL) -> tuple[dict, dict]:
    """The twin's lab values: each test of `targets` run at `params` as a campaign runs it, its
    named responses; and each test's run."""
    values, runs = {}, {}
    for test, names in targets.items():
        run = runs[test] = execute(run_spec(test, specimen, params, model))
        assert run.status == "ok", run.message
        values |= {name: float(run.responses[name]) for name in names}
    return values, runs


def main() -> None:
    args = twin_arguments("runs/twin-3d", workers=2, tolerance=0.02).parse_args()
    true = TRUE | parse_assignments(args.set)
    text = CAMPAIGN.read_text()
    started = time.perf_counter()
    stand_in = planned(parse_campaign(text, CAMPAIGN.parent))
    targets, runs = lab_values(stand_in.specimen, stand_in.fixed_params() | true, {"ucs": TARGETS})
    print("twin's lab values:", ", ".join(f"{k} {v:.4g}" for k, v in targets.items()),
          f"({runs['ucs'].responses['n_particles']:.0f} spheres)")
    campaign = planned(parse_campaign(with_targets(text, targets, args.tolerance), CAMPAIGN.parent))
    record = calibrate(campaign, Executor(RunStore(args.out), workers=args.workers))
    report(record, true, started)


def report(record, true: dict, started: float) -> None:
    """A twin's campaign against its truth: each parameter found, its error and its verdict
    (recovered within 5 %, else whether the sheet pins it and its range holds the truth, else
    missed), the errors at the identified point, and which parameters the twin's sheet pins
    and whether each range holds the truth."""
    print(f"accepted {record.accepted}, {record.dem_runs} parameter sets, "
          f"{(time.perf_counter() - started) / 60:.1f} min")
    ranges = record.identifiability.ranges if record.identifiability is not None else {}
    for name, value in true.items():
        found, r = record.identified[name], ranges.get(name)
        verdict = ("recovered" if abs(found / value - 1) <= RECOVERED else "MISSED" if r is None or
                   not r.low <= value <= r.high else f"{'' if r.pinned else 'not '}pinned, its range holds the truth")
        print(f"{name:12s} true {value:8.4g}  found {found:8.4g}  {100 * (found / value - 1):+6.2f} %  {verdict}")
    print("errors at the identified point:",
          ", ".join(f"{k} {100 * v:+.2f} %" for k, v in record.errors.items()))
    found = record.identifiability
    if found is not None:
        for name, r in found.ranges.items():
            holds = "holds" if r.low <= true[name] <= r.high else "misses"
            read = "the surrogate" if r.verified_ends is None else "DEM" + (
                "" if r.met_low is None else f", met over {r.met_low:.4g}-{r.met_high:.4g}")
            error = largest_error(r.low, r.high, record.identified[name])
            print(f"{name:12s} {'pinned' if r.pinned else 'not pinned'}: {r.low:.4g}-{r.high:.4g} (the value found "
                  f"within {100 * error:.1f} % of it, {100 * r.share:.0f} % of its box, {read}), {holds} the truth")
        print("identifiability:", found.text)


if __name__ == "__main__":
    main()
