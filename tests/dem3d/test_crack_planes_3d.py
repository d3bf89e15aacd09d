"""A 3D run's cracks on three planes (`plots.crack_planes`): each crack lands where its 3D
position projects on the front (x-z), side (y-z) and top (x-y) panels, inside the specimen's
outline (a circle where the shape is round); a 3D run keeps its cracks' (x, y, z) through the
run store and the report draws them on the three planes, a 3D run stored with its cracks seen
from the front is drawn from the front, and a 2D run's crack figure is drawn as before."""

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.patches import Circle, Rectangle

from rockcal import plots
from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.outputs.figures import _cracks
from rockcal.campaign.runs.pool import execute
from rockcal.campaign.runs.spec import RunResult, run_spec
from rockcal.campaign.runs.store import RunStore, to_blob
from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION
from rockcal.labtests.ucs import simulate_ucs
from rockcal.labtests.settings import specimen_settings
from rockcal.labtests.ucs import TEST as UCS

CYLINDER_M = (25e-3, 25e-3, 50e-3)
# cracks at known points (m): two in tension, one in shear
TENSION = np.array([[1e-3, 2e-3, 3e-3], [20e-3, 5e-3, 45e-3]])
SHEAR = np.array([[12e-3, 24e-3, 30e-3]])


def panels(fig) -> dict:
    """The figure's panels by view name ("front", "side", "top")."""
    return {ax.get_title().split()[0]: ax for ax in fig.axes if ax.get_title()}


def drawn(ax, mode: str) -> np.ndarray:
    """The points (mm) a panel drew for the cracks of `mode`, read back from its line."""
    line = next(line for line in ax.get_lines() if line.get_label().startswith(mode))
    return np.column_stack(line.get_data())


def test_plane_view_takes_the_two_coordinates_of_each_plane():
    xyz = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    assert plots.plane_view(xyz, "xz").tolist() == [[1, 3], [4, 6]]
    assert plots.plane_view(xyz, "yz").tolist() == [[2, 3], [5, 6]]
    assert plots.plane_view(xyz, "xy").tolist() == [[1, 2], [4, 5]]
    assert plots.plane_view(np.empty((0, 3)), "xy").shape == (0, 2)


def test_each_crack_lands_at_its_projection_on_each_panel():
    fig = plots.crack_planes_figure({"tension": TENSION, "shear": SHEAR}, "cylinder", CYLINDER_M, "cracks")
    try:
        found = panels(fig)
        assert set(found) == {"front", "side", "top"}
        for view, columns, labels in (("front", [0, 2], ("x (mm)", "z (mm)")),
                                      ("side", [1, 2], ("y (mm)", "z (mm)")),
                                      ("top", [0, 1], ("x (mm)", "y (mm)"))):
            ax = found[view]
            assert np.allclose(drawn(ax, "tension"), 1e3 * TENSION[:, columns]), view
            assert np.allclose(drawn(ax, "shear"), 1e3 * SHEAR[:, columns]), view
            assert (ax.get_xlabel(), ax.get_ylabel()) == labels
            assert ax.get_aspect() == 1.0
        colours = {line.get_label().split()[0]: line.get_color() for line in found["front"].get_lines()}
        assert colours == {"tension": "tab:red", "shear": "tab:blue"}  # as the 2D crack pattern's
    finally:
        plt.close(fig)


@pytest.mark.parametrize("shape, size_m, round_view", [
    ("cylinder", CYLINDER_M, "top"),       # a cylinder is round seen from the top
    ("disk", (20e-3, 10e-3, 20e-3), "front"),  # a disk along y from the front
    ("cuboid", (12e-3, 12e-3, 24e-3), None),
])
def test_the_outline_is_the_specimens_shape_on_each_plane(shape, size_m, round_view):
    fig = plots.crack_planes_figure({"tension": TENSION, "shear": SHEAR}, shape, size_m, shape)
    try:
        for view, ax in panels(fig).items():
            (patch,) = ax.patches
            plane = dict((v, p) for v, p, _ in plots.VIEWS)[view]
            across, up = (1e3 * size_m["xyz".index(c)] for c in plane)
            if view == round_view:
                assert isinstance(patch, Circle)
                assert patch.center == pytest.approx((across / 2, up / 2)) and patch.radius == pytest.approx(across / 2)
            else:
                assert isinstance(patch, Rectangle)
                assert (patch.get_x(), patch.get_y(), patch.get_width(), patch.get_height()) == \
                    pytest.approx((0, 0, across, up))
    finally:
        plt.close(fig)


class Spy:
    """A plotting function's calls (its arguments), each then drawn as it would be."""

    def __init__(self, draw):
        self.draw, self.calls = draw, []

    def __call__(self, *args, **kwargs):
        self.calls.append((args, kwargs))
        return self.draw(*args, **kwargs)


@pytest.fixture
def spies(monkeypatch):
    found = {name: Spy(getattr(plots, name)) for name in ("crack_planes", "crack_pattern")}
    for name, spy in found.items():
        monkeypatch.setattr(plots, name, spy)
    return found


ROWS_2D = np.array([[1e-3, 2e-3, BROKEN_TENSION], [3e-3, 4e-3, BROKEN_SHEAR], [5e-3, 6e-3, BROKEN_TENSION]])


def test_a_2d_runs_crack_figure_is_drawn_as_before(tmp_path, spies):
    """The stored (x, y, mode) rows of a 2D run are drawn over its disks by `crack_pattern`, the
    positions of each mode as before 3D kept its cracks' z."""
    settings = SpecimenSettings(width_mm=5.0, height_mm=10.0, rmin_mm=0.3)
    spec = run_spec("ucs", settings, {})
    store = RunStore(tmp_path)
    store.put(spec, RunResult("ok", {}, np.zeros((3, 4)), 1.0, cracks=ROWS_2D))
    assert _cracks(spec.key, "UCS run", store, tmp_path / "cracks.png") is None
    assert not spies["crack_planes"].calls
    (args, kwargs), = spies["crack_pattern"].calls
    positions, _, modes = args[:3]
    assert positions.shape[1] == 2 and kwargs == {}
    for mode, code in (("tension", BROKEN_TENSION), ("shear", BROKEN_SHEAR)):
        assert np.array_equal(modes[mode], ROWS_2D[ROWS_2D[:, 2] == code, :2])
    store.close()


CYLINDER = {"dimensions": 3, "width_mm": 7.0, "height_mm": 14.0, "rmin_mm": 0.5}
PARAMS = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0, "tau_c": 60.0}


@pytest.mark.slow  # a genesis (cached) and one small 3D run: a few seconds
def test_a_3d_run_keeps_its_cracks_in_3d_through_the_store(tmp_path, spies):
    """A 3D UCS run through the lab-test kind stores (x, y, z, mode) rows, the engine's break
    points; they read back from the store and the report's crack figure draws them on three
    planes within the cylinder's outline; the same run stored before, as (x, z, mode) rows,
    is drawn from the front."""
    spec = run_spec("ucs", SpecimenSettings(**CYLINDER), PARAMS)
    result = execute(spec)
    assert result.status == "ok", result.message
    assert result.cracks.shape[1] == 4
    store = RunStore(tmp_path)
    store.put(spec, result)
    stored = store.run(spec.key).cracks
    assert np.array_equal(stored, result.cracks)

    direct = simulate_ucs(PARAMS, UCS.make(specimen_settings(UCS, CYLINDER)))
    for code, mode in ((BROKEN_TENSION, "tension"), (BROKEN_SHEAR, "shear")):
        assert np.array_equal(stored[stored[:, 3] == code, :3], direct.cracks[mode])

    assert _cracks(spec.key, "UCS run", store, tmp_path / "planes.png") is None
    (args, _), = spies["crack_planes"].calls
    modes, shape, size_m = args[:3]
    assert shape == "cylinder" and size_m == pytest.approx((7e-3, 7e-3, 14e-3))
    assert np.array_equal(modes["tension"], direct.cracks["tension"])
    assert (tmp_path / "planes.png").stat().st_size > 0

    # a run stored with its cracks seen from the front (x, z, mode): today's front view
    old = np.column_stack([stored[:, [0, 2]], stored[:, 3]])
    store.db.execute("UPDATE runs SET cracks=? WHERE key=?", (to_blob(old), spec.key))
    assert _cracks(spec.key, "UCS run", store, tmp_path / "front.png") is None
    (args, kwargs), = spies["crack_pattern"].calls
    assert kwargs["axes"] == ("x", "z") and args[0].shape[1] == 2
    assert np.array_equal(args[2]["tension"], direct.cracks["tension"][:, [0, 2]])
    store.close()
