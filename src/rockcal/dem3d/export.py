"""Carry a 3D calibration into PFC3D: FISHTank's parameter file of the linear parallel-bonded
material (`mpParams.p3dat`) and the specimen as ball and bond lists.

The parameter file is the 2D export's (`rockcal.campaign.outputs.export`): the same FISHTank
names, groups and layout (`fish_groups`), the same `cm_matType` per FISHTank version
(`--fishtank 5|6|7`, `rockcal.materials.fishtank`), the same number format. FISHTank's
parallel-bonded material reads the same `cm_*`, `pk_*`, `pbm_*` and `lnm_*` names in PFC3D as
in PFC2D (its own `mpParams.p3dat` examples), but in PFC3D they mean (`PFC3D_NOTES`, in the
file's header too):

- `pbm_emod`, `lnm_emod`: E* of PFC3D's deformability method, kn = E* pi min(R)^2 / (R_A + R_B)
  (PFC2D: 2 min(R) t E* / (R_A + R_B)); `pbm_bemod`: kbar_n = Ebar* / (R_A + R_B) on a bond
  cross-section that is a disk of radius Rbar = pbm_rmul min(R) (area pi Rbar^2, I = pi Rbar^4
  / 4, J = pi Rbar^4 / 2), not a rectangle 2 Rbar t;
- `pbm_mcf`: the bending moment enters the bond's normal stress and the twisting moment (none
  in 2D) its shear stress;
- `pk_nc`: the cloud porosity of a 3D grain cloud (FISHTank's 3D default 0.35 with grain
  scaling, 2D's 0.08); `cm_Dlo`, `cm_Dup` are sphere diameters and `cm_densityVal` the
  spheres' density (masses rho 4/3 pi R^3, no unit thickness);
- no `pfc4` contacts: the 3D engine has PFC 5's deformability method only.

A rock's PFC3D values differ from its PFC2D ones (Potyondy & Cundall 2004 calibrated Lac du
Bonnet granite in both). The vessel (FISHTank's `mvParams.p3dat`: `mv_shape`, `mv_H`, `mv_W`,
`mv_D`) is not in the file: rockcal packs a cuboid and carves its cylinders and disks from it.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np

from rockcal.campaign.outputs.export import Calibrated, fish_groups, pfc_parameters
from rockcal.campaign.outputs.safe_text import comment_text
from rockcal.errors import InputError
from rockcal.materials import material_of
from rockcal.materials.fishtank import (
    DEFAULT_FISHTANK,
    FISHTANKS,
    MATERIAL_TYPES,
    fishtank_version,
)
from rockcal.materials.parallel_bond import MicroParams
from rockcal.output_files import atomic_path, write_csv

PARAMETER_FILE = "mpParams.p3dat"  # FISHTank's name for it: a project runs `call mpParams.p3dat`
PFC3D_NOTES = (
    "PFC3D: spheres; SI units; FISHTank's names, as in PFC2D, with PFC3D's meanings:",
    "pbm_emod, lnm_emod: kn = E* pi min(R)^2 / (R_A + R_B) (PFC3D's deformability method)",
    ("pbm_bemod: kbar_n = Ebar* / (R_A + R_B) on a bond disk of radius Rbar = pbm_rmul min(R): "
     "area pi Rbar^2, I = pi Rbar^4 / 4, J = pi Rbar^4 / 2"),
    "pbm_mcf: the bending moment in the bond's normal stress, the twisting moment in its shear stress",
    "pk_nc: the 3D grain cloud's porosity (FISHTank's 3D default 0.35); cm_Dlo, cm_Dup: sphere diameters",
    "the vessel (mvParams.p3dat) is not set here: rockcal packs a cuboid and carves the specimen from it",
)


def check_3d_material(params, settings) -> None:
    """The 3D engine's material: the parallel bond, on spheres (no clumps); InputError naming
    the field."""
    if not isinstance(params, MicroParams):
        raise InputError("model", f"the 3D engine has the parallel-bonded material only, got "
                                  f"{material_of(params).name}")
    shape = getattr(settings, "grain_shape", "ball")
    if shape != "ball":
        raise InputError("grain_shape", f"the 3D engine has spheres only, got {shape!r}")


def pfc3d_parameters(params, settings, fishtank: int = DEFAULT_FISHTANK) -> dict:
    """FISHTank's parameters (SI) of the parallel-bonded material `params` on the genesis
    `settings` (anything with rmin_mm, radius_ratio, install_gap, cloud_porosity, pressure_mpa:
    a campaign's SpecimenSettings), for the FISHTank of PFC `fishtank`: the 2D export's names
    and values (`export.pfc_parameters`), which PFC3D's FISHTank reads alike."""
    check_3d_material(params, settings)
    return pfc_parameters(Calibrated(params, settings, {}, fishtank_version(fishtank)))


def to_fish_3d(params, settings, *, fishtank: int = DEFAULT_FISHTANK,
               header: Iterable[str] = ()) -> str:
    """FISHTank's parameter file for PFC3D (`mpParams.p3dat`): `header`'s lines (e.g. where
    the calibration came from), the target FISHTank and PFC3D's meanings (`PFC3D_NOTES`) as
    comments, then the 2D export's groups (`fish_groups`) and FISHTank's own check."""
    version = fishtank_version(fishtank)
    values = pfc3d_parameters(params, settings, version)
    target = (f"for {FISHTANKS[version]} in PFC3D: cm_matType "
              f"{MATERIAL_TYPES[version]['parallel-bonded']} parallel-bonded "
              "(rockcal export --fishtank 5, 6 or 7)")
    lines = [*header, target, *PFC3D_NOTES]
    out = [f"; {comment_text(line)}" for line in lines]
    return "\n".join(out + fish_groups(values, material_of(params).pfc_group))


def write_p3dat(folder: Path, params, settings, *, fishtank: int = DEFAULT_FISHTANK,
                header: Iterable[str] = ()) -> Path:
    """Write `to_fish_3d` to `folder`/mpParams.p3dat (atomically); its path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / PARAMETER_FILE
    text = to_fish_3d(params, settings, fishtank=fishtank, header=header)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="ascii")
    return path


BALL_COLUMNS = ("id", "x_m", "y_m", "z_m", "radius_m")
BOND_COLUMNS = ("id", "ball1", "ball2", "tensile_strength_Pa", "cohesion_Pa", "bond_radius_m",
                "gap_m", "rgap_m")


def write_specimen_3d(specimen, params, folder: Path) -> tuple[Path, Path]:
    """The 3D specimen (`specimens3d.specimen.Specimen3D`) as balls.csv (`BALL_COLUMNS`: id, centre,
    radius; m) and bonds.csv (`BOND_COLUMNS`): each parallel bond's id, its spheres' ids, its
    tensile strength and cohesion at `params` (Pa; the draws the engine makes,
    `Material.pair_properties`), its radius Rbar = lambda min(R) (m, PFC's pb_radius), the
    pair's surface gap when bonded (m, negative an overlap: the bond carries no force there)
    and the reference gap of the pair's linear contact (PFC's rgap: that gap where the pair
    overlapped, 0 across a gap). Ids from 1 as in PFC; every number to the last bit."""
    check_3d_material(params, None)
    pos, radius = np.asarray(specimen.pos), np.asarray(specimen.radius)
    bonds = np.asarray(specimen.bonds).reshape(-1, 2)
    strengths = material_of(params).pair_properties(params, specimen)
    ri, rj = radius[bonds[:, 0]], radius[bonds[:, 1]]
    gap = np.linalg.norm(pos[bonds[:, 1]] - pos[bonds[:, 0]], axis=1) - ri - rj
    columns = [*strengths.values(), params.lambda_ * np.minimum(ri, rj), gap, np.minimum(gap, 0.0)]
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    balls_path, bonds_path = folder / "balls.csv", folder / "bonds.csv"
    write_csv(balls_path, list(BALL_COLUMNS),
              ([i, *(repr(float(v)) for v in p), repr(float(r))]
               for i, (p, r) in enumerate(zip(pos, radius), start=1)))
    write_csv(bonds_path, list(BOND_COLUMNS),
              ([n, int(i) + 1, int(j) + 1, *(repr(float(v)) for v in values)]
               for n, ((i, j), *values) in enumerate(zip(bonds, *columns), start=1)))
    return balls_path, bonds_path
