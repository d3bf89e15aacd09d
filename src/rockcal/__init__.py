"""rockcal: identify bonded-particle DEM micro-parameters of rock from lab tests.

The names below load on first use (PEP 562), so `import rockcal.dem.laws` loads no lab test
and no campaign; no module of rockcal imports this face, so it closes no import cycle.
"""

from importlib import import_module

from rockcal.version import __version__
from rockcal.wide_vectors import prefer_512_bit_vectors

prefer_512_bit_vectors()  # before numba loads

_HOMES = {  # a name of the face: the module it lives in
    "Calibration": "rockcal.api", "calibrate": "rockcal.api", "simulate": "rockcal.api",
    "Specimen": "rockcal.specimens.specimen", "hexagonal": "rockcal.specimens.specimen",
    "random_packing": "rockcal.specimens.specimen",
    "UCSResult": "rockcal.labtests.ucs", "simulate_ucs": "rockcal.labtests.ucs",
    "MicroParams": "rockcal.params", "make_params": "rockcal.params",
}
__all__ = sorted(_HOMES)


def __getattr__(name: str):
    if name not in _HOMES:
        raise AttributeError(f"module 'rockcal' has no attribute {name!r}")
    value = getattr(import_module(_HOMES[name]), name)
    globals()[name] = value  # found once
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_HOMES))
