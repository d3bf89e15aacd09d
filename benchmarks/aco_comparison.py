"""Compare the ant colony methods with differential evolution (and mealpy's ACOR).

Run by hand:  python benchmarks/aco_comparison.py [--seeds 15] [--budget 10000]
For each problem and method, over seeds: success rate (best objective reaches the target
within the evaluation budget) and evaluations to reach the target (median over the
successful seeds). Prints a markdown table (the one in docs/concepts/inverse-procedure.md).

mealpy's ACOR is included when MEALPY_PYTHON names a Python interpreter with mealpy
installed (mealpy 3 pins numpy < 2, so it cannot share rockcal's environment); that
interpreter runs this file with --mealpy-worker and needs only numpy and mealpy.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

# ---------------------------------------------------------------- test problems (numpy only)


def rosenbrock(X):
    return np.sum(100.0 * (X[:, 1:] - X[:, :-1] ** 2) ** 2 + (1.0 - X[:, :-1]) ** 2, axis=1)


def branin(X):
    x, y = X[:, 0], X[:, 1]
    b, c, r, s, t = 5.1 / (4 * np.pi ** 2), 5 / np.pi, 6.0, 10.0, 1 / (8 * np.pi)
    return (y - b * x ** 2 + c * x - r) ** 2 + s * (1 - t) * np.cos(x) + s


def ackley(X):
    d = X.shape[1]
    return (-20 * np.exp(-0.2 * np.sqrt(np.sum(X ** 2, axis=1) / d))
            - np.exp(np.sum(np.cos(2 * np.pi * X), axis=1) / d) + 20 + np.e)


def rock_responses(X):
    """Smooth, nonlinear stand-ins for E (GPa), ν, UCS (MPa), and two weaker responses, of
    (E_c GPa, kn/ks, σ_c MPa, τ_c MPa, μ); only the first d parameters vary."""
    full = np.tile([25.0, 2.0, 40.0, 90.0, 0.5], (len(X), 1))
    full[:, :X.shape[1]] = X
    Ec, kr, sc, tc, mu = full.T
    E = 1.55 * Ec * (1.0 - 0.09 * (kr - 1.0)) * (1.0 + 0.002 * sc)
    nu = 0.06 + 0.11 * kr ** 0.7 / (1.0 + 0.004 * Ec)
    ucs = 2.9 * sc ** 1.08 * (1.0 + 0.15 * np.tanh(tc / 60.0 - 1.0)) * (1.0 - 0.05 * (kr - 2.0))
    strain = 0.0023 * ucs / E * (1.0 + 0.3 * mu)
    ratio = (tc / sc) ** 0.5 * (1.0 + 0.4 * mu ** 2)
    return np.column_stack([E, nu, ucs, strain, ratio])


def make_ssre(truth):
    """Sum of squared relative errors against the responses at `truth` (minimum 0 there)."""
    truth = np.asarray(truth, dtype=float)
    n_resp = max(3, len(truth))
    target = rock_responses(truth[None])[0, :n_resp]

    def ssre(X):
        return np.sum(((rock_responses(X)[:, :n_resp] - target) / target) ** 2, axis=1)
    return ssre


ROCK_BOUNDS = [(20, 30), (1, 3), (30, 50), (50, 110), (0.3, 0.6)]

# name -> (function, bounds, minimum, tolerance above the minimum)
PROBLEMS = {
    "Rosenbrock 2-D": (rosenbrock, [(-2.048, 2.048)] * 2, 0.0, 1e-4),
    "Rosenbrock 4-D": (rosenbrock, [(-2.048, 2.048)] * 4, 0.0, 1e-3),
    "Branin 2-D": (branin, [(-5, 10), (0, 15)], 0.397887357729739, 1e-4),
    "Ackley 3-D": (ackley, [(-32.768, 32.768)] * 3, 0.0, 1e-3),
    "Ackley 5-D": (ackley, [(-32.768, 32.768)] * 5, 0.0, 1e-3),
    "SSRE 3-D (E, nu, UCS)": (make_ssre([25.3, 1.9, 41.7]), ROCK_BOUNDS[:3], 0.0, 1e-6),
    "SSRE 5-D (5 responses)": (make_ssre([25.3, 1.9, 41.7, 77.0, 0.42]), ROCK_BOUNDS, 0.0, 1e-6),
}


class Counter:
    """Counts evaluations (rows) and remembers when the best first reached the target."""

    def __init__(self, fun, target):
        self.fun, self.target, self.nfev, self.hit, self.best = fun, target, 0, None, np.inf

    def __call__(self, X):
        X = np.atleast_2d(X)
        f = self.fun(X)
        for value in f:
            self.nfev += 1
            self.best = min(self.best, value)
            if self.hit is None and value <= self.target:
                self.hit = self.nfev
        return f

    def one(self, x):
        return float(self(np.asarray(x)[None])[0])


# ---------------------------------------------------------------- methods


def run_ant_system(counter, bounds, seed, budget):
    from rockcal.inverse import ant_colony
    ant_colony(counter, bounds, method="ant-system", iterations=budget // 50, seed=seed,
               vectorized=True, target=counter.target)


def run_acor(counter, bounds, seed, budget):
    from rockcal.inverse import ant_colony
    ant_colony(counter, bounds, method="acor", iterations=(budget - 30) // 10, seed=seed,
               vectorized=True, target=counter.target)


def run_de(counter, bounds, seed, budget):
    from scipy.optimize import differential_evolution
    d = len(bounds)
    differential_evolution(counter.one, bounds, seed=seed, maxiter=budget // (15 * d) - 1, tol=0,
                           polish=False, callback=lambda *a, **k: counter.hit is not None)


METHODS = {"ant-system": run_ant_system, "acor": run_acor, "differential_evolution": run_de}


def mealpy_worker(problem: str, seeds: int, budget: int) -> list:
    """Runs inside MEALPY_PYTHON: mealpy's OriginalACOR (pop 30, sample 10 ≈ our acor)."""
    from mealpy import FloatVar
    from mealpy.swarm_based.ACOR import OriginalACOR
    fun, bounds, fmin, tol = PROBLEMS[problem]

    class Reached(Exception):
        pass

    def stop_at_target(x):  # mealpy has no target stop: end its run once the target is hit
        value = counter.one(x)
        if counter.hit is not None:
            raise Reached
        return value

    out = []
    for seed in range(seeds):
        counter = Counter(fun, fmin + tol)
        spec = {"obj_func": stop_at_target, "minmax": "min", "log_to": None,
                "bounds": FloatVar(lb=[b[0] for b in bounds], ub=[b[1] for b in bounds])}
        model = OriginalACOR(epoch=10_000, pop_size=30, sample_count=10, intent_factor=0.5, zeta=1.0)
        try:
            model.solve(spec, seed=seed, termination={"max_fe": budget})
        except Reached:
            pass
        out.append(counter.hit)
    return out


def run_mealpy(python, problem, seeds, budget):
    here = os.path.abspath(__file__)
    run = subprocess.run([python, here, "--mealpy-worker", problem, "--seeds", str(seeds),
                          "--budget", str(budget)], capture_output=True, text=True)
    if run.returncode != 0:
        print(f"mealpy failed on {problem}: {run.stderr.strip().splitlines()[-1:]}", file=sys.stderr)
        return None
    return json.loads(run.stdout.strip().splitlines()[-1])


def summarise(hits, seeds):
    ok = [h for h in hits if h is not None]
    rate = f"{len(ok)}/{seeds}"
    evals = f"{int(np.median(ok))}" if ok else "–"
    return f"{rate}, {evals}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=15)
    parser.add_argument("--budget", type=int, default=10_000)
    parser.add_argument("--mealpy-worker", metavar="PROBLEM")
    a = parser.parse_args()
    if a.mealpy_worker:
        print(json.dumps(mealpy_worker(a.mealpy_worker, a.seeds, a.budget)))
        return
    python = os.environ.get("MEALPY_PYTHON")
    names = list(METHODS) + (["mealpy ACOR"] if python else [])
    print(f"budget {a.budget} evaluations, {a.seeds} seeds; cells: successes, median evaluations to target\n")
    print("| problem (target f − f* ≤) | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    t0 = time.time()
    for problem, (fun, bounds, fmin, tol) in PROBLEMS.items():
        cells = []
        for run in METHODS.values():
            hits = []
            for seed in range(a.seeds):
                counter = Counter(fun, fmin + tol)
                run(counter, bounds, seed, a.budget)
                hits.append(counter.hit)
            cells.append(summarise(hits, a.seeds))
        if python:
            hits = run_mealpy(python, problem, a.seeds, a.budget)
            cells.append("failed" if hits is None else summarise(hits, a.seeds))
        print(f"| {problem} ({tol:g}) | " + " | ".join(cells) + " |", flush=True)
    print(f"\n({time.time() - t0:.0f} s)")


if __name__ == "__main__":
    main()
