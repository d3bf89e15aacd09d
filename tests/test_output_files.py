"""Files rockcal writes are written whole and never through a link (`rockcal.output_files`):
a symbolic link planted at an output's name in `simulate --out` or `sensitivity analyze --out`
is replaced and its target left alone; the temporary file of a killed write is removed by the
next write of its file, that of a write still running is kept."""

import os
import subprocess
import sys

from rockcal.output_files import HOST, atomic_path, write_atomic
import test_cli

rockcal = test_cli.rockcal  # the fixture: `rockcal ARGS` in this process


def plant_links(folder, names, victim):
    folder.mkdir()
    victim.write_text("precious")
    for name in names:
        (folder / name).symlink_to(victim)


def assert_written_beside(folder, names, victim):
    assert victim.read_text() == "precious"
    for name in names:
        path = folder / name
        assert not path.is_symlink() and path.is_file() and path.stat().st_size > 0, name
    assert not [p.name for p in folder.iterdir() if ".tmp" in p.name]


def test_simulate_replaces_a_link_at_each_output(tmp_path, rockcal):
    out, victim = tmp_path / "out", tmp_path / "victim.txt"
    names = ["ucs_curve.csv", "ucs_summary.json", "ucs_cracks.png", "ucs_curve.png"]
    plant_links(out, names, victim)
    run = rockcal("simulate", "ucs", "--width-mm", "6", "--height-mm", "12", "--rmin-mm", "0.4",
                  "--json", "--out", str(out))
    assert run.returncode == 0, run.stderr
    assert_written_beside(out, names, victim)
    assert (out / "ucs_curve.csv").read_text().startswith("axial_strain,")


def test_sensitivity_analyze_replaces_a_link_at_each_output(tmp_path, rockcal):
    out, victim = tmp_path / "out", tmp_path / "victim.txt"
    names = ["range_analysis.json", "range_analysis.png"]
    plant_links(out, names, victim)
    runs = tmp_path / "runs.csv"
    runs.write_text("a,b,E\n1,1,10\n1,2,11\n2,1,14\n2,2,15\n")
    run = rockcal("sensitivity", "analyze", str(runs), "--factors", "a,b", "--responses", "E", "--json",
                  "--out", str(out))
    assert run.returncode == 0, run.stderr
    assert_written_beside(out, names, victim)
    assert (out / "range_analysis.png").read_bytes().startswith(b"\x89PNG")


def killed_write(path) -> str:
    """Begin writing `path` in another process and kill it half way: its temporary file's name."""
    code = ("import os, sys\nfrom rockcal.output_files import atomic_path\n"
            "with atomic_path(sys.argv[1]) as tmp:\n"
            "    tmp.write_bytes(b'half')\n    print(tmp.name, flush=True)\n    os._exit(9)\n")
    run = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True, timeout=60)
    return run.stdout.strip()


def test_a_killed_writes_temporary_file_goes_with_the_next_write(tmp_path):
    target = tmp_path / "ucs_cracks.png"
    left = killed_write(target)
    assert (tmp_path / left).read_bytes() == b"half"
    pid = int(left.split(".")[3])
    others = [f".ucs_cracks.png.{pid}.{HOST}.notes",  # not our pattern
              f".ucs_curve.png.{pid}.{HOST}.abc123_x.tmp.png",  # another file's
              f"ucs_cracks.png.{pid}.{HOST}.abc123_x.tmp.png",  # not hidden
              f".ucs_cracks.png.{pid}.{'0' * 8 if HOST != '0' * 8 else '1' * 8}.abc123_x.tmp.png"]  # another machine's
    for name in others:
        (tmp_path / name).write_text("keep")
    write_atomic(target, b"png")
    assert not (tmp_path / left).exists()
    assert target.read_bytes() == b"png"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(others + [target.name])


def test_a_running_writes_temporary_file_is_kept(tmp_path):
    target = tmp_path / "report.html"
    with atomic_path(target) as tmp:  # this process's write, still running
        tmp.write_text("<p>outer</p>")
        write_atomic(target, "<p>inner</p>")
        assert tmp.read_text() == "<p>outer</p>" and f".{os.getpid()}." in tmp.name
    assert target.read_text() == "<p>outer</p>"
    assert [p.name for p in tmp_path.iterdir()] == ["report.html"]
