"""Packings on a Dask cluster: made once, where a worker is free, and sent with the runs cut
from them, so that no machine makes a packing another has made.

Each packing a batch needs that rockcal does not ship is read from the driver's specimen cache
or, if it is not there, made by a task of its own on a worker (the packings of a batch in
parallel, one per worker). Its file's bytes are then scattered to every worker (a killed worker
takes no packing with it) and written into the driver's cache (for a resume or a report), and
each run task writes its packing into its worker's cache before it runs (`install`). A 3D
packing of 25 000 spheres is about 0.8 MB.
"""

from __future__ import annotations

from typing import Callable, Iterable

from rockcal.campaign.runs.packings import new_packings, packing_file
from rockcal.campaign.runs.pool import prepare
from rockcal.campaign.runs.spec import RunSpec
from rockcal.output_files import atomic_path
from rockcal.specimens.specimen import cache_dir, stored_packing

Packing = tuple[str, bytes]  # a packing file's name and bytes


def make_packing(spec: RunSpec) -> Packing | None:
    """The task that makes the packing of `spec` on a worker (into its cache) and returns it;
    None where it cannot be made (its runs then fail as they would anywhere)."""
    import numba

    numba.set_num_threads(1)
    prepare(spec)
    name = packing_file(spec)
    path = stored_packing(name)
    return None if path is None else (name, path.read_bytes())


def install(packing: Packing | None) -> None:
    """Write a packing into this process's specimen cache unless it holds it already."""
    if packing is None:
        return
    name, data = packing
    path = cache_dir() / name
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp:
            tmp.write_bytes(data)


class ClusterPackings:
    """The packings a campaign's runs on `client` are cut from, each scattered once; `made`
    counts those made on the cluster."""

    def __init__(self, client):
        self.client = client
        self.made = 0
        self._scattered: dict[str, object] = {}  # name -> the future of its Packing on the cluster

    def of(self, spec: RunSpec):
        """The future of the packing `spec` is cut from, or None (none, or rockcal ships it)."""
        return self._scattered.get(packing_file(spec))

    def ready(self, specs: Iterable[RunSpec], show: Callable[[int, int], None] | None = None) -> None:
        """Scatter the packings of `specs` not scattered yet, making those no cache holds;
        show(made, to make) as they are made."""
        from distributed import as_completed

        specs = list(specs)
        for name in {packing_file(spec) for spec in specs} - {None} - set(self._scattered):
            path = stored_packing(name)
            if path is not None and path.parent == cache_dir():  # a shipped one is on every worker
                self._scatter((name, path.read_bytes()))
        to_make = [spec for spec in new_packings(specs) if packing_file(spec) not in self._scattered]
        if not to_make:
            return
        show = show or (lambda done, total: None)
        show(0, len(to_make))
        futures = [self.client.submit(make_packing, spec, key=f"rockcal-packing-{packing_file(spec)}",
                                      pure=False) for spec in to_make]
        for done, future in enumerate(as_completed(futures), start=1):
            try:
                packing = future.result()
            except Exception:  # its worker kept dying: the runs make it, or fail, where they run
                packing = None
            future.release()
            if packing is not None:
                install(packing)
                self._scatter(packing)
                self.made += 1
            show(done, len(to_make))

    def _scatter(self, packing: Packing) -> None:
        self._scattered[packing[0]], = self.client.scatter([packing], broadcast=True, hash=False)
