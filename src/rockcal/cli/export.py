"""`rockcal export` and `rockcal export-specimen`: a finished calibration, ready for PFC."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.markup import escape

from rockcal.errors import InputError


class Format(str, Enum):
    pfc_fish = "pfc-fish"
    pfc_python = "pfc-python"
    json = "json"


class FishTank(str, Enum):
    """The FISHTank targeted, by PFC version (`materials.fishtank.FISHTANKS`)."""

    pfc5 = "5"
    pfc6 = "6"
    pfc7 = "7"


def export(
    out: Path = typer.Argument(..., help="Output folder of a finished campaign."),
    format: Format = typer.Option(Format.pfc_fish, "--format", help="pfc-fish: FISHTank's mpParams data file "
                                  "(mpParams.p2dat in 2D, mpParams.p3dat in 3D); pfc-python: a PFC2D Python "
                                  "script (2D only); json."),
    to: Optional[Path] = typer.Option(None, "--to", help="File to write (default: stdout); a 3D "
                                    "calibration's pfc-fish writes FISHTank's vessel, mvParams.p3dat, beside it."),
    fishtank: FishTank = typer.Option(FishTank.pfc6, "--fishtank", help="The PFC version whose FISHTank reads the "
                                      "file: its cm_matType codes (flat-jointed: 3 in PFC 5's fistPkg25, 4 in "
                                      "PFC 6's; 7: numbered as 6)."),
) -> None:
    """The identified micro-parameters under PFC FISHTank's names (pbm_emod, ...), in SI units;
    a clumped material's clump template too."""
    from rockcal.campaign.outputs.export import calibration_in
    from rockcal.materials import material_of
    from rockcal.pfc.calibrated import for_fishtank
    from rockcal.pfc.formats import WRITERS, companion_files, write_export
    from rockcal.pfc.header import PFC4_NOT_IN_FISHTANK, takes_pfc4_contacts

    calibrated = for_fishtank(calibration_in(out), fishtank.value)
    notes = []
    if to is None:
        typer.echo(WRITERS[format.value](calibrated), nl=False)
        notes += [f"not written: {name}, which --to FOLDER/FILE writes beside FILE"
                  for name in companion_files(format.value, calibrated)]
    else:
        notes.append("wrote " + " and ".join(map(str, write_export(to, format.value, calibrated))))
    if takes_pfc4_contacts(calibrated.specimen, material_of(calibrated.params).name):
        notes.append(f"calibrated with PFC 3.x/4.0's contacts (contact_stiffness = \"pfc4\"): {PFC4_NOT_IN_FISHTANK}")
    for note in notes:
        Console(stderr=True).print(escape(note), soft_wrap=True)


def export_specimen(
    out: Path = typer.Argument(..., help="Output folder of a finished campaign."),
    to: Path = typer.Option(Path("specimen"), "--to", help="Folder for balls.csv and bonds.csv."),
) -> None:
    """The campaign's UCS specimen as ball and bond lists (SI), with each bond's strengths at
    the identified parameters."""
    from rockcal.campaign.outputs.export import calibration_in
    from rockcal.campaign.runs.pool import specimen_of
    from rockcal.pfc.specimen_lists import write_specimen
    from rockcal.campaign.runs.spec import run_spec
    from rockcal.labtests.registry import PRIMARY_TEST
    from rockcal.materials import material_of

    calibrated = calibration_in(out)
    if to.exists() and not to.is_dir():
        raise InputError("--to", f"{to} is a file, not a folder")
    from rockcal.campaign.files import one_line_errors

    spec = run_spec(PRIMARY_TEST, calibrated.specimen, calibrated.params.key(),
                    material_of(calibrated.params).name)
    specimen = specimen_of(PRIMARY_TEST, spec.specimen)
    with one_line_errors(to, "--to"):
        paths = write_specimen(specimen, calibrated.params, to)
    Console(stderr=True).print(f"wrote {escape(str(paths[0]))} ({specimen.n_particles} balls) and {escape(str(paths[1]))} "
                               f"({len(specimen.bonds)} bonds)")

