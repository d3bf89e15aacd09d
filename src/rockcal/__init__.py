"""rockcal: identify bonded-particle DEM micro-parameters of rock from lab tests."""

from rockcal.wide_vectors import prefer_512_bit_vectors

prefer_512_bit_vectors()  # before numba loads

from rockcal.api import Calibration, calibrate, simulate
from rockcal.dem.specimen import Specimen, hexagonal, random_packing
from rockcal.labtests.ucs import UCSResult, simulate_ucs
from rockcal.params import MicroParams, make_params

__version__ = "0.2.1"  # part of every stored run's key: runs of another version are run again (CHANGELOG.md)
__all__ = ["Calibration", "MicroParams", "Specimen", "UCSResult", "calibrate", "hexagonal", "make_params", "random_packing",
           "simulate", "simulate_ucs"]
