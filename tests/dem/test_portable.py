"""A specimen's genesis and its UCS run give the same numbers whichever SIMD code numpy picks
for this CPU: machines differ (AVX2, AVX-512), and a bonded specimen breaking amplifies a
last-bit difference into a different UCS (on the twin's 202 disks `rb**3`, computed by numpy's
AVX-512 `pow`, moved it by up to 14 %). The run is repeated in a process where numpy may use
only its baseline code."""

import os
import subprocess
import sys

import numpy as np
import pytest

RUN = """
import hashlib
import rockcal
specimen = rockcal.random_packing(10, 20, 0.4, seed=2)
result = rockcal.simulate_ucs({"E_c": 20, "kn_ks": 2.0, "sigma_c": 40, "tau_c": 200,
                               "sigma_c_cv": 0.23, "tau_c_cv": 0.23, "phi_b": 20}, specimen)
print(hashlib.sha256(specimen.pos.tobytes() + result.curve.tobytes()).hexdigest())
"""


def _run(tmp_path, name: str, env: dict) -> str:
    cache = tmp_path / name  # a cache of its own: the genesis runs in each process
    done = subprocess.run([sys.executable, "-c", RUN], capture_output=True, text=True, check=True,
                          env=os.environ | env | {"ROCKCAL_CACHE": str(cache)})
    return done.stdout.strip()


@pytest.mark.slow
def test_the_numbers_do_not_depend_on_numpys_simd_code(tmp_path):
    umath = (np._core if hasattr(np, "_core") else np.core)._multiarray_umath  # numpy 2, 1.26
    found = [f for f in getattr(umath, "__cpu_dispatch__", []) if umath.__cpu_features__.get(f)]
    if not found:
        pytest.skip("numpy dispatches no SIMD code beyond its baseline on this CPU")
    assert _run(tmp_path, "dispatched", {}) == \
        _run(tmp_path, "baseline", {"NPY_DISABLE_CPU_FEATURES": " ".join(found)})
