"""Test helpers for campaigns: the campaign file of a tiny UCS calibration (an 8 x 16 mm prism
of R_min 0.4 mm: seconds a run, E_c and sigma_c free), and an executor with no DEM."""


def tiny_campaign(samples: int = 6, checks: int = 1, iterations: int = 20, max_dem_runs: int = 9,
                  seed: int = 1) -> str:
    return f"""
[targets.ucs]
E_GPa = 20.0
ucs_MPa = 40.0
[specimen]
rmin_mm = 0.4
width_mm = 8
height_mm = 16
seed = {seed}
[search]
bounds = {{ E_c = [10, 30], sigma_c = [20, 60] }}
[surrogate]
samples = {samples}
checks = {checks}
[optimizer]
iterations = {iterations}
[acceptance]
max_dem_runs = {max_dem_runs}
"""


class StandInExecutor:
    """An executor whose runs are `result(spec)` (a synthetic forward model); nothing stored."""

    class store:
        @staticmethod
        def get(spec):
            return None

    def result(self, spec):
        raise NotImplementedError

    def run(self, specs, progress=None):
        return [self.result(spec) for spec in specs]
