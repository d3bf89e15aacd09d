"""The engine's numbers do not depend on its thread count, even changed in the middle of a run
(a campaign's pool gives the last running test both cores once the other worker is idle; the
engine takes fewer threads when cores are busy)."""

import numba
import numpy as np
import pytest

from rockcal import hexagonal, simulate_ucs
from rockcal.dem.neighbours import block_starts
from rockcal.dem.simulate import _advance_all, use_threads
from rockcal.materials.flat_joint import make_flatjoint_params
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

pytestmark = pytest.mark.slow  # DEM runs and specimens of minutes: deselect with -m "not slow"

PARAMS = {"E_c": 20, "kn_ks": 2.0, "sigma_c": 10, "tau_c": 20, "sigma_c_cv": 0.3, "tau_c_cv": 0.3}
FLATJOINTED = make_flatjoint_params({"fj_emod": 20, "fj_kratio": 2.0, "fj_ten": 10, "fj_coh": 20,
                                     "fj_ten_cv": 0.3, "fj_coh_cv": 0.3, "fjm_B_frac": 0.8})


@pytest.mark.parametrize("params, size_mm", [(PARAMS, (20, 40)), (FLATJOINTED, (16, 32))],
                         ids=["parallel_bond", "flatjoint"])  # two blocks of grains each
def test_a_run_switching_between_one_and_two_threads_gives_the_same_numbers(params, size_mm):
    specimen = hexagonal(*size_mm, 0.25)
    assert len(block_starts(len(specimen.pos))) - 1 >= 2  # blocks run in parallel
    cap = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = simulate_ucs(params, specimen)
        switches = []

        def switch(strain, stress):
            switches.append(strain)
            use_threads(1 + len(switches) % min(2, numba.config.NUMBA_NUM_THREADS))

        switched = simulate_ucs(params, specimen, progress=switch)
    finally:
        use_threads(None)
        numba.set_num_threads(cap)
    assert one.n_broken_tension + one.n_broken_shear > 100  # it failed
    assert len(switches) > 100
    assert np.array_equal(one.curve, switched.curve)
    assert (one.ucs_MPa, one.E_GPa, one.nu, one.steps) == \
        (switched.ucs_MPa, switched.E_GPa, switched.nu, switched.steps)


def test_steps_go_on_when_one_thread_does_every_task():
    """Two workers' tasks run by one thread, the first worker's all steps before the second
    starts (as when the system keeps a thread from running): the first does the second's
    tasks once kept waiting, and the numbers are those of one worker."""
    specimen = hexagonal(20, 40, 0.25)
    cap = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        runs = []
        for workers in (1, 2):
            state = new_state(specimen.pos, specimen.radius, specimen.bonds, make_params(PARAMS),
                              walls=(0, 0, specimen.pos[:, 1].min() - 0.25e-3,
                                     specimen.pos[:, 1].max() + 0.25e-3),
                              wall_active=(False, False, True, True))
            state.walls.vel[2:] = (0.05, -0.05)
            _advance_all(state, 300, workers)
            runs.append(state)
    finally:
        numba.set_num_threads(cap)
    one, two = runs
    assert one.step == two.step == 300
    assert np.array_equal(one.particles.disks, two.particles.disks)
    assert np.array_equal(one.walls.pos, two.walls.pos)
