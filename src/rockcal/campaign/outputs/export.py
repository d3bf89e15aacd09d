"""The campaign's side of the PFC export: a finished campaign's calibration (`read_calibration`),
read from its store as the record the PFC writers take (`rockcal.pfc.calibrated.Calibrated`)."""

from __future__ import annotations

from pathlib import Path

from rockcal.campaign.procedure.result import read_result
from rockcal.campaign.runs.spec import ENGINE
from rockcal.errors import InputError
from rockcal.materials import DEFAULT_MATERIAL, material
from rockcal.pfc.calibrated import Calibrated


def read_calibration(store, folder: Path) -> Calibrated:
    """The identified material of the campaign in `store`; InputError if it has not finished."""
    result = read_result(store)
    if result is None:
        raise InputError("OUT", f"the campaign in {folder} has not finished; run "
                                f"`rockcal calibrate --resume --out {folder}`")
    final_run = store.run(result.final_ucs_run_key)
    u = result.uncertainty
    origin = {"rock": result.rock, "campaign": str(folder), "accepted": result.accepted,
              "dem_runs": result.dem_runs, "targets": result.targets, "verified": result.verified,
              "identified": result.identified,
              "intervals": {} if u is None else {n: i.to_dict() for n, i in u.intervals.items()},
              "engine": final_run.engine if final_run else ENGINE}
    if result.quick_look:
        origin["quick_look"] = result.quick_look
    model = material(result.material or DEFAULT_MATERIAL)
    return Calibrated(model.make(result.identified_params), result.specimen, origin)
