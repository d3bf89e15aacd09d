"""The misfit F between measured and computed responses (the objective of the inverse procedure).

F = Σ_i w_i e_i² + Σ_c w_c RE_c², where for each scalar response i
- "relative" (default): e_i = (y_i^c − y_i^m) / y_i^m, so E in GPa, ν and UCS in MPa weigh
  alike and F = 0.0025 means a 5 % error on one response;
- "normalised": e_i = (y_i^c − y_i^m) / s_i with a scale s_i per response given by the user
  (e.g. the spread of the response over the design runs);
- "absolute": e_i = y_i^c − y_i^m, the source's plain sum, meaningless with mixed units;
and for each curve c given, RE_c = ‖y^C − y^M‖ / ‖y^M‖ on common abscissae.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from rockcal.errors import InputError
from rockcal.inverse.goodness import relative_error

FORMS = ("relative", "normalised", "absolute")


def _check(measured, weights, form, scales, curves):
    if form not in FORMS:
        raise InputError("form", f"must be one of {', '.join(FORMS)}, got {form!r}")
    if not measured and not curves:
        raise InputError("measured", "at least one measured response or curve is needed")
    for name, value in measured.items():
        if not np.isfinite(value):
            raise InputError(f"measured.{name}", f"must be a finite number, got {value}")
        if form == "relative" and value == 0:
            raise InputError(f"measured.{name}", "is 0: a relative error is undefined; use form='normalised'")
    known = set(measured) | set(curves or {})
    for name, w in (weights or {}).items():
        if name not in known:
            raise InputError(f"weights.{name}", f"no such response (known: {', '.join(sorted(known))})")
        if not (np.isfinite(w) and w >= 0):
            raise InputError(f"weights.{name}", f"must be a finite number >= 0, got {w}")
    if form == "normalised":
        for name in measured:
            s = (scales or {}).get(name)
            if s is None or not (np.isfinite(s) and s > 0):
                raise InputError(f"scales.{name}", f"form 'normalised' needs a scale > 0 per response, got {s}")


def misfit(computed: dict, measured: dict[str, float], *, weights: dict[str, float] | None = None,
           form: str = "relative", scales: dict[str, float] | None = None,
           curves: dict[str, tuple] | None = None):
    """F for computed responses (scalars, or arrays for many parameter sets at once).

    curves: {name: (x_measured, y_measured)}; computed[name] is then (x, y) of one run.
    """
    _check(measured, weights, form, scales, curves)
    weights = weights or {}
    total = 0.0
    for name, y_m in measured.items():
        if name not in computed:
            raise InputError("computed", f"the model gives no response {name!r}")
        y_c = np.asarray(computed[name], dtype=float)
        if form == "relative":
            e = (y_c - y_m) / y_m
        elif form == "normalised":
            e = (y_c - y_m) / scales[name]
        else:
            e = y_c - y_m
        total = total + weights.get(name, 1.0) * e ** 2
    for name, (x_m, y_m) in (curves or {}).items():
        if name not in computed:
            raise InputError("computed", f"the model gives no curve {name!r}")
        x_c, y_c = computed[name]
        total = total + weights.get(name, 1.0) * relative_error(x_c, y_c, x_m, y_m) ** 2
    return float(total) if np.ndim(total) == 0 else total


class Objective:
    """F(x) = misfit(model(x), measured, ...): the function the ant colony minimises.

    model maps parameters to {response: value}; if it also maps (n, d) rows to arrays (as
    RBFSurrogate.predict does), the objective is vectorised too.
    """

    def __init__(self, model: Callable, measured: dict[str, float], *, weights=None,
                 form: str = "relative", scales=None, curves=None):
        _check(measured, weights, form, scales, curves)
        self.model, self.measured = model, dict(measured)
        self.weights, self.form, self.scales, self.curves = weights, form, scales, curves

    def __call__(self, x):
        return misfit(self.model(x), self.measured, weights=self.weights, form=self.form,
                      scales=self.scales, curves=self.curves)

    def describe(self) -> str:
        """One line saying what F sums, for reports."""
        terms = {"relative": "((y_c - y_m) / y_m)^2", "normalised": "((y_c - y_m) / s)^2",
                 "absolute": "(y_c - y_m)^2"}[self.form]
        text = f"F = sum over {', '.join(self.measured)} of w * {terms}"
        if self.weights:
            text += "; w: " + ", ".join(f"{n} {self.weights.get(n, 1.0):g}" for n in self.measured)
        if self.curves:
            text += f" + sum over curves {', '.join(self.curves)} of w * RE^2"
        return text
