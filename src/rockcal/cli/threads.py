"""The `--threads` option of `rockcal simulate` and `rockcal calibrate`."""

from __future__ import annotations

import numba

from rockcal.dem.simulate import use_threads
from rockcal.errors import InputError


def use_threads_option(threads: int | None) -> None:
    """The engine's threads from `--threads`: a fixed number, or (None) one per free core."""
    if threads is not None and threads > numba.config.NUMBA_NUM_THREADS:
        raise InputError("--threads", f"at most {numba.config.NUMBA_NUM_THREADS} here "
                                      f"(NUMBA_NUM_THREADS), got {threads}")
    use_threads(threads)
