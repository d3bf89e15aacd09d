"""A specimen's genesis and its UCS run give the same numbers whichever SIMD code numpy picks
and whichever BLAS kernel OpenBLAS picks for this CPU: machines differ (AVX2, AVX-512), and a
bonded specimen breaking amplifies a last-bit difference into a different UCS (on the twin's
202 disks `rb**3`, computed by numpy's AVX-512 `pow`, moved it by up to 14 %; on two-pebble
clumps a dot product by OpenBLAS's SkylakeX kernel moved the UCS of a twin's truth by 9 %).
Balls, two-pebble clumps and spheres (3D) are each run in processes where numpy may use only
its baseline code, or OpenBLAS only its kernels without fused multiply-add, or numba's loops
only LLVM's preferred 256-bit vectors where rockcal has it use 512 (`rockcal.wide_vectors`;
balls and spheres)."""

import os
import subprocess
import sys

import numpy as np
import pytest

from rockcal.wide_vectors import NO_256_BIT_PREFERENCE

RUN = """
import hashlib
import sys
import rockcal
params = {"E_c": 20, "kn_ks": 2.0, "sigma_c": 40, "tau_c": 200, "sigma_c_cv": 0.23, "tau_c_cv": 0.23,
          "phi_b": 20}
specimens = {"balls": {"width_mm": 10, "height_mm": 20, "rmin_mm": 0.4, "seed": 2},
             "clumps": {"width_mm": 8, "height_mm": 16, "rmin_mm": 0.4, "grain_shape": "two-pebble"},
             "spheres": {"width_mm": 8, "height_mm": 16, "rmin_mm": 0.5, "dimensions": 3}}
for specimen in sys.argv[1:] or specimens:
    result = rockcal.simulate("ucs", params, **specimens[specimen])
    cracks = result.cracks if isinstance(result.cracks, dict) else {"": result.cracks}  # 3D: by axis
    digest = hashlib.sha256(result.curve.tobytes())
    for name in sorted(cracks):
        digest.update(cracks[name].tobytes())
    print(digest.hexdigest()[:16])
"""
# OpenBLAS's oldest x86-64 kernels, without FMA: another rounding than every newer processor's
OLDEST_BLAS = {"OPENBLAS_CORETYPE": "Prescott"}


def _run(tmp_path, name: str, env: dict, specimens: tuple[str, ...] = ()) -> list[str]:
    """The fingerprints of `specimens` (all: balls, clumps, spheres) run in a new process."""
    cache = tmp_path / name  # a cache of its own: the genesis runs in each process
    done = subprocess.run([sys.executable, "-c", RUN, *specimens], capture_output=True, text=True,
                          check=True, env=os.environ | env | {"ROCKCAL_CACHE": str(cache)})
    return done.stdout.split()


def _numpy_dispatch() -> list[str]:
    umath = (np._core if hasattr(np, "_core") else np.core)._multiarray_umath  # numpy 2, 1.26
    return [f for f in getattr(umath, "__cpu_dispatch__", []) if umath.__cpu_features__.get(f)]


@pytest.fixture(scope="module")
def as_dispatched(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("portable"), "dispatched", {})


@pytest.mark.slow
def test_the_numbers_do_not_depend_on_numpys_simd_code(tmp_path, as_dispatched):
    found = _numpy_dispatch()
    if not found:
        pytest.skip("numpy dispatches no SIMD code beyond its baseline on this CPU")
    assert len(as_dispatched) == 3
    assert _run(tmp_path, "baseline", {"NPY_DISABLE_CPU_FEATURES": " ".join(found)}) == as_dispatched


@pytest.mark.slow
def test_the_numbers_do_not_depend_on_the_blas_kernel(tmp_path, as_dispatched):
    assert len(as_dispatched) == 3
    assert _run(tmp_path, "oldest-blas", OLDEST_BLAS) == as_dispatched


@pytest.mark.slow
def test_the_numbers_do_not_depend_on_the_vector_width(tmp_path, as_dispatched):
    features = os.environ.get("NUMBA_CPU_FEATURES", "")
    if not features.endswith(NO_256_BIT_PREFERENCE):
        pytest.skip("rockcal compiles for 512-bit vectors only on a processor with AVX-512")
    assert len(as_dispatched) == 3
    llvm_choice = features.removesuffix("," + NO_256_BIT_PREFERENCE)  # compiles the engines anew
    # balls and spheres: compiling the clumps' engine anew as well would add most of a minute
    assert _run(tmp_path, "256-bit", {"NUMBA_CPU_FEATURES": llvm_choice}, ("balls", "spheres")) \
        == [as_dispatched[0], as_dispatched[2]]
