"""A specimen past the grain limit is refused before its genesis, in one line with the count,
the memory and the flag that allows it; the flag raises the limit."""

import sys

import pytest

from rockcal.cli.app import main
from rockcal.specimens.grain_limit import ENV, expected_grains
from rockcal.specimens.specimen import hexagonal, random_packing
from rockcal.errors import InputError


def run_cli(args, monkeypatch, capsys) -> tuple[int, str]:
    monkeypatch.setattr(sys, "argv", ["rockcal", *args])
    with pytest.raises(SystemExit) as exit:
        main()
    return exit.value.code, capsys.readouterr().err


@pytest.mark.parametrize("args, grains", [
    (["simulate", "ucs", "--rmin-mm", "0.001"], "808,735,216"),
    (["simulate", "ucs", "--rmin-mm", "0.02"], "2,021,838"),
    (["simulate", "bending", "--rmin-mm", "0.01"], "17,792,175"),
    (["simulate", "brazilian", "--rmin-mm", "0.005"], "16,174,704"),
    (["simulate", "ucs", "--packing", "hexagonal", "--rmin-mm", "0.01"], "14,433,757"),
])
def test_a_specimen_past_the_limit_is_one_line_before_genesis(args, grains, monkeypatch, capsys):
    monkeypatch.delenv(ENV, raising=False)
    code, stderr = run_cli(args, monkeypatch, capsys)
    assert code == 2 and len(stderr.splitlines()) == 1, stderr
    assert stderr.startswith("rockcal: error: specimen: a ") and f"about {grains}" in stderr
    assert "GiB of memory, past the limit of 1,000,000 grains" in stderr
    assert "allow it with rockcal --max-grains " in stderr


def test_the_flag_raises_the_limit(monkeypatch, capsys):
    monkeypatch.setenv(ENV, "1000000")  # the flag sets it: monkeypatch then removes it again
    code, stderr = run_cli(["--max-grains", "100", "simulate", "ucs", "--width-mm", "20", "--height-mm", "40",
                            "--rmin-mm", "0.4"], monkeypatch, capsys)
    assert code == 2 and "past the limit of 100 grains" in stderr and "--max-grains 809" in stderr
    monkeypatch.setenv(ENV, "10")
    with pytest.raises(InputError, match="^specimen: .* past the limit of 10 grains"):
        random_packing(20, 40, 0.4, seed=99, cache=False)
    with pytest.raises(InputError, match="^specimen: a hexagonal"):
        hexagonal(20, 40, 0.4)
    monkeypatch.setenv(ENV, "many")
    with pytest.raises(InputError, match=f"^{ENV}: must be a whole number"):
        random_packing(20, 40, 0.4, seed=99, cache=False)


def test_the_estimate_is_the_grain_clouds_count():
    """The full-size granite specimen: 50 x 100 mm, R_min 0.25 x 1.65, cloud porosity 0.09."""
    assert expected_grains(50, 100, 0.25, 1.65, 0.09) == pytest.approx(12938, rel=1e-3)


def test_a_negative_seed_is_refused(monkeypatch, capsys):
    code, stderr = run_cli(["simulate", "ucs", "--seed", "-1"], monkeypatch, capsys)
    assert code == 2 and len(stderr.splitlines()) == 1 and "--seed" in stderr, stderr
    with pytest.raises(InputError, match="^seed: must be a whole number >= 0"):
        random_packing(20, 40, 0.4, seed=-1)
