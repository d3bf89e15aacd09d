"""`rockcal sensitivity analyze`: tables, JSON, the bar chart, and one-line errors with exit 2.

The error tests go through the `rockcal` entry point (python -m rockcal), which prints an
InputError as one line and exits 2; they need `sensitivity` registered in rockcal.cli.app.
"""

import csv
import json
import subprocess
import sys

import pytest
from typer.testing import CliRunner

from rockcal.cli import sensitivity
from rockcal.inverse import design

LEVELS = {"E_c": [15, 20, 25, 30], "kn_ks": [1.0, 1.67, 2.33, 3.0], "sigma_c": [20, 30, 40, 50],
          "tau_c": [50, 70, 90, 110], "mu": [0.3, 0.4, 0.5, 0.6]}
FACTORS = ",".join(LEVELS)


def write_results(path, rows=None, header=None):
    runs = design("L16(4^5)", LEVELS)
    table = {**runs, "E": 1.4 * runs["E_c"] + 2 * runs["kn_ks"], "nu": 0.1 + 0.05 * runs["kn_ks"],
             "UCS": 3 * runs["sigma_c"] + 0.1 * runs["tau_c"]}
    header = header or list(table)
    body = rows if rows is not None else [[table[k][i] for k in table] for i in range(16)]
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(header)
        writer.writerows(body)
    return path


def analyze(*args):
    return CliRunner().invoke(sensitivity.app, ["analyze", *map(str, args)])


@pytest.mark.slow
def test_json_output_and_bar_chart(tmp_path):
    path = write_results(tmp_path / "runs.csv")
    run = analyze(path, "--factors", FACTORS, "--responses", "E,nu,UCS", "--json", "--out", tmp_path / "out")
    assert run.exit_code == 0, run.output
    summary = json.loads(run.stdout)
    assert summary["chosen"] == ["E_c", "kn_ks", "sigma_c"]
    assert summary["ranking"]["UCS"][:2] == ["sigma_c", "tau_c"]
    ucs = summary["UCS"]["sigma_c"]
    assert ucs["R"] == pytest.approx(90) and ucs["k"] == pytest.approx([68, 98, 128, 158])
    assert ucs["K"] == pytest.approx([272, 392, 512, 632])
    assert (tmp_path / "out" / "range_analysis.png").stat().st_size > 1000
    assert json.loads((tmp_path / "out" / "range_analysis.json").read_text()) == summary


def test_tables(tmp_path):
    path = write_results(tmp_path / "runs.csv")
    run = analyze(path, "--factors", FACTORS, "--responses", "E,nu,UCS")
    assert run.exit_code == 0, run.output
    for text in ("Range analysis of UCS", "K4", "k4", "Parameters to invert: E_c, kn_ks, sigma_c"):
        assert text in run.stdout


@pytest.mark.parametrize("args, field", [
    (("--responses", "E,G"), "--responses"),
    (("--responses", "E", "--threshold", "2"), "--threshold"),
    (("--responses", "E_c"), "--responses"),
])
def test_bad_options_raise_input_error(tmp_path, args, field):
    from rockcal.errors import InputError
    run = analyze(write_results(tmp_path / "runs.csv"), "--factors", FACTORS, *args)
    assert isinstance(run.exception, InputError) and run.exception.field == field


def rockcal(*args):
    return subprocess.run([sys.executable, "-m", "rockcal", *map(str, args)], capture_output=True, text=True)


def bad_files(tmp_path):
    good = tmp_path / "good.csv"
    write_results(good)
    rows = list(csv.reader(open(good)))
    nan = write_results(tmp_path / "nan.csv", rows=[r[:-1] + ["nan"] for r in rows[1:]], header=rows[0])
    text = write_results(tmp_path / "text.csv", rows=[rows[1][:-1] + ["abc"]] + rows[2:], header=rows[0])
    short = write_results(tmp_path / "short.csv", rows=rows[1:9], header=rows[0])
    return good, nan, text, short


@pytest.mark.slow
@pytest.mark.parametrize("case, field", [
    ("missing-column", "--factors"),
    ("nan", "nan.csv"),
    ("text", "text.csv"),
    ("too-few-runs", "too few"),
    ("no-file", "none.csv"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, case, field):
    good, nan, text, short = bad_files(tmp_path)
    args = {"missing-column": (good, "--factors", "E_c,colour", "--responses", "E"),
            "nan": (nan, "--factors", FACTORS, "--responses", "E,nu,UCS"),
            "text": (text, "--factors", FACTORS, "--responses", "E,nu,UCS"),
            "too-few-runs": (short, "--factors", FACTORS, "--responses", "E"),
            "no-file": (tmp_path / "none.csv", "--factors", FACTORS, "--responses", "E")}[case]
    run = rockcal("sensitivity", "analyze", *args)
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rockcal: error:") and field in lines[0], run.stderr
    assert "Traceback" not in run.stderr
