"""rockcal from Python: `rockcal.simulate` gives the numbers `rockcal simulate` prints, and
`rockcal.calibrate` the result `rockcal calibrate` writes, resumed without running again."""

import json
import sys

import pytest

import rockcal
from rockcal.cli.app import main
from rockcal.errors import InputError

SMALL = {"rmin_mm": 0.4, "width_mm": 8.0, "height_mm": 16.0}


def cli_json(args, monkeypatch, capsys) -> dict:
    monkeypatch.setattr(sys, "argv", ["rockcal", *args])
    with pytest.raises(SystemExit) as exit:
        main()
    assert exit.value.code == 0
    return json.loads(capsys.readouterr().out)


def test_simulate_gives_the_commands_numbers_to_the_bit(monkeypatch, capsys):
    result = rockcal.simulate("ucs", {"E_c": 25.0}, **SMALL).summary()
    printed = cli_json(["simulate", "ucs", "--set", "E_c=25", "--rmin-mm", "0.4", "--width-mm", "8",
                        "--height-mm", "16", "--json"], monkeypatch, capsys)
    for name in ("E_GPa", "nu", "ucs_MPa", "n_broken_tension"):
        assert result[name] == printed[name], name


@pytest.mark.parametrize("call, field", [
    (lambda: rockcal.simulate("ucs", rmin_m=0.4), "rmin_m"),
    (lambda: rockcal.simulate("ucs", {"E_cc": 20.0}, **SMALL), "E_cc"),
    (lambda: rockcal.simulate("ucs", width_mm=float("nan")), "width_mm"),
    (lambda: rockcal.simulate("triaxial"), "test"),
    (lambda: rockcal.calibrate(workers=-1), "workers"),
], ids=["setting", "parameter", "nan", "test", "workers"])
def test_bad_input_raises_an_input_error_naming_the_key(call, field):
    with pytest.raises(InputError) as error:
        call()
    assert error.value.field == field


@pytest.mark.slow
def test_calibrate_writes_the_record_and_resumes_without_running_again(tmp_path):
    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent / "campaign"))
    from tiny import tiny_campaign

    config = tmp_path / "tiny.toml"
    config.write_text(tiny_campaign(samples=4, iterations=10, max_dem_runs=5))
    first = rockcal.calibrate(config, out=tmp_path / "out", workers=1)
    record = json.loads((tmp_path / "out" / "record.json").read_text())
    assert record["identified"] == first.identified and first.executed_runs > 0
    again = rockcal.calibrate(config, out=tmp_path / "out", workers=1, resume=True)
    assert again.identified == first.identified and again.executed_runs == 0
