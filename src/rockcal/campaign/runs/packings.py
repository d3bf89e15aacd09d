"""The packings a batch of runs is cut from: those neither in the specimen cache nor shipped
with rockcal are made first, a stage of their own with its own progress (a genesis can take
longer than its specimen's test), one packing per worker at a time."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Callable, Iterable

from rockcal.campaign.runs.spec import RunSpec
from rockcal.labtests.kind import all_settings
from rockcal.labtests.registry import lab_test
from rockcal.specimens.specimen import stored_packing

Progress = Callable[[int, int], None]  # progress(packings made, packings to make)


def packing_file(spec: RunSpec) -> str | None:
    """The file name of the packing a run's specimen is cut from (None: it makes none)."""
    return lab_test(spec.kind).packing_file(SimpleNamespace(**all_settings(dict(spec.specimen))))


def new_packings(specs: Iterable[RunSpec]) -> list[RunSpec]:
    """A run for each distinct packing that `specs` are cut from and that is neither cached nor
    shipped: making its specimen makes the packing."""
    found: dict[str, RunSpec] = {}
    for spec in specs:
        name = packing_file(spec)
        if name is not None and name not in found and stored_packing(name) is None:
            found[name] = spec
    return list(found.values())


def make_in_turn(specs: list[RunSpec], make: Callable[[RunSpec], None], progress: Progress | None) -> None:
    """Make the specimens of `specs` one after another here, showing `progress`."""
    for done, spec in enumerate(specs):
        if progress:
            progress(done, len(specs))
        make(spec)
    if progress and specs:
        progress(len(specs), len(specs))
