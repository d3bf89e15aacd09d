"""What a forward run is and what it gave: a lab test, its specimen settings and a material's
complete micro-parameters (`RunSpec`), keyed by all of them and the engine's version, which is
how the store finds a run done before; and its result (`RunResult`)."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass

import numpy as np

from rockcal.version import __version__
from rockcal.specimens.clump_genesis import CLUMP_GENESIS_VERSION
from rockcal.materials.clump_templates import DEFAULT_SHAPE
from rockcal.specimens.specimen import GENERATOR_VERSION
from rockcal.dem3d import ENGINE_VERSION_3D
from rockcal.specimens3d.specimen import GENERATOR_VERSION_3D
from rockcal.labtests.registry import lab_test
from rockcal.materials import DEFAULT_MATERIAL, material

SPECIMEN_KEYS = ("n_particles", "porosity", "coordination", "bonds_per_particle", "floaters")  # of each run
ENGINE = f"rockcal {__version__}, specimen generator {GENERATOR_VERSION}"


@dataclass(frozen=True)
class RunSpec:
    """What a forward run is: the test, its specimen settings and the full micro-parameters."""

    kind: str  # a lab test's name (`rockcal.labtests.registry`)
    specimen: tuple  # sorted (name, value) pairs
    params: tuple  # sorted (name, value) pairs, every micro-parameter
    engine: str

    @property
    def key(self) -> str:
        text = json.dumps([self.kind, self.specimen, self.params, self.engine])
        return hashlib.sha256(text.encode()).hexdigest()[:32]


@dataclass
class RunResult:
    """What a forward run gave: responses (or the error message), its curve and its cracks."""

    status: str  # "ok", "failed" or "timed out"
    responses: dict
    curve: np.ndarray | None
    wall_s: float
    message: str = ""
    # rows (x m, y m, mode 1 tension / 2 shear) of broken bonds; a 3D run's (x, y, z m, mode), one
    # stored before 3D runs kept their y (x, z m, mode)
    cracks: np.ndarray | None = None



def run_spec(kind: str, specimen_settings, params: dict, model: str = DEFAULT_MATERIAL,
             own: dict | None = None) -> RunSpec:
    """The spec of a run of the lab test `kind`: its specimen settings (with `own`, settings
    of the test's own such as a confinement, over them), and `params` of the material `model`
    completed with the defaults so the key is total (the material is named among them unless
    it is the default, so the runs stored before materials keep their keys). A 3D run's
    settings hold `dimensions` 3 and its engine the 3D engine's and generator's versions, a
    clumped run's engine the clumps' genesis version; a 2D run of balls keeps the key it had
    before 3D and clumps (`kind.LATER_SETTINGS`)."""
    test = lab_test(kind)
    settings = test.key_settings(specimen_settings) | (own or {})
    full = material(model).make(params).key() | ({} if model == DEFAULT_MATERIAL else {"model": model})
    revision = test.of_dimensions(settings.get("dimensions", 2)).revision
    engine = ENGINE if revision == 1 else f"{ENGINE}, {kind} test revision {revision}"
    if settings.get("dimensions") == 3:  # a 3D run (keyed by `dimensions` too): the 3D engine's
        engine += f", 3D engine {ENGINE_VERSION_3D}, 3D specimen generator {GENERATOR_VERSION_3D}"
    if settings.get("grain_shape", DEFAULT_SHAPE) != DEFAULT_SHAPE:  # a clumped run: of the clumps' genesis
        engine += f", clump genesis {CLUMP_GENESIS_VERSION}"
    return RunSpec(kind, tuple(settings.items()), tuple(sorted(full.items())), engine)


def params_of(spec: RunSpec):
    """The micro-parameters of a run, of its material."""
    values = dict(spec.params)
    return material(values.pop("model", DEFAULT_MATERIAL)).make(values)
