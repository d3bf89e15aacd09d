"""Compile the engines' loops to 512-bit vectors on a processor with AVX-512.

LLVM, numba's compiler, prefers 256-bit vectors on such processors even where their 512-bit
units are there to use (on early ones a 512-bit instruction lowered the clock). With 512-bit
vectors the 3D step runs 8-14 % faster and the 2D step 4-11 % on an Intel Xeon
(`benchmarks/step_3d.py`). The numbers are the same either way, to the bit: numba compiles the
loops without fast-math, so each vector lane does the same IEEE operations in the same order,
whatever the lanes per instruction (`tests/dem/test_portable.py`).

numba sets up its compiler for the processor at its first compiled function, so this runs when
rockcal is imported: a user's own `NUMBA_CPU_NAME`, `NUMBA_CPU_FEATURES` or `NUMBA_ENABLE_AVX`
is left to decide, and a process that compiled a function of its own before importing rockcal
keeps LLVM's choice. The setting passes to the processes rockcal starts (a campaign's workers).
"""

import os
import sys

NO_256_BIT_PREFERENCE = "-prefer-256-bit"
USERS_OWN = ("NUMBA_CPU_NAME", "NUMBA_CPU_FEATURES", "NUMBA_ENABLE_AVX")


def prefer_512_bit_vectors() -> bool:
    """Set `NUMBA_CPU_FEATURES` to this processor's features without LLVM's preference for
    256-bit vectors, if it has AVX-512 and the user set no processor of their own; whether it
    did."""
    if any(name in os.environ for name in USERS_OWN):
        return False
    from llvmlite import binding

    try:
        features = binding.get_host_cpu_features().flatten()
    except RuntimeError:  # LLVM cannot tell on this platform: numba then compiles generic code
        return False
    if "+avx512f" not in features.split(","):
        return False
    os.environ["NUMBA_CPU_FEATURES"] = f"{features},{NO_256_BIT_PREFERENCE}"
    if "numba" in sys.modules:  # loaded, maybe with nothing compiled yet: read the setting now
        from numba.core import config

        config.reload_config()
    return True
