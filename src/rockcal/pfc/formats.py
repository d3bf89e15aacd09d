"""The export's formats by name (`rockcal export --format`): each a writer of a calibration's text."""

from __future__ import annotations

from rockcal.pfc.json_file import to_json
from rockcal.pfc.parameter_file import to_fish
from rockcal.pfc.python_script import to_python

WRITERS = {"pfc-fish": to_fish, "pfc-python": to_python, "json": to_json}
FORMATS = tuple(WRITERS)
