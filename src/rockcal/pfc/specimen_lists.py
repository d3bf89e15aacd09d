"""A specimen as PFC's ball and bond lists (`write_specimen`): balls.csv and bonds.csv, ids
from 1 as in PFC, every number to the last bit; PFC2D's disks (`write_specimen_2d`) with each
bonded pair's properties, PFC3D's spheres (`write_specimen_3d`) with each parallel bond's."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rockcal.materials import material_of
from rockcal.output_files import write_csv
from rockcal.pfc.parameters import check_3d_material

BALL_COLUMNS = ("id", "x_m", "y_m", "z_m", "radius_m")  # PFC3D's
BOND_COLUMNS = ("id", "ball1", "ball2", "tensile_strength_Pa", "cohesion_Pa", "bond_radius_m",
                "gap_m", "rgap_m")  # PFC3D's


def write_specimen(specimen, params, folder: Path) -> tuple[Path, Path]:
    """The specimen's balls.csv and bonds.csv in `folder`, in its dimension's columns; their paths."""
    if specimen.dimensions == 3:
        return write_specimen_3d(specimen, params, folder)
    return write_specimen_2d(specimen, params, folder)


def write_specimen_2d(specimen, params, folder: Path) -> tuple[Path, Path]:
    """The specimen as balls.csv (id, x, y, radius; m) and bonds.csv (ball ids and the
    properties of each bonded pair at `params` (`Material.pair_properties`): a parallel bond's
    tensile strength and cohesion, Pa; a flat joint's type, initial gap, λ and strengths), ids
    from 1 as in PFC."""
    bonds = np.asarray(specimen.bonds)
    columns = material_of(params).pair_properties(params, specimen)
    folder.mkdir(parents=True, exist_ok=True)
    balls_path, bonds_path = folder / "balls.csv", folder / "bonds.csv"
    write_csv(balls_path, ["id", "x_m", "y_m", "radius_m"],
              ([i, repr(float(x)), repr(float(y)), repr(float(r))]
               for i, ((x, y), r) in enumerate(zip(specimen.pos, specimen.radius), start=1)))
    write_csv(bonds_path, ["ball1", "ball2", *columns],
              ([int(i) + 1, int(j) + 1, *(repr(v.item()) for v in values)]
               for (i, j), *values in zip(bonds, *columns.values())))
    return balls_path, bonds_path


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
