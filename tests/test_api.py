"""rockcal from Python: `rockcal.simulate` gives the numbers `rockcal simulate` prints, and
`rockcal.calibrate` the result `rockcal calibrate` writes, resumed without running again, from a
file or a dict of its tables, with its figures shown in a notebook and its export."""

import json
import sys
import tomllib
from pathlib import Path

import pytest

import rockcal
from rockcal.cli.app import main
from rockcal.errors import InputError

SMALL = {"rmin_mm": 0.4, "width_mm": 8.0, "height_mm": 16.0}
sys.path.insert(0, str(Path(__file__).parent / "campaign"))
from tiny import tiny_campaign  # noqa: E402


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


def test_a_test_named_as_the_command_line_names_it_runs_the_same():
    """"direct-tension" (the command's spelling) is the test "direct_tension", to the bit; its
    responses are plain Python numbers, as a notebook shows them."""
    spelt, named = (rockcal.simulate(test, {"E_c": 25.0}, **SMALL).summary()
                    for test in ("direct-tension", "direct_tension"))
    assert spelt.pop("wall_s") > 0 and named.pop("wall_s") > 0
    assert spelt == named
    assert all(type(value) in (int, float, str, bool) for value in spelt.values()), spelt


@pytest.mark.parametrize("call, field", [
    (lambda: rockcal.simulate("ucs", rmin_m=0.4), "rmin_m"),
    (lambda: rockcal.simulate("ucs", {"E_cc": 20.0}, **SMALL), "E_cc"),
    (lambda: rockcal.simulate("ucs", width_mm=float("nan")), "width_mm"),
    (lambda: rockcal.simulate("triaxial"), "test"),
    (lambda: rockcal.calibrate(workers=-1), "workers"),
    (lambda: rockcal.calibrate({"targets": {"ucs": {"E_GPaa": 20.0}}}), "targets.ucs.E_GPaa"),
    (lambda: rockcal.calibrate({"specimen": {"rmin_mm": None}}), "specimen.rmin_mm"),
    (lambda: rockcal.calibrate("no-such-rock.toml"), "campaign"),
    (lambda: rockcal.calibrate([1.0]), "campaign"),
], ids=["setting", "parameter", "nan", "test", "workers", "dict key", "dict value", "no file", "not a dict"])
def test_bad_input_raises_an_input_error_naming_the_key(call, field):
    with pytest.raises(InputError) as error:
        call()
    assert error.value.field == field


@pytest.mark.slow
def test_calibrate_writes_the_record_and_resumes_without_running_again(tmp_path):
    config = tmp_path / "tiny.toml"
    config.write_text(tiny_campaign(samples=4, iterations=10, max_dem_runs=5))
    first = rockcal.calibrate(config, out=tmp_path / "out", workers=1)
    record = json.loads((tmp_path / "out" / "record.json").read_text())
    assert record["identified"] == first.identified and first.executed_runs > 0
    again = rockcal.calibrate(config, out=tmp_path / "out", workers=1, resume=True)
    assert again.identified == first.identified and again.executed_runs == 0


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """The tiny campaign calibrated from its file and from a dict of its tables."""
    folder = tmp_path_factory.mktemp("api")
    text = tiny_campaign(samples=4, iterations=10, max_dem_runs=5)
    (folder / "tiny.toml").write_text(text)
    from_file = rockcal.calibrate(folder / "tiny.toml", out=folder / "file", workers=1)
    from_dict = rockcal.calibrate(tomllib.loads(text), out=folder / "dict", workers=1)
    return from_file, from_dict


@pytest.mark.slow
def test_a_dict_calibrates_as_its_file(tiny):
    from_file, from_dict = tiny
    assert from_dict.identified == from_file.identified and from_dict.verified == from_file.verified
    assert json.loads((from_dict.out / "record.json").read_text())["identified"] == from_dict.identified


@pytest.mark.slow
def test_a_store_in_out_is_named_as_the_call_names_it(tiny):
    """A call's error speaks of its arguments, not of the command's options."""
    from_file = tiny[0]
    with pytest.raises(InputError) as error:
        rockcal.calibrate(from_file.out.parent / "tiny.toml", out=from_file.out, workers=1)
    assert error.value.field == "out" and "add resume=True" in error.value.problem
    assert "--" not in error.value.problem


@pytest.mark.slow
def test_the_figures_shown_are_the_pngs_written(tiny):
    calibration = tiny[1]
    written = {path.stem for path in calibration.out.glob("*.png")}
    assert written and set(calibration.figures) == written
    for name, figure in calibration.figures.items():
        png = figure._repr_png_()
        assert png.startswith(b"\x89PNG") and png == (calibration.out / f"{name}.png").read_bytes()


@pytest.mark.slow
def test_the_summary_shown_holds_the_identified_parameters(tiny):
    calibration = tiny[1]
    shown = calibration._repr_html_()
    for name, value in calibration.identified.items():
        assert f"<td>{name}</td><td>{value:.4g}</td>" in shown
    assert shown.count("data:image/png;base64,") == len(calibration.figures)


@pytest.mark.slow
@pytest.mark.parametrize("format", ["pfc-fish", "json"])
def test_export_writes_what_the_command_writes(tiny, cli, tmp_path, format):
    calibration = tiny[1]
    ran = cli("export", calibration.out, "--format", format, "--to", tmp_path / "by_cli")
    assert ran.returncode == 0
    path = calibration.export(format, to=tmp_path / "by_api")
    assert path.read_bytes() == (tmp_path / "by_cli").read_bytes()
    if format == "pfc-fish":
        assert calibration.export() == calibration.out / "mpParams.p2dat"
        assert (calibration.out / "mpParams.p2dat").read_bytes() == path.read_bytes()
