"""FISHTank's parameter file of a calibrated material, one layout for PFC2D (`to_fish`) and
PFC3D (`to_fish_3d`, written as `mpParams.p3dat` by `write_p3dat`): the header's comments
(`header`), a clumped material's clump template created first (`clump template create`, as
FISHTank's `clump distribute` takes it), then FISHTank's parameter groups (`fish_groups`): the
common and packing group functions, the material's group (`mpSetPBParams` for the
parallel-bonded material, `mpSetFJParams` for the flat-jointed one, each with the linear
material group `lnm_*`), in SI units, and FISHTank's own check `_mpCheckAllParams`. `cm_matType`
differs between the FISHTanks of PFC 5, 6 and 7 (`--fishtank`, `rockcal.materials.fishtank`).

FISHTank's flat-jointed material reads `fjm_Nal` (the elements of each ring of a joint's disk) in
PFC3D alone, and `fjm_Nr` there counts the disk's rings (`header.FLAT_JOINT_3D_NOTES`).
FISHTank's parallel-bonded material reads the same `cm_*`, `pk_*`, `pbm_*` and `lnm_*` names in
PFC3D as in PFC2D (its own `mpParams.p3dat` examples), but in PFC3D they mean
(`header.PFC3D_NOTES`, in the file's header too):

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
Bonnet granite in both). The vessel is FISHTank's other file, `mvParams.p3dat` (`vessel_file`),
which `write_p3dat` writes beside it.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from rockcal.materials import material_of
from rockcal.materials.fishtank import (DEFAULT_FISHTANK, fishtank_version, grain_template, template_name,
                                        template_pebbles)
from rockcal.output_files import atomic_path
from rockcal.pfc.calibrated import Calibrated, fishtank_of, in_3d
from rockcal.pfc.fish_value import fish_value
from rockcal.pfc.header import comment_text, header_of, notes_3d, origin_lines, seed_line
from rockcal.pfc.parameters import SIZE_ARRAYS, UNITS, clump_templates, pfc3d_parameters, pfc_parameters
from rockcal.pfc.vessel_file import VESSEL_FILE, to_vessel_fish

PARAMETER_FILE = "mpParams.p3dat"  # FISHTank's name for PFC3D's: a project runs `call mpParams.p3dat`


def to_fish(calibrated: Calibrated) -> str:
    """A FISH data file in the layout of FISHTank's mpParams: the header, a clumped material's
    template, the common, packing and material group functions, then FISHTank's own check
    (`_mpCheckAllParams`); for a 3D calibration PFC3D's (`to_fish_3d`)."""
    if in_3d(calibrated):
        return to_fish_3d(calibrated.params, calibrated.specimen, fishtank=fishtank_of(calibrated),
                          header=origin_lines(calibrated))
    comments, templates = header_of(calibrated), clump_templates(calibrated)
    return fish_file(comments, pfc_parameters(calibrated), material_of(calibrated.params).pfc_group, templates)


def to_fish_3d(params, settings, *, fishtank: int = DEFAULT_FISHTANK,
               header: Iterable[str] = ()) -> str:
    """FISHTank's parameter file for PFC3D (`mpParams.p3dat`): `header`'s lines (e.g. where
    the calibration came from), the target FISHTank, PFC3D's meanings (`header.notes_3d`) and
    the packing seed as comments, a clumped material's template (`template_command`), then the
    2D file's groups (`fish_groups`) and FISHTank's own check."""
    version = fishtank_version(fishtank)
    values = pfc3d_parameters(params, settings, version)
    comments = [*header, *notes_3d(version, material_of(params).pfc_group, settings), seed_line(settings)]
    shape = grain_template(settings)
    templates = {} if shape is None else {template_name(shape): template_pebbles(shape)}
    return fish_file(comments, values, material_of(params).pfc_group, templates)


def write_p3dat(folder: Path, params, settings, *, fishtank: int = DEFAULT_FISHTANK,
                header: Iterable[str] = ()) -> tuple[Path, Path]:
    """Write `to_fish_3d` to `folder`/mpParams.p3dat and the vessel (`vessel_file`) to
    `folder`/mvParams.p3dat, each atomically; their paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    header = list(header)
    texts = {PARAMETER_FILE: to_fish_3d(params, settings, fishtank=fishtank, header=header),
             VESSEL_FILE: to_vessel_fish(settings, header)}
    for name, text in texts.items():
        with atomic_path(folder / name) as tmp:
            Path(tmp).write_text(text, encoding="ascii")
    return folder / PARAMETER_FILE, folder / VESSEL_FILE


def fish_file(comments: Iterable[str], values: dict, group: str, templates: dict | None = None) -> str:
    """The file: `comments` as comment lines (made safe, `comment_text`), each clump template's
    command and an empty line, then the groups of `values` with the material group `group`."""
    out = [f"; {comment_text(line)}" for line in comments]
    for name, pebbles in (templates or {}).items():
        out += [*template_command(name, pebbles), ""]
    return "\n".join(out + fish_groups(values, group))


def template_command(name: str, pebbles) -> list[str]:
    """PFC's command creating the clump template `name` of `pebbles` (radius, x, y; 3D: x, y, z), its
    inertial properties computed from the pebbles as FISHTank's clumped examples do
    (`pebcalculate`): one line per pebble, each number to the last bit."""
    lines = [f"clump template create pebcalculate name {name} pebbles {len(pebbles)} ..."]
    lines += [" ".join(["   ", *(repr(float(v)) for v in pebble)]) + " ..." for pebble in pebbles]
    lines[-1] = lines[-1].removesuffix(" ...")
    return lines


def fish_groups(values: dict, group: str) -> list[str]:
    """FISHTank's parameter groups of `values` (PFC names, SI), one line each: the common and
    packing group functions, the material group function `group`, FISHTank's own check
    (`_mpCheckAllParams`), and a last empty line."""
    arrays = [name for name in SIZE_ARRAYS if name in values]

    def assign(name: str, target: str | None = None) -> str:
        unit = f"  ; {UNITS[name]}" if name in UNITS else ""
        return f"  {target or name} = {fish_value(values[name])}{unit}"

    common = [name for name in values if name.startswith("cm_") and name not in arrays]
    out = ["def mpSetCommonParams", *(assign(name) for name in common), "  cm_matNameSAV = cm_matName"]
    out += [f"  {name} = array.create(cm_nSD)" for name in arrays]
    out += [assign(name, f"{name}(1)") for name in arrays]
    out += ["end", "@mpSetCommonParams", "", "def mpSetPackingParams",
            *(assign(name) for name in values if name.startswith("pk_")),
            "end", "@mpSetPackingParams", "", f"def {group}",
            *(assign(name) for name in values if not name.startswith(("cm_", "pk_"))),
            "end", f"@{group}", "", "@_mpCheckAllParams", ""]
    return out
