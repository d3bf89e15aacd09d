"""Comparing a campaign's record with one written on another machine.

The engine's numbers, the stored runs read back, the run keys and every parameter set the
procedure runs (rounded to 4 significant digits) are the same to the bit on every processor of
our kind. What goes through BLAS, LAPACK or numpy's SIMD code (the surrogate's predictions, the
search's objective, the intervals, the verdict's least errors, the curve fit) follows the
kernels the processor picks (AVX2 or AVX-512), and agrees only to round-off: those parts of the
record are compared to a relative ROUNDOFF, every other value exactly.
"""

import math

ROUNDOFF = 1e-9

# dotted paths into the record ("*": any list item) whose numbers come from BLAS or scipy
BLAS_PATHS = (
    "surrogate_check.predicted", "surrogate_check.max_relative_error",
    "iterations.*.predicted", "iterations.*.history_x",
    "uncertainty.intervals", "uncertainty.samples",
    "verdict.unreachable", "verdict.conflicts.*.least_error", "verdict.least_error_all",
    "curve_fit",
)
# the search's objective, a sum of squared relative errors: near its zero a relative round-off
# of the predictions is an absolute one of its square root (the errors' root sum of squares)
OBJECTIVE_PATHS = ("iterations.*.objective_surrogate", "iterations.*.history_fun")


def differences(now, before, path: str = "") -> list[str]:
    """Where `now` differs from `before`: beyond ROUNDOFF under BLAS_PATHS and OBJECTIVE_PATHS,
    at all elsewhere."""
    if isinstance(before, dict):
        if not isinstance(now, dict) or now.keys() != before.keys():
            return [f"{path or 'record'}: keys {sorted(now) if isinstance(now, dict) else now!r} "
                    f"against {sorted(before)}"]
        return [d for key in before for d in differences(now[key], before[key], _join(path, key))]
    if isinstance(before, list):
        if not isinstance(now, list) or len(now) != len(before):
            return [f"{path}: {now!r} against {before!r}"]
        return [d for i, (a, b) in enumerate(zip(now, before)) for d in differences(a, b, _join(path, str(i)))]
    numbers = isinstance(now, float) and isinstance(before, float)
    if numbers and _under(path, OBJECTIVE_PATHS) and now >= 0 and before >= 0:
        same = abs(math.sqrt(now) - math.sqrt(before)) <= ROUNDOFF
    elif numbers and _under(path, BLAS_PATHS):
        same = math.isclose(now, before, rel_tol=ROUNDOFF, abs_tol=0.0)
    else:
        same = type(now) is type(before) and now == before
    return [] if same else [f"{path}: {now!r} against {before!r}"]


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _under(path: str, patterns: tuple[str, ...]) -> bool:
    parts = path.split(".")
    return any(len(parts) >= len(head) and all(h == p or (h == "*" and p.isdigit()) for h, p in zip(head, parts))
               for head in (pattern.split(".") for pattern in patterns))
