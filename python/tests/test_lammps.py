"""The LAMMPS bridge from Python: the decks and imports `aggpack export-lammps` and `import-lammps` make."""
import filecmp

import pytest

import aggpack
from conftest import cli

SMALL_BED = ('title = "LAMMPS from Python"\nseed = 5\n[container]\nside = 0.06\nheight = 0.3\n[particles]\n'
             'diameter = 0.01\ncount = 300\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n'
             '[deposition]\n[dynamics]\nmax_time = 1.0\n[analysis]\nbox_sides = [0.03]\n')


def same_tree(a, b):
    compared = filecmp.dircmp(a, b)
    return not compared.left_only and not compared.right_only and not compared.diff_files and all(
        same_tree(a / d, b / d) for d in compared.common_dirs)


def test_export_and_import_are_the_clis(tmp_path):
    scenario = tmp_path / "small.toml"
    scenario.write_text(SMALL_BED)
    step = aggpack.export_lammps(scenario, tmp_path / "py_deck", set=["seed=6"])
    cli("export-lammps", scenario, "--set", "seed=6", "--out", tmp_path / "cli_deck")
    assert "settle" in step
    assert same_tree(tmp_path / "py_deck", tmp_path / "cli_deck")
    # A Scenario read from its file takes its overrides and its seed along.
    aggpack.export_lammps(aggpack.Scenario.from_file(scenario, set=["seed=6"]), tmp_path / "py_deck2")
    assert same_tree(tmp_path / "py_deck2", tmp_path / "cli_deck")
    aggpack.export_lammps(aggpack.Scenario.from_file(scenario, seed=6), tmp_path / "py_deck3")
    assert same_tree(tmp_path / "py_deck3", tmp_path / "cli_deck")
    aggpack.export_lammps(aggpack.Scenario.from_file(scenario), tmp_path / "seed_5")
    assert not same_tree(tmp_path / "seed_5", tmp_path / "cli_deck")  # the seed makes another bed

    # A bed settled by LAMMPS within a run, its dump imported as the CLI imports it.
    aggpack.run(aggpack.Scenario.from_file(scenario, set=['dynamics.engine="lammps"']), out=tmp_path / "lammps_run")
    dump = next((tmp_path / "lammps_run" / "lammps").glob("**/*.dump"))
    report = aggpack.import_lammps(dump, scenario=scenario, out=tmp_path / "py_import")
    cli("import-lammps", dump, "--scenario", scenario, "--quiet", "--out", tmp_path / "cli_import")
    assert (tmp_path / "py_import" / "particles.csv").read_bytes() == (
        tmp_path / "cli_import" / "particles.csv").read_bytes()
    assert report.output_directory == tmp_path / "py_import"
    assert len(report.bed) == 300 and 0.5 < report.density < 0.7


def test_a_scenario_of_no_file_is_refused_saying_what_to_do(tmp_path):
    from_text = aggpack.Scenario.from_toml(SMALL_BED, name=tmp_path / "nowhere.toml")
    with pytest.raises(aggpack.InputError, match="write scenario.text to a file and give its path"):
        aggpack.export_lammps(from_text, tmp_path / "deck")
    assert not (tmp_path / "deck").exists()
