"""A long run stopped part way goes on from its last snapshot to the same numbers to the bit as
a run never stopped (`rockcal.labtests.snapshots`): a confined test of clumped flat-jointed
grains, a UCS test of balls, a UCS test of a cylinder of spheres and a confined test of a prism
of them, each stopped after half its readings and run again."""

import pickle
import numpy as np
import pytest

import rockcal
from rockcal.campaign.runs.pool import execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.input.config import SpecimenSettings
from rockcal.labtests.biaxial import simulate_biaxial
from rockcal.labtests.ucs import simulate_ucs
from rockcal.specimens.specimen import cache_dir
from rockcal.labtests import snapshots
from rockcal.labtests.biaxial import simulate_biaxial
from rockcal.labtests.registry import lab_test
from rockcal.labtests.settings import specimen_settings
from rockcal.labtests.ucs import simulate_ucs
from rockcal.materials import material, parameters

FLAT_JOINT = {"fj_emod": 30.0, "fj_kratio": 2.0, "fj_ten": 20.0, "fj_ten_cv": 0.2, "fj_coh": 60.0,
              "fj_coh_cv": 0.2}
BALLS = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0, "tau_c": 60.0, "sigma_c_cv": 0.2, "tau_c_cv": 0.2}


class Stopped(Exception):
    """The process killed part way."""


def _specimen(test: str, **settings):
    kind = lab_test(test)
    return kind.make(specimen_settings(kind, settings))


def _confined(**options):
    spec = _specimen("biaxial", width_mm=8, height_mm=16, rmin_mm=0.4, grain_shape="two-pebble")
    return simulate_biaxial(parameters(material("flatjoint"), FLAT_JOINT), spec, 5.0, **options)


def _ucs(**options):
    spec = _specimen("ucs", width_mm=10, height_mm=20, rmin_mm=0.4)
    return simulate_ucs(parameters(material("parallel_bond"), BALLS), spec, **options)


def _ucs_3d(**options):
    spec = _specimen("ucs", width_mm=8, height_mm=16, rmin_mm=0.5, dimensions=3)
    return simulate_ucs(parameters(material("parallel_bond"), BALLS), spec, **options)


def _confined_3d(**options):
    spec = _specimen("biaxial", width_mm=8, height_mm=16, rmin_mm=0.5, dimensions=3)
    return simulate_biaxial(parameters(material("parallel_bond"), BALLS), spec, 5.0, **options)


def _counted(stop_at: int | None = None):
    """A progress callback counting the readings; at reading `stop_at` it stops the run."""
    def progress(strain, load):
        progress.readings += 1
        if progress.readings == stop_at:
            raise Stopped

    progress.readings = 0
    return progress


def _equal(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, np.ndarray):
        return np.array_equal(a, b)
    return a == b


def _same(a, b) -> bool:
    """Two results alike to the bit in everything but their wall time."""
    a, b = vars(a) | {"wall_s": 0}, vars(b) | {"wall_s": 0}
    return _equal(a, b)


@pytest.mark.parametrize("run", [_confined, _ucs, _ucs_3d, _confined_3d],
                         ids=["confined clumped flat joints", "UCS of balls", "UCS of spheres", "confined spheres"])
def test_a_run_stopped_part_way_goes_on_from_its_snapshot_to_the_same_numbers(tmp_path, run):
    whole = _counted()
    uninterrupted = run(progress=whole)
    stop_at = whole.readings // 2
    with pytest.raises(Stopped), snapshots.kept_in(tmp_path, "key", every_s=0.0):
        run(progress=_counted(stop_at))
    kept = tmp_path / snapshots.FOLDER / "key.pickle"
    assert kept.exists()  # a stopped run keeps its snapshot
    rest = _counted()
    with snapshots.kept_in(tmp_path, "key", every_s=0.0):
        resumed = run(progress=rest)
    # it went on after the last reading saved: the one before the stop
    assert rest.readings == whole.readings - (stop_at - 1)
    assert _same(resumed, uninterrupted)
    assert not kept.exists()  # a run done leaves no snapshot


def test_a_snapshot_of_another_version_or_cut_short_is_left_aside(tmp_path):
    uninterrupted = _ucs()
    kept = tmp_path / snapshots.FOLDER / "key.pickle"
    kept.parent.mkdir()
    other_version = pickle.dumps(("0.0.0", 1.0, ("anything",)))
    for written in (snapshots._signature(other_version) + other_version, b"\x80\x05cut sh"):
        kept.write_bytes(written)
        whole = _counted()
        with snapshots.kept_in(tmp_path, "key", every_s=0.0):
            assert _same(_ucs(progress=whole), uninterrupted)
        assert not kept.exists()


def test_a_stored_run_takes_its_snapshot_in_the_stores_folder_and_leaves_none(tmp_path, monkeypatch):
    specimen = SpecimenSettings(width_mm=8, height_mm=16, rmin_mm=0.4)
    spec = run_spec("ucs", specimen, BALLS)
    kept = tmp_path / snapshots.FOLDER / f"{spec.key}.pickle"
    written = []
    save = snapshots.Snapshot.save

    def saved(snapshot, objects):  # a snapshot after every reading, each on disk in the store's folder
        save(snapshot, objects)
        written.append(snapshot.path == kept and kept.exists())

    monkeypatch.setattr(snapshots, "SNAPSHOT_EVERY_S", 0.0)
    monkeypatch.setattr(snapshots.Snapshot, "save", saved)
    result = execute(spec, snapshots_in=tmp_path)
    assert result.status == "ok"
    assert rockcal.__version__ in spec.engine
    assert written and all(written)
    assert not kept.exists()


def test_a_stored_run_gone_on_from_a_snapshot_counts_its_time_before(tmp_path, monkeypatch):
    """Its stored time, and its wall-time limit, count the time before the snapshot."""
    spec = run_spec("ucs", SpecimenSettings(width_mm=8, height_mm=16, rmin_mm=0.4), BALLS)
    monkeypatch.setattr(snapshots, "earlier_s", lambda: 1e6)  # as if a day ran before the stop
    assert execute(spec, snapshots_in=tmp_path).wall_s > 1e6
    timed_out = execute(spec, time_limit_s=1e5, snapshots_in=tmp_path)
    assert timed_out.status == "timed out" and timed_out.wall_s > 1e6


class _Planted:
    """An object whose unpickling would write a file: what a hostile snapshot could do."""

    def __init__(self, mark):
        self.mark = mark

    def __reduce__(self):
        return (open, (str(self.mark), "w"))


def test_a_snapshot_not_signed_with_the_users_key_is_never_unpickled(tmp_path):
    uninterrupted = _ucs()
    mark = tmp_path / "unpickled"
    kept = tmp_path / snapshots.FOLDER / "key.pickle"
    kept.parent.mkdir()
    body = pickle.dumps((rockcal.__version__, 1.0, _Planted(mark)))
    kept.write_bytes(bytes(32) + body)  # signed with another key
    with snapshots.kept_in(tmp_path, "key", every_s=0.0):
        assert _same(_ucs(), uninterrupted)
    assert not mark.exists()
    key = cache_dir() / snapshots.KEY_FILE
    assert key.stat().st_mode & 0o777 == 0o600


def test_a_snapshot_never_writes_through_a_link_planted_in_its_folder(tmp_path):
    """Run keys are predictable: a link at the snapshot's name, or at its old `.part` name, is
    replaced or left, never followed; the snapshot is whole and loads back."""
    target = tmp_path / "precious"
    target.write_bytes(b"keep me")
    folder = tmp_path / snapshots.FOLDER
    folder.mkdir()
    for name in ("key.part", "key.pickle"):
        (folder / name).symlink_to(target)
    snapshot = snapshots.Snapshot(folder / "key.pickle", every_s=0.0)
    snapshot.save(("readings", [1, 2, 3]))
    assert target.read_bytes() == b"keep me"
    assert not (folder / "key.pickle").is_symlink()
    assert snapshots.Snapshot(folder / "key.pickle").load() == ("readings", [1, 2, 3])
    assert [p.name for p in folder.iterdir() if p.name.startswith(".")] == []  # no temporary file left
