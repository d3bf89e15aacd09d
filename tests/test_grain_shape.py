"""`grain_shape` as a specimen setting of the lab tests (UCS, Brazilian, bending), of the campaign
file's [specimen] and of `rockcal simulate`: stored runs keep their keys at the default (balls),
the packing of a test carries it, and carving a disk or a notch keeps or drops clumps whole.

Small specimens (a few hundred grains) keep each test to seconds."""

from types import SimpleNamespace

import numpy as np
import pytest
from pydantic import ValidationError

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.spec import ENGINE, RunSpec, run_spec
from rockcal.specimens.carving import grains, keep_particles
from rockcal.specimens.specimen import packing_name
from rockcal.labtests import bending, brazilian, ucs
from rockcal.labtests.bending import Beam, notched_beam
from rockcal.labtests.brazilian import brazilian_disk
from rockcal.labtests.kind import LATER_SETTINGS, all_settings
from rockcal.labtests.settings import specimen_settings
from rockcal.labtests.ucs import ucs_specimen

SMALL = dict(rmin_mm=0.5, radius_ratio=1.25)


def test_a_ucs_run_at_the_default_shape_keeps_the_key_it_had_before_the_setting():
    settings = SpecimenSettings()
    assert settings.grain_shape == "ball" and LATER_SETTINGS["grain_shape"] == "ball"
    before = [name for name in ucs.TEST.settings if name != "grain_shape"]
    old_key = {name: getattr(settings, name) for name in before
               if not (name in LATER_SETTINGS and getattr(settings, name) == LATER_SETTINGS[name])}
    spec = run_spec("ucs", settings, {})
    assert dict(spec.specimen) == old_key
    assert spec.key == RunSpec("ucs", tuple(old_key.items()), spec.params, spec.engine).key
    assert spec.engine.startswith(ENGINE)
    assert all_settings(dict(spec.specimen))["grain_shape"] == "ball"
    # settings made before the shape existed (without it as an attribute) make balls
    assert ucs.TEST.settings_of(SimpleNamespace(**all_settings(old_key)))["grain_shape"] == "ball"
    assert "grain_shape" not in SpecimenSettings().model_dump()  # left out of a record at its default
    other = run_spec("ucs", SpecimenSettings(grain_shape="two-pebble"), {})
    assert dict(other.specimen)["grain_shape"] == "two-pebble" and other.key != spec.key


@pytest.mark.parametrize("test", [ucs.TEST, brazilian.TEST, bending.TEST])
def test_the_packing_of_a_test_carries_the_shape(test):
    for shape in ("ball", "two-pebble"):
        p = test.packing(SpecimenSettings(grain_shape=shape))
        assert p["grain_shape"] == shape
    # ball packings keep their file names
    ball = test.packing(SpecimenSettings())
    assert packing_name(**ball) == packing_name(**{k: v for k, v in ball.items() if k != "grain_shape"})


def test_an_unknown_shape_is_refused_naming_the_setting():
    with pytest.raises(ValidationError, match="grain_shape"):
        SpecimenSettings(grain_shape="blob")
    with pytest.raises(Exception, match="grain_shape"):
        specimen_settings(ucs.TEST, {"grain_shape": "blob"})


def _clumps_whole(spec, source) -> None:
    """Every clump of `spec` is a whole clump of `source` (as many pebbles), numbered 0..n-1."""
    assert spec.clump_of is not None and len(spec.clump_of) == spec.n_particles
    assert set(np.unique(spec.clump_of)) == set(range(spec.n_grains))
    counts = np.bincount(spec.clump_of)
    assert (counts == np.bincount(source.clump_of)[0]).all()  # a template's pebbles, every one
    # no bond within a clump
    assert (spec.clump_of[spec.bonds[:, 0]] != spec.clump_of[spec.bonds[:, 1]]).all()


def test_a_disk_keeps_whole_clumps_judged_at_their_centroids():
    disk = brazilian_disk(12.0, seed=1, grain_shape="two-pebble", **SMALL)
    square = ucs_specimen(12.0, 12.0, seed=1, grain_shape="two-pebble", **SMALL)
    _clumps_whole(disk, square)
    assert disk.n_grains < square.n_grains and disk.n_particles == 2 * disk.n_grains
    centre, size = grains(disk)
    r = 6e-3
    assert (np.hypot(*(centre - r).T) + size <= r * (1 + 1e-12)).all()
    # the ball disk as before: judged as its balls
    balls = brazilian_disk(12.0, seed=1, **SMALL)
    assert balls.clump_of is None


def test_a_notch_removes_whole_clumps():
    beam = Beam(length_mm=30.0, height_mm=10.0, notch_mm=3.0, notch_width_mm=1.5, span_mm=24.0)
    notched = notched_beam(beam, seed=1, grain_shape="two-pebble", **SMALL)
    source = ucs_specimen(30.0, 10.0, seed=1, grain_shape="two-pebble", **SMALL)
    _clumps_whole(notched, source)
    assert notched.n_grains < source.n_grains
    centre, size = grains(notched)
    middle, half = 15e-3, 0.75e-3  # no kept clump's disk overlaps the notch
    dx = np.maximum.reduce([middle - half - centre[:, 0], np.zeros(len(centre)), centre[:, 0] - middle - half])
    dy = np.maximum(centre[:, 1] - 3e-3, 0.0)
    assert (dx**2 + dy**2 >= size**2).all()
    cut = notched_beam(Beam(length_mm=30.0, height_mm=10.0, notch_mm=3.0, notch_width_mm=0.0, span_mm=24.0),
                       seed=1, grain_shape="two-pebble", **SMALL)
    assert cut.n_particles == source.n_particles and (cut.clump_of == source.clump_of).all()


def test_keep_particles_keeps_a_clump_only_with_all_its_pebbles():
    spec = ucs_specimen(10.0, 10.0, seed=1, grain_shape="two-pebble", **SMALL)
    keep = np.ones(spec.n_particles, bool)
    keep[np.flatnonzero(spec.clump_of == 3)[0]] = False  # one pebble of clump 3
    out = keep_particles(spec, keep, "less clump 3")
    assert out.n_grains == spec.n_grains - 1 and out.n_particles == spec.n_particles - 2


def test_simulate_ucs_with_two_pebble_grains(cli):
    import json

    run = cli("simulate", "ucs", "--grain-shape", "two-pebble", "--width-mm", "10", "--height-mm", "20",
              "--rmin-mm", "0.5", "--radius-ratio", "1.25", "--json")
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    assert summary["n_particles"] == 2 * summary["n_grains"]
    assert "two-pebble clumps" in summary["specimen"] and summary["ucs_MPa"] > 0


def test_simulate_refuses_an_unknown_shape_in_one_line(cli):
    run = cli("simulate", "ucs", "--grain-shape", "blob", "--width-mm", "10", "--height-mm", "20",
              "--rmin-mm", "0.5")
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "--grain-shape" in lines[0], run.stderr
    assert "Traceback" not in run.stderr
