"""A run that starts from a bed held in Python (particles.from = "-", aggpack.run(..., bed=...))
against the same run reading that bed from a file."""
import json

import numpy as np
import pytest

import aggpack
from conftest import EXAMPLES, cli


def settle_scenario(particles_from, **particles):
    """Example 1's container and beads, the bed given, settled for 0.05 s of DEM."""
    return {
        "title": "settle a given bed",
        "seed": 3,
        "container": {"side": "12 in", "height": "24 in", "sides": "walls"},
        "particles": {"from": str(particles_from), **particles},
        "material": {"density": 1050, "friction_particle": 0.17, "friction_wall": 0.17, "youngs_modulus": 3e9,
                     "poisson_ratio": 0.3, "wall_youngs_modulus": 3e9, "wall_poisson_ratio": 0.3,
                     "restitution": 0.5},
        "dynamics": {"time_step": 1e-5, "max_time": 0.05},
        "analysis": {"box_sides": ["6 in"]},
    }


@pytest.fixture(scope="module")
def deposited(tmp_path_factory):
    """Example 1's drop-and-roll bed, written by the CLI."""
    out = tmp_path_factory.mktemp("deposited") / "example1"
    cli("run", EXAMPLES / "example1.toml", "--quiet", "--stop-after", "deposition", "--out", out)
    return out / "particles.csv"


@pytest.fixture(scope="module")
def settled_from_file(tmp_path_factory, deposited):
    """The CLI settling the deposited bed read from its file: what a run from the arrays must give."""
    folder = tmp_path_factory.mktemp("from_file")
    scenario = folder / "settle.toml"
    scenario.write_text(aggpack.toml_text(settle_scenario(deposited)))
    cli("run", scenario, "--quiet", "--threads", "1", "--out", folder / "out")
    return folder / "out"


def test_a_run_from_arrays_gives_the_bytes_of_the_run_from_their_file(tmp_path, deposited, settled_from_file):
    table = np.loadtxt(deposited, delimiter=",", skiprows=1)
    bed = aggpack.Bed.from_arrays(table[:, 1:4], table[:, 4])
    scenario = aggpack.Scenario.from_dict(settle_scenario("-"))
    scenario.check(bed=bed)
    report = aggpack.run(scenario, bed=bed, threads=2)
    assert report.simulated_time == pytest.approx(0.05, rel=1e-9)
    assert np.any(report.bed.positions != bed.positions)  # the DEM moved it; the given bed is untouched
    assert np.array_equal(bed.positions, table[:, 1:4])
    aggpack.write_outputs(report, tmp_path / "py")
    for name in ("particles.csv", "timeseries.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (settled_from_file / name).read_bytes(), name
    summary = report.summary()
    expected = json.loads((settled_from_file / "summary.json").read_text())
    assert summary["density"] == expected["density"]
    assert summary["input"]["format"] == f"given by the caller ({len(bed)} spheres)"
    assert any("given by the caller" in note for note in report.notes)
    assert summary["input"]["file"] == "-"
    # Another run's bed is a starting bed too, its velocities with it (a file's spheres start at rest).
    short = settle_scenario("-")
    short["dynamics"]["max_time"] = 1e-4
    again = aggpack.run(aggpack.Scenario.from_dict(short), bed=report.bed, threads=1)
    assert again.summary()["input"]["format"] == summary["input"]["format"]
    at_rest = aggpack.run(aggpack.Scenario.from_dict(short), threads=1,
                          bed=aggpack.Bed.from_arrays(report.bed.positions, report.bed.radii))
    assert np.any(report.bed.velocities != 0)
    assert not np.array_equal(again.bed.positions, at_rest.bed.positions)


def test_the_given_bed_takes_particles_material_or_its_own(deposited):
    table = np.loadtxt(deposited, delimiter=",", skiprows=1)
    two = settle_scenario("-", material="glass")
    two["materials"] = {"glass": {"density": 2500}}
    two["dynamics"]["max_time"] = 1e-4
    scenario = aggpack.Scenario.from_dict(two)
    report = aggpack.run(scenario, bed=aggpack.Bed.from_arrays(table[:, 1:4], table[:, 4]))
    glass = report.bed.materials[0]
    assert glass != 0 and np.all(report.bed.materials == glass)
    volume = 4.0 / 3.0 * np.pi * table[:, 4] ** 3
    assert np.allclose(report.bed.masses, 2500 * volume, rtol=1e-12)
    # Each sphere of its own material: half the beads glass, particles.material left out.
    own = np.where(np.arange(len(table)) % 2 == 0, 0, glass)
    mixed = aggpack.Bed.from_arrays(table[:, 1:4], table[:, 4], materials=own)
    with pytest.raises(aggpack.InputError, match="gives each sphere's material: expected no particles.material"):
        aggpack.run(scenario, bed=mixed)
    del two["particles"]["material"]
    report = aggpack.run(aggpack.Scenario.from_dict(two), bed=mixed)
    assert np.array_equal(report.bed.materials, own)
    assert np.allclose(report.bed.masses, np.where(own == 0, 1050, 2500) * volume, rtol=1e-12)


def test_a_files_material_column_names_the_materials_of_a_run_from_it(tmp_path, deposited):
    table = np.loadtxt(deposited, delimiter=",", skiprows=1)
    names = np.where(np.arange(len(table)) % 3 == 0, "glass", "default")
    with open(tmp_path / "named.csv", "w") as f:
        f.write("id,x,y,z,r,material\n")
        for row, name in zip(table, names):
            f.write(",".join(f"{v:.17g}" for v in row[1:5]).join([f"{int(row[0])},", f",{name}\n"]))
    bed = aggpack.read_bed(tmp_path / "named.csv")
    assert bed.material_names == list(names)
    two = settle_scenario("-")
    two["materials"] = {"glass": {"density": 2500}}
    two["dynamics"]["max_time"] = 1e-4
    report = aggpack.run(aggpack.Scenario.from_dict(two), bed=bed)
    from_file = settle_scenario(tmp_path / "named.csv")
    from_file["materials"] = two["materials"]
    from_file["dynamics"]["max_time"] = 1e-4
    expected = aggpack.run(aggpack.Scenario.from_dict(from_file))
    assert np.array_equal(report.bed.materials, expected.bed.materials)
    assert np.array_equal(report.bed.positions, expected.bed.positions)
    assert len(set(report.bed.materials)) == 2
    two["materials"] = {"steel": {"density": 7800}}
    with pytest.raises(aggpack.InputError, match='is of material "glass", which the scenario does not name'):
        aggpack.run(aggpack.Scenario.from_dict(two), bed=bed)


def test_a_bed_that_is_not_there_or_not_wanted_is_refused(tmp_path, deposited):
    table = np.loadtxt(deposited, delimiter=",", skiprows=1)
    bed = aggpack.Bed.from_arrays(table[:, 1:4], table[:, 4])
    given = aggpack.Scenario.from_dict(settle_scenario("-"))
    # The CLI has no bed to give: the same message as Python's run without one, exit 2.
    (tmp_path / "given.toml").write_text(given.text)
    code, printed = cli("run", tmp_path / "given.toml", "--quiet", "--out", tmp_path / "cli", check=False)
    assert code == 2
    with pytest.raises(aggpack.InputError, match=r'particles.from = "-" takes the starting bed from the library') as e:
        aggpack.run(aggpack.Scenario.from_file(tmp_path / "given.toml"))
    assert str(e.value) in printed
    assert not (tmp_path / "cli").exists()
    with pytest.raises(aggpack.InputError, match='a starting bed was given, and the scenario\'s particles are read'):
        aggpack.run(aggpack.Scenario.from_dict(settle_scenario(deposited)), bed=bed)
    with pytest.raises(aggpack.InputError, match="bed= with out=.*aggpack.write_outputs"):
        aggpack.run(given, bed=bed, out=tmp_path / "py")
    assert not (tmp_path / "py").exists()
    with pytest.raises(aggpack.InputError, match="sphere 1 of the starting bed given .* is of material 7, and the "
                                                 "scenario has 1"):
        aggpack.run(given, bed=aggpack.Bed.from_arrays(table[:, 1:4], table[:, 4], materials=[0, 7] + [0] * (len(table) - 2)))
    with pytest.raises(aggpack.InputError, match="materials: entry 0 is 1.5; expected a material's index"):
        aggpack.Bed.from_arrays(table[:2, 1:4], table[:2, 4], materials=[1.5, 0])
    # Checked as a file would be: a sphere outside the container, two spheres one inside the other.
    outside = table[:, 1:4].copy()
    outside[5, 0] = 2.0
    with pytest.raises(aggpack.InputError, match="the starting bed given"):
        given.check(bed=aggpack.Bed.from_arrays(outside, table[:, 4]))
    coincident = table[:, 1:4].copy()
    coincident[1] = coincident[0]
    with pytest.raises(aggpack.InputError, match="the starting bed given"):
        aggpack.run(given, bed=aggpack.Bed.from_arrays(coincident, table[:, 4]))
    with pytest.raises(aggpack.InputError, match="a bed given by the caller"):
        aggpack.Scenario.from_dict(settle_scenario("-", length_unit="mm"))
    with pytest.raises(aggpack.InputError, match='takes the starting bed from the library'):
        given.check()
    # The commands that make their bed from the scenario alone refuse it, naming why.
    code, printed = cli("predict", tmp_path / "given.toml", check=False)
    assert code == 2 and 'particles.from = "-": the bed is given by the library\'s caller' in printed
    code, printed = cli("export-lammps", tmp_path / "given.toml", "--out", tmp_path / "deck", check=False)
    assert code == 2 and "export-lammps makes the bed from the scenario" in printed
    code, printed = cli("calibrate", tmp_path / "given.toml", "--out", tmp_path / "c.json", check=False)
    assert code == 2 and 'are a bed given by the caller (particles.from = "-")' in printed
    code, printed = cli("calibrate", tmp_path / "given.toml", "--dem", "--measured", "0.6", "--out",
                        tmp_path / "c.json", check=False)
    assert code == 2 and "calibrate --dem runs the scenario again and again from its file" in printed

