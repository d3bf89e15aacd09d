"""The time model of a campaign's runs, shared by the route and the first screen: a run's work
(grains x rows of its specimen) and its time relative to a UCS run's.

Work per step grows with the grains, and the steps of a test with its rows of grains (the
loading speed is set per row), so a run's time goes about as (grains x rows)^WORK_EXPONENT; a
test's own `time_factor` (a bending run's span, a Brazilian disk's bearing strips) scales it.
A 3D beam's or disk's steps are its pin's or platens' travel to the peak instead, at a step set
by the grain size: about as many at any resolution (`TRAVEL_ROWS_3D`).
"""

from __future__ import annotations

import numpy as np

from rockcal.materials.clump_templates import DEFAULT_SHAPE
from rockcal.specimens3d.specimen import cloud_spheres, expected_spheres
from rockcal.labtests.registry import PRIMARY_TEST, lab_test
from rockcal.labtests.specimen_settings import SpecimenSettings

# run time ~ work^WORK_EXPONENT[dimensions]: in 2D a half-resolution UCS run (1/8 of the work)
# takes about 1/10 of the full-size one at the same point on one thread (a small specimen stays
# in the caches); in 3D a coarse run's steps fall faster than its rows (R_min x 1.4-1.5: the
# granite's and the Lac du Bonnet cylinder's UCS runs 0.17 and 0.11 of the full-size ones, for
# exponents 1.34 and 1.40, the latter's confined runs 1.38: `NUMBA_NUM_THREADS=1 python
# benchmarks/plan_3d.py STORE` on the stores of docs/campaigns/granite-3d-all-targets.toml and
# ldb-3d.toml)
WORK_EXPONENT = {2: 1.1, 3: 1.35}
# The rows of a 3D UCS cylinder whose steps a 3D beam's or Brazilian disk's run takes (tests
# whose steps do not follow their rows: `LabTest.steps_follow_rows`): its pin's or platens'
# travel to the peak, at a step set by the grain size (the same benchmark: the granite's beam
# 33 and 52 rows at R_min 0.8 and 1.12 mm, the Lac du Bonnet disk 28 and 39 at 0.5 and 0.75 mm;
# their geometric mean)
TRAVEL_ROWS_3D = 37.0
# A packing's genesis on one thread: its time goes with the packing's grains x rows as a run's
# does (every step moves every grain; a taller vessel takes more steps to settle), in seconds per
# grain-row per ms of the engine probe's step (`engine_speed`): 2D balls, 3D spheres (the 3D one
# measured by `python benchmarks/genesis_3d.py --coefficient`)
GENESIS_S_PER_WORK = {2: 4.3e-4, 3: 9.5e-4}
GENESIS_CLUMPS = 1.3  # a clumped packing's genesis over a ball packing's of as many grains
# What is left to compile once the probe has compiled the 2D engine on an install's first run
# (numba's cache then holds it for every later run): the 2D tests' own loops, or the 3D engine and
# its genesis, s per ms of the probe's step
FIRST_RUN_COMPILE_S = {2: 20.0, 3: 190.0}


def grain_count(width_mm: float, height_mm: float, s: SpecimenSettings) -> int:
    """Grains of a genesis in a width x height vessel (in 3D, width x width x height): the
    cloud's count (floaters are enlarged, not added)."""
    if s.dimensions == 3:
        return int(round(expected_spheres(width_mm, height_mm, s.rmin_mm, s.radius_ratio, s.cloud_porosity)))
    rmin = s.rmin_mm
    mean_area = np.pi * rmin**2 * (1 + s.radius_ratio + s.radius_ratio**2) / 3
    return int(round((1 - s.cloud_porosity) * width_mm * height_mm / mean_area))


def work(width_mm: float, height_mm: float, s: SpecimenSettings, follow_rows: bool = True) -> float:
    """Grains x rows of a specimen: what a test's run time goes with (to the power
    WORK_EXPONENT); TRAVEL_ROWS_3D rows where its steps do not follow its rows."""
    rows = height_mm / (s.rmin_mm * (1 + s.radius_ratio)) if follow_rows else TRAVEL_ROWS_3D
    return grain_count(width_mm, height_mm, s) * rows


def specimen_size(test: str, s: SpecimenSettings) -> tuple[str, int, float]:
    """A test's specimen in words, its grains and its work (grains x rows)."""
    kind = lab_test(test)
    settings = kind.settings_of(s)
    o = kind.outline(settings)
    grains = round(o.share * grain_count(o.width_mm, o.height_mm, s))
    return o.text, grains, o.share * work(o.width_mm, o.height_mm, s, kind.steps_follow_rows(settings))


def time_factor(test: str, s: SpecimenSettings) -> float:
    """A run of `test` on specimen settings `s` over a UCS run's of the same work."""
    kind = lab_test(test)
    return kind.time_factor(kind.settings_of(s))


def relative_time(campaign, test: str) -> float:
    """One run of `test` over one UCS run, on the campaign's specimen: their works' ratio to
    the power WORK_EXPONENT, by the test's `time_factor`."""
    s = campaign.specimen
    work = specimen_size(test, s)[2] / specimen_size(PRIMARY_TEST, s)[2]
    return work ** WORK_EXPONENT[s.dimensions] * time_factor(test, s)


def genesis_work(test: str, s: SpecimenSettings) -> float:
    """Grains x rows of the packing a test's specimen is cut from (its whole vessel)."""
    kind = lab_test(test)
    o = kind.outline(kind.settings_of(s))
    if o.vessel_mm is not None:
        grains = cloud_spheres(o.vessel_volume_mm3, s.rmin_mm, s.radius_ratio, s.cloud_porosity)
        height_mm = o.vessel_mm[2]
    else:
        grains, height_mm = grain_count(o.width_mm, o.height_mm, s), o.height_mm
    return grains * height_mm / (s.rmin_mm * (1 + s.radius_ratio))


def genesis_s(test: str, s: SpecimenSettings, probe_ms: float) -> float:
    """The genesis of a test's packing on one thread of a machine whose probe step takes
    `probe_ms`, s."""
    d = s.dimensions
    clumps = GENESIS_CLUMPS if getattr(s, "grain_shape", DEFAULT_SHAPE) != DEFAULT_SHAPE else 1.0
    return probe_ms * GENESIS_S_PER_WORK[d] * genesis_work(test, s) * clumps
