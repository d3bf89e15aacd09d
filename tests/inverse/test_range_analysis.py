"""Range analysis returns known factor effects exactly and refuses unusable designs."""

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.inverse import design, range_analysis

LEVELS = {"E_c": [15, 20, 25, 30], "kn_ks": [1.0, 1.67, 2.33, 3.0], "sigma_c": [20, 30, 40, 50],
          "tau_c": [50, 70, 90, 110], "mu": [0.3, 0.4, 0.5, 0.6]}
EFFECTS = {  # additive effect of each level on the response UCS, and on E
    "UCS": {"E_c": [0, 1, 3, 2], "kn_ks": [0, -2, -1, 0], "sigma_c": [0, 30, 55, 90],
            "tau_c": [0, 4, 5, 6], "mu": [0, 0, 0, 0]},
    "E": {"E_c": [0, 7, 14, 21], "kn_ks": [0, -1, -2, -4], "sigma_c": [0, 0, 0, 0.5],
          "tau_c": [0, 0, 0, 0], "mu": [0, 0.1, 0, 0]},
}


def runs_with_effects():
    runs = design("L16(4^5)", LEVELS)
    responses = {}
    for r, effects in EFFECTS.items():
        y = np.full(16, 100.0)
        for f, eff in effects.items():
            codes = np.searchsorted(LEVELS[f], runs[f])
            y += np.asarray(eff)[codes]
        responses[r] = y
    return runs, responses


def test_additive_effects_are_recovered_exactly():
    runs, responses = runs_with_effects()
    ra = range_analysis(runs, responses)
    for r, effects in EFFECTS.items():
        for f, eff in effects.items():
            e = ra.effects[r][f]
            # k_i = mean + effect_i - mean effect of the other factors' levels (all balanced)
            others = sum(np.mean(v) for g, v in effects.items() if g != f)
            np.testing.assert_allclose(e.k, 100 + np.asarray(eff) + others, rtol=1e-12)
            np.testing.assert_allclose(e.K, 4 * e.k, rtol=1e-12)
            assert e.R == pytest.approx(max(eff) - min(eff), abs=1e-9)
            np.testing.assert_array_equal(e.levels, sorted(LEVELS[f]))


def test_ranking_and_choice():
    ra = range_analysis(*runs_with_effects())
    assert ra.ranking("UCS")[:3] == ["sigma_c", "tau_c", "E_c"]
    assert ra.ranking("E")[:2] == ["E_c", "kn_ks"]
    assert ra.chosen() == ["E_c", "sigma_c"]
    assert ra.chosen(threshold=0.15) == ["E_c", "kn_ks", "sigma_c"]  # kn_ks: R 4 >= 0.15 * 21
    d = ra.to_dict()
    assert d["ranking"]["UCS"][0] == "sigma_c" and d["responses"]["E"]["E_c"]["R"] == pytest.approx(21)


def test_unbalanced_levels_refused():
    runs, responses = runs_with_effects()
    runs = {f: v[:-1] for f, v in runs.items()}
    responses = {r: v[:-1] for r, v in responses.items()}
    with pytest.raises(InputError, match="unbalanced"):
        range_analysis(runs, responses)


def test_too_few_runs_for_the_design():
    runs = {"A": np.repeat([1.0, 2, 3, 4], 2), "B": np.tile([1.0, 2, 3, 4], 2)}
    with pytest.raises(InputError, match="too few"):
        range_analysis(runs, {"y": np.arange(8.0)})


def test_nan_response_refused():
    runs, responses = runs_with_effects()
    responses["E"][3] = np.nan
    with pytest.raises(InputError, match="run 4"):
        range_analysis(runs, responses)
