"""Compile the engines' loops to 512-bit vectors on a processor with AVX-512.

LLVM, numba's compiler, prefers 256-bit vectors on such processors even where their 512-bit
units are there to use (on early ones a 512-bit instruction lowered the clock). The 3D bond
loop runs about a sixth faster with 512-bit vectors (`benchmarks/step_3d.py`); the 2D loops
neither gain nor lose. The numbers are the same either way, to the bit: numba compiles the
loops without fast-math, so each vector lane does the same IEEE operations in the same order,
whatever the lanes per instruction (`tests/dem/test_portable.py`).

numba sets up its compiler for the processor at its first compiled function, so this runs when
rockcal is imported: a user's own `NUMBA_CPU_NAME` or `NUMBA_CPU_FEATURES` is left as it is, and
a process that compiled a function of its own before importing rockcal keeps LLVM's choice. The
setting passes to the processes rockcal starts (a campaign's workers).
"""

import os
import sys

NO_256_BIT_PREFERENCE = "-prefer-256-bit"


def prefer_512_bit_vectors() -> bool:
    """Set `NUMBA_CPU_FEATURES` to this processor's features without LLVM's preference for
    256-bit vectors, if it has AVX-512 and the user set no processor of their own; whether it
    did."""
    if {"NUMBA_CPU_NAME", "NUMBA_CPU_FEATURES"} & os.environ.keys():
        return False
    from llvmlite import binding

    features = binding.get_host_cpu_features().flatten()
    if "+avx512f" not in features.split(","):
        return False
    os.environ["NUMBA_CPU_FEATURES"] = f"{features},{NO_256_BIT_PREFERENCE}"
    if "numba" in sys.modules:  # loaded, maybe with nothing compiled yet: read the setting now
        from numba.core import config

        config.reload_config()
    return True
