"""The rock lab at the granite's identified point: the strength envelope (Mohr-Coulomb c and phi,
Hoek-Brown m_i), CI / UCS and CD / UCS, Brazilian and direct tensile strength of the
parallel-bonded granite, beside the lab's values for granite.

Run by hand: `python benchmarks/rock_lab_table.py [--out runs/rock-lab] [--rmin-mm 0.25]
[--confinement-mpa 0,5,10,20] [--workers 1] [--from CAMPAIGN_OUT] [--grain-shape two-pebble]
[--seed 2]`. The parameters are the
embedded granite campaign's (`rockcal.campaign.granite.toml`: its specimen, genesis and fixed
parameters) at the point its calibration identifies (E_c 21.65 GPa, kn/ks 1.985, sigma_c
35.61 MPa), or with `--from` those a finished campaign identified, of its material, on its
specimen (e.g. `docs/campaigns/granite-flatjoint.toml`'s; the lab column stays granite's). Every run goes
through the run store in OUT (a stopped table resumes, a run done is never run again). Writes
OUT/rock_lab_table.md (the table), OUT/rock_lab.json, and the figures: the envelope
(biaxial_strength_envelope.png), the confined curves (biaxial_confined_compression_curves.png)
and CI / CD on the UCS curve (ucs_crack_stresses.png).
"""

import argparse
import json
import time
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import SpecimenSettings, load_campaign
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore
from rockcal.plots import plot_crack_stresses
from rockcal.labtests.envelope import fit_mohr_coulomb
from rockcal.labtests.registry import lab_test
from rockcal.materials import DEFAULT_MATERIAL, material

IDENTIFIED = {"E_c": 21.65, "kn_ks": 1.985, "sigma_c": 35.61}  # docs/validation/granite-calibration.md
GRANITE_M_I = 32.0  # Hoek (2007), Practical Rock Engineering, table of m_i: granite 32 +/- 3
SOURCE_UCS_MPA = 138.8  # the source's granite (the embedded campaign's [targets.ucs])


def hoek_brown_envelope(confinements: list[float]) -> dict:
    """Mohr-Coulomb c and phi fitted, as the model's are, to the intact Hoek-Brown envelope of
    granite (m_i 32, sigma_ci the source's UCS) at the same confinements."""
    s3 = np.asarray(confinements, float)
    s1 = s3 + SOURCE_UCS_MPA * np.sqrt(GRANITE_M_I * s3 / SOURCE_UCS_MPA + 1)
    mc = fit_mohr_coulomb(s3, s1)
    return {"c_MPa": mc.c_MPa, "phi_deg": mc.phi_deg}


def lab_values(confinements: list[float]) -> dict:
    """The lab's values for granite by row, with their sources (docs/validation/rock-lab.md)."""
    hb = hoek_brown_envelope(confinements)
    implied = f"(Hoek–Brown, m_i {GRANITE_M_I:g}, σ_ci {SOURCE_UCS_MPA:g} MPa, fitted at the same σ3)"
    return {
        "UCS (MPa)": f"{SOURCE_UCS_MPA:g} (the source's granite, 3 samples)",
        "E (GPa)": "41.5 (the source's granite)",
        "ν": "0.23 (the source's granite)",
        "c (MPa)": f"{hb['c_MPa']:.1f} {implied}",
        "φ (degrees)": f"{hb['phi_deg']:.1f} {implied}",
        "m_i": f"{GRANITE_M_I:g} ± 3 (granite; Hoek 2007)",
        "CI / UCS, onset of cracking": "0.42–0.47 (unconfined, 376 tests; Nicksiar & Martin 2013)",
        "CI / UCS, crack volumetric strain": "0.42–0.47 (as above)",
        "CI / peak q, confined, crack volumetric strain": "0.50–0.54 (confined; Nicksiar & Martin 2013)",
        "CD / UCS": "about 0.7–0.8 (Lac du Bonnet granite; Martin & Chandler 1994)",
        "Brazilian σ_t (MPa)": "— (the source gives none)",
        "direct σ_t (MPa)": "about 0.77 × Brazilian (Nicksiar & Martin 2013; Lac du Bonnet granite: 6.9 / 8.8 MPa, "
                            "Rock Mech Rock Eng 2019)",
        "UCS / Brazilian σ_t": "about 23 (Lac du Bonnet granite: UCS 200 MPa as Potyondy & Cundall 2004 quote it, "
                               "Brazilian 8.8 MPa, Rock Mech Rock Eng 2019)",
    }


def calibrated_point(folder: Path | None) -> tuple[SpecimenSettings, dict, str, str]:
    """(specimen settings, parameters, material, the model in words) of the point the table
    is read at: that of the finished campaign in `folder`, else the embedded granite's."""
    if folder is None:
        granite, _ = load_campaign(None)
        return granite.specimen, granite.fixed_params() | IDENTIFIED, DEFAULT_MATERIAL, "parallel-bonded granite"
    record = json.loads((folder / "record.json").read_text())
    model = record["material"] or DEFAULT_MATERIAL
    words = material(model).title.split(" (")[0]
    return SpecimenSettings(**record["specimen"]), record["identified_params"], model, f"{words} {record['rock']}"


def run_all(out: Path, point, settings: dict, confinements: list[float], workers: int):
    """The tests at the calibrated point, through the store in `out`, on its specimen with
    `settings` changed: the specimen settings, the runs by name and the wall time of the runs
    done now."""
    specimen, params, model, _ = point
    specimen = specimen.model_copy(update=settings)
    specs = {"ucs": run_spec("ucs", specimen, params, model),
             "brazilian": run_spec("brazilian", specimen, params, model),
             "direct_tension": run_spec("direct_tension", specimen, params, model)}
    specs |= {f"biaxial {s3:g}": run_spec("biaxial", specimen, params, model, own={"confinement_mpa": s3})
              for s3 in confinements}
    started = time.perf_counter()
    executor = Executor(RunStore(out), workers=workers)
    try:
        results = executor.run(list(specs.values()))
    finally:
        executor.close()
    failed = [(name, r.message) for name, r in zip(specs, results) if r.status != "ok"]
    if failed:
        raise SystemExit(f"runs failed: {failed}")
    return specimen, dict(zip(specs, results)), time.perf_counter() - started


def table(runs: dict, confinements: list[float]) -> tuple[dict, dict]:
    """The model's values by row of the table, and the envelope's whole fit."""
    biaxial = lab_test("biaxial")
    peaks = [runs[f"biaxial {s3:g}"].responses for s3 in confinements]
    envelope = biaxial.combine(peaks)
    ucs = runs["ucs"].responses
    sigma_t = runs["brazilian"].responses["sigma_t_MPa"]
    confined = [p["ci_strain_ratio"] for p in peaks if p["confinement_MPa"] > 0]
    model = {
        "UCS (MPa)": ucs["ucs_MPa"], "E (GPa)": ucs["E_GPa"], "ν": ucs["nu"], "c (MPa)": envelope["c_MPa"],
        "φ (degrees)": envelope["phi_deg"], "m_i": envelope["m_i"],
        "CI / UCS, onset of cracking": ucs["ci_ratio"], "CI / UCS, crack volumetric strain": ucs["ci_strain_ratio"],
        "CI / peak q, confined, crack volumetric strain": (min(confined), max(confined)) if confined else None,
        "CD / UCS": ucs["cd_ratio"], "Brazilian σ_t (MPa)": sigma_t,
        "direct σ_t (MPa)": runs["direct_tension"].responses["sigma_t_direct_MPa"],
        "UCS / Brazilian σ_t": ucs["ucs_MPa"] / sigma_t,
    }
    return model, envelope


def _cell(value) -> str:
    """A value to 3 significant digits, a range as low–high, none as a dash."""
    if value is None:
        return "—"
    return "–".join(f"{v:.2f}" for v in value) if isinstance(value, tuple) else f"{value:.3g}"


def markdown(model: dict, envelope: dict, confinements: list[float], specimen, words: str) -> str:
    lab = lab_values(confinements)
    rows = [f"| | {words} (rockcal) | lab |", "|---|---|---|"]
    rows += [f"| {name} | {_cell(value)} | {lab[name]} |" for name, value in model.items()]
    peaks = ", ".join(f"{s3:g}: {s1:.1f}" for s3, s1 in zip(confinements, envelope["sigma1_MPa"]))
    return "\n".join(rows) + (
        f"\n\nPeaks σ1 (MPa) at σ3 (MPa) {peaks}. Mohr–Coulomb σ_c {envelope['mc_sigma_c_MPa']:.1f} MPa, "
        f"R² {envelope['mc_r2']:.4f}, rms {envelope['mc_rms_MPa']:.2f} MPa; Hoek–Brown σ_ci "
        f"{envelope['sigma_ci_MPa']:.1f} MPa, r² {envelope['hb_r2']:.4f}, rms {envelope['hb_rms_MPa']:.2f} MPa. "
        f"Specimen {specimen.width_mm:g} × {specimen.height_mm:g} mm (disk D {specimen.disk_diameter_mm:g} mm), "
        f"R_min {specimen.rmin_mm:g} mm, packing seed {specimen.seed}, grains: {specimen.grain_shape}.\n")


def figures(out: Path, runs: dict, confinements: list[float], words: str) -> None:
    biaxial = lab_test("biaxial")
    done = [(runs[f"biaxial {s3:g}"].responses, runs[f"biaxial {s3:g}"].curve) for s3 in confinements]
    name = words[:1].upper() + words[1:]
    for figure in biaxial.series_figures:
        figure.draw(done, out / figure.file("biaxial"), f"{name} at the identified point: {figure.title.lower()}")
    plot_crack_stresses(runs["ucs"].curve, out / "ucs_crack_stresses.png",
                        f"UCS test of the {words} at the identified point")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", type=Path, default=Path("runs/rock-lab"))
    parser.add_argument("--rmin-mm", type=float, default=None, help="default: the granite campaign's, 0.25 mm")
    parser.add_argument("--confinement-mpa", default="0,5,10,20")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--grain-shape", default=None, help="the grains: ball or a clump template (default: the point's)")
    parser.add_argument("--seed", type=int, default=None, help="packing seed (default: the point's)")
    parser.add_argument("--from", dest="campaign", type=Path, default=None,
                        help="a finished campaign's OUT: its identified point (default: the embedded granite's)")
    args = parser.parse_args()
    confinements = [float(v) for v in args.confinement_mpa.split(",")]
    args.out.mkdir(parents=True, exist_ok=True)
    point = calibrated_point(args.campaign)
    settings = {k: v for k, v in (("rmin_mm", args.rmin_mm), ("grain_shape", args.grain_shape), ("seed", args.seed))
                if v is not None}
    specimen, runs, wall_s = run_all(args.out, point, settings, confinements, args.workers)
    model, envelope = table(runs, confinements)
    text = markdown(model, envelope, confinements, specimen, point[3])
    (args.out / "rock_lab_table.md").write_text(text)
    (args.out / "rock_lab.json").write_text(json.dumps(
        {"model": model, "envelope": envelope, "runs": {name: r.responses for name, r in runs.items()},
         "run_wall_s": {name: r.wall_s for name, r in runs.items()}, "wall_s_now": wall_s}, indent=2))
    figures(args.out, runs, confinements, point[3])
    print(text)


if __name__ == "__main__":
    main()
