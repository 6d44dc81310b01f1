"""aggpack.specimen against `aggpack specimen`: the same files and specimen.json, from a run's folder
or from a Bed in memory."""
import json

import numpy as np
import pytest

import aggpack
from conftest import EXAMPLES, cli


@pytest.fixture(scope="module")
def deposited(tmp_path_factory):
    """Example 1's drop-and-roll bed, written by the CLI."""
    out = tmp_path_factory.mktemp("deposited") / "example1"
    cli("run", EXAMPLES / "example1.toml", "--quiet", "--stop-after", "deposition", "--out", out)
    return out


def test_a_specimen_from_python_is_the_clis(tmp_path, deposited):
    cli("specimen", deposited, "--itz", "1mm", "--min-size", "1in", "--voxel", "2mm", "--out", tmp_path / "cli")
    got = aggpack.specimen(deposited, tmp_path / "py", itz=0.001, min_size=0.0254, voxel=0.002)
    expected = json.loads((tmp_path / "cli" / "specimen.json").read_text())
    assert got == expected
    for name in ("specimen.vti", "specimen.inp", "specimen.geo", "specimen.json"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    # The largest virtual box's density is the specimen's exact aggregate fraction.
    summary = json.loads((deposited / "summary.json").read_text())
    largest = max(summary["density"]["boxes"], key=lambda b: b["side_m"])
    assert got["exact"]["aggregate_fraction"] == pytest.approx(largest["density"], abs=1e-9)
    assert got["voxels"]["itz_fraction"] > 0


def test_a_bed_in_memory_is_cut_as_its_file(tmp_path, deposited):
    bed = aggpack.read_bed(deposited / "particles.csv")
    box = [0.08, 0.08, 0.05, 0.2, 0.2, 0.17]
    from_bed = aggpack.specimen(bed, tmp_path / "bed", box=box, formats=["vti"])
    from_file = aggpack.specimen(deposited / "particles.csv", tmp_path / "file", box=box, formats=["vti"])
    assert from_bed["exact"] == from_file["exact"]
    assert from_bed["voxels"] == from_file["voxels"]
    with pytest.raises(aggpack.InputError, match="give the specimen's box or cylinder"):
        aggpack.specimen(bed, tmp_path / "none")
    with pytest.raises(aggpack.InputError, match="box and cylinder: give one specimen"):
        aggpack.specimen(bed, tmp_path / "two", box=box, cylinder=[0.15, 0.15, 0.05, 0.15, 0.04])
    with pytest.raises(aggpack.InputError, match="is not inside the bed"):
        aggpack.specimen(bed, tmp_path / "out", box=[0, 0, 0, 1, 1, 1])
    with pytest.raises(aggpack.InputError, match=r"cylinder \(m\): expected X,Y,ZLO,ZHI,RADIUS"):
        aggpack.specimen(bed, tmp_path / "out", cylinder=[0.15, 0.15, 0.15, 0.05, 0.04])
    with pytest.raises(aggpack.InputError, match=r"mesh_size \(m\): expected AGGREGATE\[,MORTAR\[,ITZ\]\]"):
        aggpack.specimen(bed, tmp_path / "out", box=box, mesh_size=[0.001, -1.0])
    assert not (tmp_path / "out").exists()
    arrays = aggpack.Bed.from_arrays(bed.positions, bed.radii)
    cylinder = aggpack.specimen(arrays, tmp_path / "core", cylinder=[0.15, 0.15, 0.05, 0.15, 0.04], formats=["vti"])
    assert cylinder["region"]["shape"] == "cylinder"
    assert abs(cylinder["voxels"]["aggregate_fraction_minus_exact"]) < 0.01
    assert np.isclose(cylinder["exact"]["aggregate_fraction"], 0.58, atol=0.06)


def test_a_grains_particles_csv_is_refused_not_read_as_separate_spheres(tmp_path):
    """read_bed refuses the grain column as the CLI does (its spheres are a grain's members, which
    a Bed of spheres would cut as separate particles, their overlaps counted twice)."""
    csv = tmp_path / "particles.csv"
    csv.write_text("id,x,y,z,r,grain\n1,0.01,0.01,0.01,0.003,1\n2,0.013,0.01,0.01,0.003,1\n"
                   "3,0.02,0.02,0.02,0.002,0\n")
    with pytest.raises(aggpack.InputError, match="grain column"):
        aggpack.read_bed(csv)
    code, output = cli("specimen", csv, "--box", "0,0,0,0.02,0.02,0.02", "--out", tmp_path / "cli", check=False)
    assert code == 2 and "grain column" in output


def test_a_bed_of_overlapping_spheres_is_refused_as_analyze_refuses_it(tmp_path):
    """Spheres overlapping deeper than a DEM contact are not separate particles: specimen() of such
    a Bed is refused (was cut with each overlap counted twice), as analyze() refuses it."""
    positions = np.array([[0.01, 0.01, 0.01], [0.013, 0.01, 0.01], [0.02, 0.02, 0.02]])
    bed = aggpack.Bed.from_arrays(positions, np.array([0.003, 0.003, 0.002]))
    with pytest.raises(aggpack.InputError, match="overlap"):
        aggpack.analyze(bed)
    with pytest.raises(aggpack.InputError, match="count each overlap twice"):
        aggpack.specimen(bed, tmp_path / "s", box=[0.008, 0.008, 0.008, 0.02, 0.02, 0.02], formats=["vti"])
    assert not (tmp_path / "s").exists()


def test_an_output_path_that_is_a_file_is_an_input_error(tmp_path, deposited):
    """out= a file (was a raw RuntimeError from the filesystem): the module's InputError naming it."""
    a_file = tmp_path / "a_file"
    a_file.write_text("mine\n")
    with pytest.raises(aggpack.InputError, match="is a file, not a folder"):
        aggpack.specimen(deposited, a_file, formats=["vti"])
    with pytest.raises(aggpack.InputError, match="is a file, not a folder"):
        aggpack.specimen(deposited, a_file / "below", formats=["vti"])
    assert a_file.read_text() == "mine\n"
