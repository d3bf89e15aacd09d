"""A multi-fidelity surrogate: a surrogate of cheap low-fidelity runs, corrected by fewer
high-fidelity runs.

Kennedy & O'Hagan's autoregressive form (2000; the basis of co-kriging) with RBFs in place of
Gaussian processes: the high-fidelity response is ŷ_h(x) = ρ ŷ_l(x) + δ(x), with ŷ_l the
surrogate of the low-fidelity runs, ρ a constant per response (least squares over the
high-fidelity runs) and δ a Gaussian RBF of what is left at those runs, with a constant tail.
A coarse DEM specimen's responses follow the fine one's closely but not exactly (a coarser
packing is stiffer or stronger by a nearly constant factor): ρ takes that factor, and δ, which
varies slowly, needs few fine runs.
"""

from __future__ import annotations

import numpy as np

from rockcal.inverse.surrogate import RBFSurrogate


class CorrectedSurrogate:
    """ŷ_h = ρ ŷ_l + δ for each response, from the low-fidelity surrogate `low` and the
    high-fidelity runs x (n, d) with their `responses` (a NaN: not measured at that run, left
    out of that response's ρ and δ); the same interface as RBFSurrogate."""

    def __init__(self, low: RBFSurrogate, x, responses: dict[str, np.ndarray], bounds):
        x = np.atleast_2d(np.asarray(x, float))
        at_runs = low.predict(x)
        self.low = low
        self.names = tuple(responses)
        self.rho, self.delta, self.epsilon = {}, {}, {}
        for r in self.names:
            high = np.asarray(responses[r], float)
            measured = ~np.isnan(high)
            self.rho[r] = _scale(at_runs[r][measured], high[measured])
            left = high[measured] - self.rho[r] * at_runs[r][measured]
            # one high-fidelity run fixes ρ alone: nothing is left to interpolate
            self.delta[r] = RBFSurrogate(x[measured], {r: left}, bounds, degree=0) if measured.sum() > 1 else None
            self.epsilon[r] = (low if self.delta[r] is None else self.delta[r]).epsilon[r]

    def predict(self, x) -> dict:
        """{response: prediction} at x, (d,) for one point (scalars out) or (m, d)."""
        low = self.low.predict(x)
        return {r: self.rho[r] * low[r] + (self.delta[r].predict(x)[r] if self.delta[r] else 0.0)
                for r in self.names}

    validate = RBFSurrogate.validate


def _scale(low: np.ndarray, high: np.ndarray) -> float:
    """ρ minimising Σ (high - ρ low)²; 1 when the low values are all zero."""
    norm = float(low @ low)
    return float(low @ high) / norm if norm > 0 else 1.0
