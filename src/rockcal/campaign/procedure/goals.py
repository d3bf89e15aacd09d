"""What a campaign calibrates against, gathered once from its [targets]: the target value of
each response, the tests that give them, their weights and the lab's spread, and the measured
curve (when a target section gives one)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rockcal.campaign.input.config import Campaign


@dataclass(frozen=True)
class Goals:
    targets: dict[str, float]  # response: target, of every test calibrated against
    tests: dict[str, list[str]]  # test: its target responses, in the order the tests run
    weights: dict[str, float]
    spread: dict[str, float | list[float]]
    curve: np.ndarray | None  # measured (strain, stress MPa), the curve fit's reference


def goals_of(campaign: Campaign) -> Goals:
    """The campaign's goals; a section's measured curve completes its targets (`measured`)."""
    sections = campaign.target_sections()
    measured = {test: section.measured() for test, section in sections.items()}
    curves = [section.measured_curve() for section in sections.values()]
    return Goals(
        targets={r: v for values in measured.values() for r, v in values.items()},
        tests={test: list(values) for test, values in measured.items()},
        weights={r: w for s in sections.values() for r, w in s.weights.items()},
        spread={r: list(v) if isinstance(v, tuple) else v for s in sections.values() for r, v in s.spread.items()},
        curve=next((c for c in curves if c is not None), None))


def goals_of_tests(goals: Goals, tests: list[str]) -> Goals:
    """The goals of some of the tests only (a verification's first stage)."""
    responses = [r for test in tests for r in goals.tests[test]]
    return Goals(targets={r: goals.targets[r] for r in responses}, tests={t: goals.tests[t] for t in tests},
                 weights={r: w for r, w in goals.weights.items() if r in responses},
                 spread={r: v for r, v in goals.spread.items() if r in responses}, curve=goals.curve)
