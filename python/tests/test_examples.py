"""The example scripts of examples/python/ run as a researcher would start them (no window)."""
import csv
import os
import pathlib
import re
import subprocess
import sys


SCRIPTS = pathlib.Path(__file__).parents[2] / "examples" / "python"


def run_script(name, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, SCRIPTS / name, *map(str, args)], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_example2_profile_plots_the_profile_and_the_sizes(tmp_path):
    printed = run_script("example2_profile.py", "--quick", "--threads", "1", "--out", tmp_path)
    assert (tmp_path / "example2_profile.png").stat().st_size > 10_000
    assert (tmp_path / "particles.csv").exists() and (tmp_path / "summary.json").exists()
    assert re.match(r"density 0\.\d{4};", printed)


def test_sweep_fa_carries_each_blend_to_its_whole_grading(tmp_path):
    printed = run_script("sweep_fa.py", "--fa", "30", "45", "--threads", "1", "--out", tmp_path, "--set",
                         'particles.fine.d_min="0.1 in"')
    rows = list(csv.DictReader(open(tmp_path / "sweep.csv")))
    assert [float(r["fa_percent"]) for r in rows] == [30.0, 45.0]
    for r in rows:  # the fines below the cut-off only add
        assert float(r["density_whole_grading"]) > float(r["density_at_cut"])
    assert (tmp_path / "sweep.png").stat().st_size > 10_000
    assert "densest: Fa" in printed


def test_lammps_dump_compare_measures_lammpss_bed_beside_aggpacks(tmp_path):
    printed = run_script("lammps_dump_compare.py", "--out", tmp_path, "--threads", "1")
    difference = float(re.search(r"LAMMPS - aggpack: ([-+]\d\.\d+)", printed).group(1))
    assert abs(difference) < 0.005, printed
    dump = next((tmp_path / "lammps" / "lammps").glob("**/*.dump"))
    again = run_script("lammps_dump_compare.py", "--dump", dump, "--cube", "0.03")
    assert "300 spheres" in again and "LAMMPS dump" in again
