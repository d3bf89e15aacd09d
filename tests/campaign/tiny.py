"""The campaign file of the tests' tiny UCS calibration: an 8 x 16 mm prism of R_min 0.4 mm
(seconds a run), E_c and sigma_c free."""


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
