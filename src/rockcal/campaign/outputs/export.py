"""The campaign's side of the PFC export: a finished campaign's calibration (`read_calibration`,
or `calibration_in` its folder), read from its store as the record the PFC writers take
(`rockcal.pfc.calibrated.Calibrated`)."""

from __future__ import annotations

from pathlib import Path

from rockcal.campaign.files import one_line_errors
from rockcal.campaign.procedure.result import read_result
from rockcal.campaign.runs.lock import holder_of
from rockcal.campaign.runs.spec import ENGINE
from rockcal.campaign.runs.store import RunStore
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


def calibration_in(out: Path) -> Calibrated:
    """The finished campaign in the folder `out` (the command's OUT); one not finished that a
    rockcal is running (its lock is held) is an InputError saying so, not resumed."""
    with one_line_errors(out, "OUT"):
        store = RunStore(out, create=False, readonly=True)
        try:
            if read_result(store) is None and (holder := holder_of(out)) is not None:
                raise InputError("OUT", f"the campaign in {out} is running ({holder}); wait for it to "
                                        "end, then export again")
            return read_calibration(store, out)
        finally:
            store.close()
