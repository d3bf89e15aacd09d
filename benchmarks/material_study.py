"""What moves a bonded-particle granite's strength ratios: the grain shape, the material and the
flat joint's settings, each at the granite's E and UCS.

For each variant (a material, a grain shape and settings over the granite's calibrated point)
the study

1. brings the variant to the granite's E (41.5 GPa) and UCS (138.8 MPa) by scaling: every
   stiffness (E_c, Ebar_c; fj_emod, lnm_emod) by E_target / E and every strength (sigma_c,
   tau_c; fj_ten, fj_coh, fj_cohres, and absolute spreads) by UCS_target / UCS, from a UCS run
   on packing 1, repeated until both are within SCALE_TOLERANCE. A bonded-particle model with
   no gap that closes under load is exact under this scaling (displacements scale by the ratio
   of strength to stiffness; forces, slip and breakage follow), so the dimensionless ratios
   below are the variant's own, not those of where it started;
2. runs, on packings 1-3: the UCS test, confined compression at 5, 10 and 20 MPa, the
   Brazilian test between bearing strips (`--strip-modulus-gpa`) and direct tension;
3. reads per packing m_i and the Mohr-Coulomb phi and c through the four peaks (sigma3 0, 5,
   10, 20 MPa), UCS / Brazilian, UCS / direct and CD / UCS, and gives their mean and sd.

Every run goes through the run store in OUT: a stopped study resumes, a run done is never run
again. Each run done is kept in the table TABLE (JSON, default OUT/material_study.json; the
full-size study's is `benchmarks/data/material_study_full.json`, the half resolution's clumped
flat joints of three pebbles and of clouds and the Lac du Bonnet point's variants
`benchmarks/data/material_study_half.json`), so a study stopped goes on from its last run, on
another day and machine too; writes OUT/material_study.md (the variants done) and
OUT/material_study.png (m_i against UCS / Brazilian, each variant's mean and sd).

Run by hand: `python benchmarks/material_study.py [--out runs/material-study] [--rmin-mm 0.5]
[--variants pb-ball,pb-two-pebble,...] [--packings 3] [--seeds 2,3] [--tests 20.0,10.0]
[--table TABLE]` (`--list` names the variants). `--seeds` runs only those packings and `--tests`
only those runs of each, in that order: two studies on the same `--table`, each with its own
`--out`, can share a variant's packings, or one packing's runs, between two cores (start the
second once the first has scaled the variant to the granite, and made the packing, or each
would do it).
"""

from __future__ import annotations

import argparse
import fcntl
import json
import math
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import SpecimenSettings, load_campaign
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore
from rockcal.labtests.envelope import envelope_responses

E_TARGET_GPA, UCS_TARGET_MPA = 41.5, 138.8  # the source's granite
SCALE_TOLERANCE = 0.02
MAX_SCALINGS = 4
CONFINEMENTS_MPA = (5.0, 10.0, 20.0)
TESTS = ("ucs", "brazilian", *map(str, CONFINEMENTS_MPA), "direct")  # a packing's runs, by name
STIFFNESSES = ("E_c", "Ebar_c", "fj_emod", "lnm_emod")
STRENGTHS = ("sigma_c", "tau_c", "sigma_c_sd", "tau_c_sd", "fj_ten", "fj_coh", "fj_ten_sd", "fj_coh_sd",
             "fj_cohres")
# the granite's calibrated points: the parallel bond (the embedded campaign's) and the flat
# joint (docs/campaigns/granite-flatjoint.toml's: N_r 2, 30 % slit, phi 0)
PARALLEL_BOND = {"E_c": 21.65, "kn_ks": 1.985, "sigma_c": 35.61}
FLAT_JOINT = {"fj_emod": 38.03, "fj_kratio": 1.922, "fj_ten": 48.4, "fj_coh": 90, "fj_fric": 0.5, "fj_fa": 0,
              "fj_nr": 2, "fjm_B_frac": 0.7, "fj_ten_cv": 0.23, "fj_coh_cv": 0.23, "density": 2622}
# the Lac du Bonnet calibration's closest point (docs/validation/lac-du-bonnet.md): elements weak
# in tension against their cohesion, and a residual cohesion
LAC_DU_BONNET = {"fj_emod": 62.11, "fj_kratio": 1.277, "fj_ten": 20.94, "fj_coh": 132.3, "fj_fric": 0.6,
                 "fj_fa": 0, "fj_nr": 2, "fjm_B_frac": 0.73, "fj_cohres": 46.3, "fj_resmode": 1,
                 "density": 2630}
SHAPES = ("ball", "two-pebble", "three-pebble", "cloud")


def variants() -> dict[str, tuple[str, dict, dict]]:
    """Each variant by name: (material, parameters, specimen settings)."""
    granite, _ = load_campaign(None)
    pb = granite.fixed_params() | PARALLEL_BOND
    found = {}
    for shape in SHAPES:
        found[f"pb-{shape}"] = ("parallel_bond", pb, {"grain_shape": shape})
        found[f"fj-{shape}"] = ("flatjoint", FLAT_JOINT, {"grain_shape": shape})
    flat = {  # the flat joint's own settings, on balls
        "fj-no-slit": {"fjm_B_frac": 1.0},
        "fj-slit-60": {"fjm_B_frac": 0.4},
        "fj-fa-30": {"fj_fa": 30.0},
        "fj-nr-1": {"fj_nr": 1},
        "fj-nr-4": {"fj_nr": 4},
        "fj-residual": {"fj_resmode": 1, "fj_cohres": 45.0},
        "fj-gapped-30": {"fjm_B_frac": 0.7, "fjm_G_frac": 0.3, "fjm_G_m": 0.0025},
    }
    found |= {name: ("flatjoint", FLAT_JOINT | extra, {}) for name, extra in flat.items()}
    found["fj-igap-0.3"] = ("flatjoint", FLAT_JOINT, {"install_gap": 0.3})
    for shape in ("ball", "two-pebble"):
        found[f"fj-ldb-{shape}"] = ("flatjoint", LAC_DU_BONNET, {"grain_shape": shape})
    found["pb-igap-0.3"] = ("parallel_bond", pb, {"install_gap": 0.3})
    return found


def scaled(params: dict, stiffness: float, strength: float) -> dict:
    """The parameters with every stiffness times `stiffness` and every strength times `strength`."""
    factor = {k: stiffness for k in STIFFNESSES} | {k: strength for k in STRENGTHS}
    return {k: v * factor[k] if k in factor and v is not None else v for k, v in params.items()}


class Study:
    def __init__(self, out: Path, specimen: SpecimenSettings, strip_modulus_gpa: float, packings: int,
                 tests: tuple[str, ...] = TESTS):
        self.executor = Executor(RunStore(out), workers=1, threads=1)
        self.specimen, self.strip, self.packings, self.tests = specimen, strip_modulus_gpa, packings, tests

    def run(self, specs: dict) -> dict:
        results = self.executor.run(list(specs.values()))
        failed = [(name, r.message) for name, r in zip(specs, results) if r.status != "ok"]
        if failed:
            raise SystemExit(f"runs failed: {failed}")
        return {name: r.responses for name, r in zip(specs, results)}

    def at_granite(self, model: str, params: dict, settings: dict, steps: list,
                   keep: Callable[..., None]) -> dict:
        """The variant's parameters scaled to the granite's E and UCS on packing 1, going on
        from `params` after the scaling steps `steps` (the (E, UCS) of each UCS run so far);
        each step kept (`keep(params=..., scaling=steps)`) as it is done."""
        specimen = self.specimen.model_copy(update=settings | {"seed": 1})
        while not scaling_done(steps):
            r = self.run({"ucs": run_spec("ucs", specimen, params, model)})["ucs"]
            steps.append((r["E_GPa"], r["ucs_MPa"]))
            if not near_granite(*steps[-1]):
                params = scaled(params, E_TARGET_GPA / r["E_GPa"], UCS_TARGET_MPA / r["ucs_MPa"])
                keep(params=params, scaling=steps)
        return params

    def lab_sheet(self, model: str, params: dict, settings: dict, seeds: list[int],
                  keep: Callable[..., dict]) -> None:
        """Per packing of `seeds` that the variant's row (`keep()`) has no sheet of: the rock
        lab's values at `params`, from the runs of this study's tests that the row lacks, in
        their order. Each run's responses are kept (`keep(seed=..., runs=...)`) as it is done,
        under its packing in the row's "runs", so a packing too long for one sitting goes on
        from its last run and another study may do its other tests; the sheet is kept
        (`keep(seed=..., sheet=...)`) by the study that finds all of them done."""
        for seed in seeds:
            row = keep()
            if any(s["seed"] == seed for s in row["sheets"]):
                continue
            specimen = self.specimen.model_copy(update=settings | {"seed": seed})
            strips = specimen.model_copy(update={"brazilian_loading": "strips", "strip_modulus_gpa": self.strip})
            specs = {"ucs": run_spec("ucs", specimen, params, model),
                     "brazilian": run_spec("brazilian", strips, params, model)}
            specs |= {str(s3): run_spec("biaxial", specimen, params, model, own={"confinement_mpa": s3})
                      for s3 in CONFINEMENTS_MPA}
            specs["direct"] = run_spec("direct_tension", specimen, params, model)
            for name in self.tests:
                if name not in keep()["runs"].get(str(seed), {}):
                    keep(seed=seed, runs=self.run({name: specs[name]}))
            runs = keep()["runs"].get(str(seed), {})
            if set(specs) <= set(runs):
                keep(seed=seed, sheet=sheet(runs) | {"seed": seed})


def near_granite(E_GPa: float, ucs_MPa: float) -> bool:
    return (abs(E_GPa / E_TARGET_GPA - 1) <= SCALE_TOLERANCE
            and abs(ucs_MPa / UCS_TARGET_MPA - 1) <= SCALE_TOLERANCE)


def scaling_done(steps: list) -> bool:
    """Whether the scaling steps so far end it: the last at the granite, or as many as allowed."""
    return len(steps) >= MAX_SCALINGS or bool(steps) and near_granite(*steps[-1])


def sheet(runs: dict) -> dict:
    """A packing's lab values from its runs' responses."""
    ucs = runs["ucs"]
    sigma1 = [ucs["ucs_MPa"]] + [runs[str(s3)]["sigma1_MPa"] for s3 in CONFINEMENTS_MPA]
    fit = envelope_responses([0.0, *CONFINEMENTS_MPA], sigma1)
    bts = runs["brazilian"]["sigma_t_MPa"]
    direct = runs["direct"]["sigma_t_direct_MPa"]
    return {"E_GPa": ucs["E_GPa"], "nu": ucs["nu"], "ucs_MPa": ucs["ucs_MPa"], "phi_deg": fit["phi_deg"],
            "c_MPa": fit["c_MPa"], "m_i": fit["m_i"], "hb_r2": fit["hb_r2"], "sigma1_MPa": sigma1,
            "brazilian_MPa": bts, "split": runs["brazilian"]["split"], "direct_MPa": direct,
            "ucs_bts": ucs["ucs_MPa"] / bts, "ucs_dts": ucs["ucs_MPa"] / direct, "cd_ucs": ucs["cd_ratio"]}


COLUMNS = (("E_GPa", "E (GPa)", 1), ("nu", "ν", 3), ("ucs_MPa", "UCS (MPa)", 1), ("phi_deg", "φ (°)", 1),
           ("c_MPa", "c (MPa)", 1), ("m_i", "m_i", 1), ("brazilian_MPa", "σ_t Braz. (MPa)", 2),
           ("ucs_bts", "UCS / σ_t Braz.", 1), ("direct_MPa", "σ_t direct (MPa)", 2), ("ucs_dts", "UCS / σ_t direct", 1),
           ("cd_ucs", "CD / UCS", 2))


def mean_sd(sheets: list[dict], key: str) -> tuple[float, float]:
    values = np.array([s[key] for s in sheets], float)
    return float(values.mean()), float(values.std(ddof=1)) if len(values) > 1 else 0.0


def shown(rows: dict):
    """The variants to draw, by label: each with all its packings, or with two or more of them
    done (labelled with how many)."""
    for name, row in rows.items():
        done = len(row["sheets"])
        if row.get("complete", True):
            yield name, row
        elif done >= 2:
            yield f"{name} ({done} of {row['packings']} packings)", row


def markdown(rows: dict) -> str:
    head = "| variant | " + " | ".join(title for _, title, _ in COLUMNS) + " | splits |"
    lines = [head, "|" + "---|" * (len(COLUMNS) + 2)]
    for name, row in shown(rows):
        cells = []
        for key, _, digits in COLUMNS:
            mean, sd = mean_sd(row["sheets"], key)
            cells.append("—" if math.isnan(mean) else f"{mean:.{digits}f} ± {sd:.{digits}f}")
        splits = sum(s["split"] for s in row["sheets"])
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {splits:g}/{len(row['sheets'])} |")
    return "\n".join(lines) + "\n"


def figure(rows: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    ax.set_prop_cycle(color=plt.get_cmap("tab20").colors)  # a colour per variant, up to 20
    for name, row in shown(rows):
        (x, dx), (y, dy) = mean_sd(row["sheets"], "ucs_bts"), mean_sd(row["sheets"], "m_i")
        marker = "o" if name.startswith("pb") else "s"
        ax.errorbar(x, y, xerr=dx, yerr=dy, fmt=marker, capsize=3, label=name)
    ax.axhspan(29, 35, color="0.9", zorder=0, label="granite m_i 32 ± 3")
    ax.axvline(23, color="0.5", ls="--", lw=1, label="Lac du Bonnet UCS / σ_t 23")
    ax.set_xlabel("UCS / Brazilian σ_t")
    ax.set_ylabel("Hoek–Brown m_i (σ3 0–20 MPa)")
    ax.legend(fontsize=7, ncol=2)
    ax.set_title("At the granite's E and UCS: mean ± sd over packings")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


class Table:
    """The study's JSON table: a row per variant, kept as each run is done (a stopped study goes
    on from its last run). Each write re-reads the table under a lock and changes only what its
    study did (`update`): other studies may share the table, on other variants or on other
    packings of the same one."""

    def __init__(self, path: Path, rmin_mm: float, packings: int):
        self.path, self.rmin_mm, self.packings = path, rmin_mm, packings

    def rows(self) -> dict:
        rows = json.loads(self.path.read_text()) if self.path.exists() else {}
        return {name: by_packing(row) for name, row in rows.items()}

    def row(self, name: str) -> dict | None:
        """The variant's row, if it has one; a row of another resolution or count of packings
        stops the study."""
        row = self.rows().get(name)
        if row is not None and (row.get("rmin_mm", self.rmin_mm), row.get("packings", self.packings)) \
                != (self.rmin_mm, self.packings):
            raise SystemExit(f"{self.path} holds {name} at R_min {row['rmin_mm']} mm on {row['packings']} "
                             f"packings: give another --table")
        return row

    def update(self, name: str, new_row: dict, change: Callable[[dict], None], markdown_path: Path) -> dict:
        """The variant's row as the table holds it now (or `new_row`), changed by `change`,
        written back; the row."""
        with open(self.path.with_suffix(".lock"), "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)  # another study's write waits: no run lost
            rows = self.rows()
            row = rows.get(name, new_row)
            change(row)
            rows[name] = row
            self.path.write_text(json.dumps(rows, indent=2))
        markdown_path.write_text(markdown(rows))
        return row


def by_packing(row: dict) -> dict:
    """A row with its sheets and runs by packing: each sheet with its "seed", the runs of each
    packing under way under its seed. (A row kept by one study at a time held the sheets in
    packing order and the one packing under way's runs with a "seed" among them.)"""
    for k, s in enumerate(row["sheets"]):
        s.setdefault("seed", k + 1)
    runs = row.get("runs", {})
    if "seed" in runs:
        seed = runs.pop("seed")
        runs = {str(seed): runs} if runs else {}
    row["runs"] = runs
    return row


def measure(study: Study, table: Table, name: str, model: str, params: dict, settings: dict,
            seeds: list[int], markdown_path: Path) -> None:
    """A variant's row: scaled to the granite (from its row's last scaling step, if any), then
    its packings of `seeds` that the row lacks, each run kept in the table as it is done.
    Its wall_s adds up the time of every study that worked on it."""
    clock = time.perf_counter()
    row = table.row(name) or {"model": model, "settings": settings, "rmin_mm": table.rmin_mm,
                              "packings": table.packings, "params": params, "scaling": [],
                              "sheets": [], "runs": {}, "wall_s": 0.0}

    def keep(seed: int | None = None, runs: dict | None = None, sheet: dict | None = None,
             **scaling) -> dict:
        """Keep in the table what this study did: a scaling step (params, scaling), a packing's
        runs so far, or its sheet; the row as the table then holds it."""
        nonlocal clock, row
        now = time.perf_counter()

        def change(stored: dict) -> None:
            stored.update(scaling)
            if runs is not None:
                stored["runs"].setdefault(str(seed), {}).update(runs)
            if sheet is not None:
                stored["runs"].pop(str(seed), None)
                stored["sheets"] = sorted([s for s in stored["sheets"] if s["seed"] != seed] + [sheet],
                                          key=lambda s: s["seed"])
            stored["complete"] = len(stored["sheets"]) == table.packings
            stored["wall_s"] = round(stored["wall_s"] + now - clock, 1)

        row = table.update(name, row, change, markdown_path)
        clock = now
        return row

    keep(params=study.at_granite(model, row["params"], settings, row["scaling"], keep))
    study.lab_sheet(model, row["params"], settings, seeds, keep)
    print(f"{name}: done, {row['wall_s']} s in all", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", type=Path, default=Path("runs/material-study"))
    parser.add_argument("--rmin-mm", type=float, default=0.5, help="the full size's is 0.25")
    parser.add_argument("--variants", default=",".join(f"pb-{s}" for s in SHAPES))
    parser.add_argument("--packings", type=int, default=3)
    parser.add_argument("--seeds", help="the packings this study runs, e.g. 3 or 2,3 (default: "
                                        "all); the others are left to another study")
    parser.add_argument("--tests", default=",".join(TESTS),
                        help="the runs this study makes on each packing, in this order; the others "
                             "are left to another study")
    parser.add_argument("--strip-modulus-gpa", type=float, default=0.5)
    parser.add_argument("--table", type=Path, help="the JSON table kept run by run "
                                                    "(default OUT/material_study.json)")
    parser.add_argument("--list", action="store_true", help="name the variants and stop")
    args = parser.parse_args()
    known = variants()
    if args.list:
        print("\n".join(known))
        return
    granite, _ = load_campaign(None)
    specimen = granite.specimen.model_copy(update={"rmin_mm": args.rmin_mm})
    args.out.mkdir(parents=True, exist_ok=True)
    tests = tuple(args.tests.split(","))
    if not set(tests) <= set(TESTS):
        raise SystemExit(f"--tests: the tests are {','.join(TESTS)}")
    study = Study(args.out, specimen, args.strip_modulus_gpa, args.packings, tests)
    table = Table(args.table or args.out / "material_study.json", args.rmin_mm, args.packings)
    seeds = [int(k) for k in args.seeds.split(",")] if args.seeds else list(range(1, args.packings + 1))
    if not set(seeds) <= set(range(1, args.packings + 1)):
        raise SystemExit(f"--seeds: packings are 1-{args.packings}")
    for name in args.variants.split(","):
        measure(study, table, name, *known[name], seeds, args.out / "material_study.md")
    rows = table.rows()
    figure(rows, args.out / "material_study.png")
    print(markdown(rows))


if __name__ == "__main__":
    main()
