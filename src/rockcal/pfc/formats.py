"""The export's formats by name (`rockcal export --format`): each a writer of a calibration's
text, the files a format writes beside it (`companion_files`), and all of them written
(`write_export`)."""

from __future__ import annotations

from pathlib import Path

from rockcal.errors import InputError
from rockcal.output_files import write_atomic
from rockcal.pfc.calibrated import in_3d
from rockcal.pfc.header import origin_lines
from rockcal.pfc.json_file import to_json
from rockcal.pfc.parameter_file import to_fish
from rockcal.pfc.python_script import to_python
from rockcal.pfc.vessel_file import VESSEL_FILE, to_vessel_fish

WRITERS = {"pfc-fish": to_fish, "pfc-python": to_python, "json": to_json}
FORMATS = tuple(WRITERS)


def companion_files(format: str, calibrated) -> dict[str, str]:
    """The files (name: text) written in the same folder as a calibration's `format` file: a
    3D calibration's FISHTank vessel (mvParams.p3dat) beside its mpParams.p3dat; none else."""
    if format == "pfc-fish" and in_3d(calibrated):
        return {VESSEL_FILE: to_vessel_fish(calibrated.specimen, origin_lines(calibrated)[:1])}
    return {}


def write_export(path, format: str, calibrated, field: str = "--to") -> list[Path]:
    """Write the calibration's `format` file to `path` and its companions beside it, each
    whole or not at all (a link is replaced, not followed); their paths. InputError naming
    `field` for a path a companion would overwrite or a folder that cannot be written."""
    path = Path(path)
    files = {path: WRITERS[format](calibrated)}
    for name, text in companion_files(format, calibrated).items():
        if path.name == name:
            raise InputError(field, f"{name} is the vessel's file, written beside the parameter file: "
                                    "name that one otherwise (mpParams.p3dat)")
        files[path.with_name(name)] = text
    for file, text in files.items():
        try:
            write_atomic(file, text)
        except OSError as exc:
            raise InputError(field, f"cannot write {file}: {exc.strerror}") from None
    return list(files)
